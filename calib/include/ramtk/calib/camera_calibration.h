#pragma once
// Camera calibration sessions: board detections → single-camera and stereo calibration with
// OpenCV, per-view reprojection errors, automatic rejection of outlier views (with the reason),
// parameter standard deviations, a picture of image coverage and residuals, and the stereo
// calibration file of DESIGN.md (OpenCV FileStorage, keys K1 D1 K2 D2 R T image_size), written by
// ramtk::camera's one writer. The camera model is ramtk::camera's (one model for calib and vision).

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/calib/board.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/progress.h"
#include "ramtk/core/termination.h"

namespace ramtk::calib {

// One image's board features.
struct ViewPoints {
  std::string name;                        // image file or label
  std::vector<cv::Point2f> image_points;   // px
  std::vector<cv::Point3f> object_points;  // mm, board frame
  std::vector<int> ids;                    // feature ids (BoardObjectPoints index)
};

struct RejectedView {
  std::string name;
  std::string reason;  // e.g. "board not found", "RMS 2.31 px > 3 x median 0.12 px"
};

// The lens model a session estimates (camera_model.h): OpenCV's 5 coefficients, its rational
// model (8: CALIB_RATIONAL_MODEL), rational with thin prism (12: CALIB_THIN_PRISM_MODEL too), or
// the fisheye model (cv::fisheye::calibrate, k1..k4).
enum class CalibrationModel { kPinhole5, kRational, kThinPrism, kFisheye };
// "pinhole5", "rational", "thin-prism", "fisheye"; InputError naming `where` otherwise.
CalibrationModel ParseCalibrationModel(const std::string& text, const InputLocation& where);
camera::LensModel LensModelOf(CalibrationModel model);

struct CameraCalibrationOptions {
  CalibrationModel model = CalibrationModel::kPinhole5;  // the lens model estimated
  bool fix_k3 = true;             // estimate k1 k2 p1 p2 only (k3 = 0), OpenCV's CALIB_FIX_K3 (not fisheye)
  bool zero_tangential = false;   // p1 = p2 = 0 (CALIB_ZERO_TANGENT_DIST)
  bool fix_aspect_ratio = false;  // fx = fy (CALIB_FIX_ASPECT_RATIO)
  int min_views = 4;              // fewer usable views is an error
  // A view is rejected when its RMS reprojection error exceeds outlier_factor × the median view
  // RMS and also outlier_min_px; the worst such view goes first, then the camera is re-calibrated.
  double outlier_factor = 3.0;
  double outlier_min_px = 0.25;
  double max_rejected_fraction = 0.3;  // never reject more than this share of the views
  // Stereo: pairs whose stereo RMS exceeds the same limits are rejected likewise.
  ProgressCallback progress;
  // Stereo parameter σ: each camera's residuals with their own variance (the sandwich covariance of
  // the unweighted fit) instead of one pooled variance; for devices of different noise, e.g. a
  // camera and a projector whose corners come from decoded phase.
  bool per_camera_variance = false;

  std::string Validate() const;
  int OpenCvFlags() const;
};

struct CameraCalibrationResult {
  camera::CameraIntrinsics intrinsics;  // fx fy cx cy, distortion (of options.model) and image size
  double rms_px = 0.0;                  // over every point of the used views
  // Standard deviations of fx fy cx cy then the distortion vector's coefficients in OpenCV's
  // order (k1 k2 p1 p2 k3 [k4 k5 k6 [s1 s2 s3 s4]]; fisheye k1 k2 k3 k4), from the Jacobian scaled
  // by the residual variance (OpenCV's stdDeviationsIntrinsics; computed alike for the fisheye
  // model); 0 for fixed parameters.
  std::vector<double> std_intrinsics;
  std::vector<std::string> view_names;    // used views
  std::vector<double> per_view_rms_px;    // per used view
  std::vector<cv::Vec3d> rvecs, tvecs;    // camera_from_board per used view (Rodrigues, mm)
  std::vector<cv::Vec6d> std_extrinsics;  // per used view: rvec (rad) then tvec (mm)
  std::vector<RejectedView> rejected;
};

struct CameraCalibrationSummary {
  Termination termination = Termination::kNotRun;
  std::string message;          // "converged" or the reason for failure
  int rounds = 0;               // calibrations run (1 + one per rejected view)
  double initial_rms_px = 0.0;  // first round, all views
  double final_rms_px = 0.0;
  double worst_view_rms_px = 0.0;
  std::string worst_view;
  int used_views = 0;
  std::vector<RejectedView> rejected;  // the outliers

  std::string BriefReport() const;
};

// Calibrates one camera from board views. InputError if fewer than min_views remain.
CameraCalibrationResult CalibrateCamera(const std::vector<ViewPoints>& views, cv::Size image_size,
                                        const CameraCalibrationOptions& options,
                                        CameraCalibrationSummary* summary = nullptr);

struct StereoCalibrationResult {
  // The calibrated rig, as `ramtk scan` reads it back: both cameras' intrinsics after the joint
  // refinement, right_from_left (x_right = R·x_left + T, mm), the stereo RMS, per_view_errors_px
  // (left, right per used pair) and parameter_std in kCalibParameterStdOrder: both cameras'
  // intrinsics, R's rotation vector (rad) and T (mm), from the joint Jacobian of both cameras'
  // residuals (intrinsics, R, T, board poses) scaled by the residual variance; empty if it could
  // not be computed.
  camera::StereoCalibration rig;
  // Each camera calibrated alone first: its views, board poses, rejections, and its single-camera
  // estimates and σ (the rig's intrinsics are the jointly refined ones).
  CameraCalibrationResult left, right;
  std::vector<std::string> pair_names;  // used pairs
  std::vector<RejectedView> rejected_pairs;
};

// Stereo: left[i] and right[i] are the same board pose. Each camera is calibrated alone, then
// cv::stereoCalibrate (CALIB_USE_INTRINSIC_GUESS) on the pairs both kept, with pair rejection; the
// fisheye model: cv::fisheye::stereoCalibrate with the intrinsics fixed. parameter_std only for
// the 5-coefficient model.
StereoCalibrationResult CalibrateStereo(const std::vector<ViewPoints>& left, const std::vector<ViewPoints>& right,
                                        cv::Size image_size, const CameraCalibrationOptions& options,
                                        CameraCalibrationSummary* summary = nullptr);
// The same for two devices of different image sizes (a camera and a projector): each calibrated
// with its own size, the rig's intrinsics carry them.
StereoCalibrationResult CalibrateStereo(const std::vector<ViewPoints>& left, const std::vector<ViewPoints>& right,
                                        cv::Size left_size, cv::Size right_size,
                                        const CameraCalibrationOptions& options,
                                        CameraCalibrationSummary* summary = nullptr);

// Detects the board in image files (grey or colour, 8 or 16 bit; any format image::LoadImageGrey8
// reads: PNG, BMP, and through OpenImageIO JPEG, TIFF, ...). Images
// where the board is not found are listed in `rejected`. InputError names an unreadable file and
// a file whose size differs from the first one.
// With `sector_based`, that list is filled too, view for view, with the sector-based detector's
// own corners (BoardDetection::sector_points; a view without them has no points there).
std::vector<ViewPoints> DetectBoardInImages(const std::vector<std::string>& paths, const BoardSpec& board,
                                            cv::Size* image_size, std::vector<RejectedView>* rejected,
                                            const ProgressCallback& progress = {},
                                            std::vector<ViewPoints>* sector_based = nullptr);

// Which chessboard corners a session is calibrated from. Neither refinement wins everywhere: on
// rendered boards the refined corners are the unbiased ones (the sector-based ones bias fx by
// 7–10 σ at a lower RMS), on the opencv-doc stereo session they also give the lower RMS, on a
// public 1928×1208 real set the sector-based ones did (docs/calib.md).
enum class CornerChoice {
  kSubPix,       // CornerRefinement::kSubPix corners (the default)
  kSectorBased,  // CornerRefinement::kSectorBased corners
  kLowerRms,     // whichever gives the lower reprojection RMS (stereo RMS for a rig)
};
// "subpix", "sector", "auto"; InputError naming `where` otherwise.
CornerChoice ParseCornerChoice(const std::string& text, const InputLocation& where);

// One corner set's calibration, for the comparison.
struct CornerSetFit {
  bool ok = false;
  std::string error;               // why the calibration failed (ok = false)
  int views = 0;                   // views (pairs) used
  double rms_px = 0.0;             // reprojection RMS (stereo RMS for a rig)
  double fx_sigma_px[2] = {0, 0};  // reported σ of fx, left and right camera (right 0 for one camera)
};

// Both corner sets calibrated the same way, and the one kept.
struct CornerComparison {
  CornerSetFit subpix, sector;
  CornerRefinement chosen = CornerRefinement::kSubPix;
  std::string BriefReport() const;
};

// Calibrates from both corner sets (views from DetectBoardInImages and its sector_based list) and
// returns the result of the one `choice` keeps. A set that cannot be calibrated is reported in
// the comparison; InputError if the kept one (or, for kLowerRms, both) cannot.
CameraCalibrationResult CalibrateCameraComparingCorners(const std::vector<ViewPoints>& subpix,
                                                        const std::vector<ViewPoints>& sector, cv::Size image_size,
                                                        const CameraCalibrationOptions& options, CornerChoice choice,
                                                        CameraCalibrationSummary* summary,
                                                        CornerComparison* comparison);
StereoCalibrationResult CalibrateStereoComparingCorners(const std::vector<ViewPoints>& left_subpix,
                                                        const std::vector<ViewPoints>& right_subpix,
                                                        const std::vector<ViewPoints>& left_sector,
                                                        const std::vector<ViewPoints>& right_sector,
                                                        cv::Size image_size, const CameraCalibrationOptions& options,
                                                        CornerChoice choice, CameraCalibrationSummary* summary,
                                                        CornerComparison* comparison);

// The stereo calibration file (OpenCV FileStorage YAML text, camera::StereoCalibrationText): the
// rig's keys (image_size K1 D1 K2 D2 R T rms_px per_view_errors_px parameter_std), then the
// session's: board, and per camera its single-camera fit (rms1, per_view_errors1, views1,
// rejected_views1, the same with 2) and the rejected pairs.
// With `corners`, also the comparison: corners (the kept set), corner_rms_px_subpix/_sector,
// corner_fx_sigma_px_subpix/_sector (left, right) and corner_views_subpix/_sector.
// `format`: the FileStorage dialect (YAML unless the output is named .json or .xml).
std::string StereoCalibrationYaml(const StereoCalibrationResult& stereo, const BoardSpec& board,
                                  const CornerComparison* corners = nullptr,
                                  camera::CalibrationFormat format = camera::CalibrationFormat::kYaml);
// Single camera (camera::CameraCalibrationText): image_size K1 D1 rms_px per_view_errors_px
// parameter_std (fx fy cx cy k1 k2 p1 p2 k3), then board, views1, rejected_views1.
std::string CameraCalibrationYaml(const CameraCalibrationResult& camera, const BoardSpec& board,
                                  const CornerComparison* corners = nullptr,
                                  camera::CalibrationFormat format = camera::CalibrationFormat::kYaml);

// Coverage and residual picture of one camera: every used feature (a dot per view colour) and
// its residual vector magnified residual_scale times; rejected views' features in grey.
cv::Mat DrawCoverage(const CameraCalibrationResult& camera, const std::vector<ViewPoints>& views,
                     double residual_scale = 100.0);

}  // namespace ramtk::calib
