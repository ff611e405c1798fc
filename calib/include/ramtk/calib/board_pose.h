#pragma once
// Board poses with their covariance: each view's camera_from_board from its detected features,
// either by PnP with known intrinsics or from a camera calibration, with the 6×6 covariance the
// corner noise implies (σ_px² (JᵀJ)⁻¹ of the reprojection problem). These are the measurements of
// a hand-eye calibration from images; the covariance becomes its per-view weight.
//
// Covariance order everywhere: the rotation vector ω of a rotation applied on the left (in the
// camera frame: R' = exp(ω)·R), then the translation (t' = t + δt). In files ω is in degrees and
// t in millimetres; in memory ω is in radians.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/calib/camera_calibration.h"
#include "ramtk/camera/camera_model.h"
#include "ramtk/core/rotation.h"

namespace ramtk::calib {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct BoardPoseEstimate {
  std::string name;                                     // image file or view label
  int pose = 0;  // 1-based number of the robot pose (image) it belongs to; 0: its place in the list
  Isometry3 camera_from_board = Isometry3::Identity();  // mm
  Mat6 covariance = Mat6::Zero();                       // [ω (rad, left, camera frame); t (mm)]
  int points = 0;                                       // features used
  double rms_px = 0.0;                                  // reprojection RMS of this view
};

struct BoardPoseOptions {
  int min_points = 6;  // a view with fewer features is skipped
  // Corner noise (px, 1σ per coordinate) for the covariance; 0: estimated from the pooled PnP
  // residuals, sqrt(Σ r² / (2N − 6V)) over the V views and N points.
  double sigma_px = 0.0;

  std::string Validate() const;  // empty if valid
};

struct BoardPoseSummary {
  int views = 0;                       // views given
  int used = 0;                        // views with a pose
  double sigma_px = 0.0;               // corner noise used for the covariances
  bool sigma_estimated = false;        // sigma_px came from the residuals
  double rms_px = 0.0;                 // reprojection RMS over the used views
  std::vector<RejectedView> skipped;  // views without a pose, with the reason

  std::string BriefReport() const;
};

// Jacobian (2n × 6) of the projections of `object_points` with respect to the pose perturbation
// [ω; δt] above, at camera_from_board.
Eigen::MatrixXd BoardPoseJacobian(const camera::CameraIntrinsics& camera, const std::vector<cv::Point3f>& object_points,
                                  const Isometry3& camera_from_board);

// camera_from_board per view by PnP (IPPE, then Levenberg–Marquardt on the reprojection error)
// with the intrinsics held fixed, and its covariance σ_px² (JᵀJ)⁻¹. Views with too few points or
// where PnP fails are listed in the summary's `skipped`, not fatal. InputError for bad options.
std::vector<BoardPoseEstimate> EstimateBoardPoses(const std::vector<ViewPoints>& views,
                                                  const camera::CameraIntrinsics& camera,
                                                  const BoardPoseOptions& options = {},
                                                  BoardPoseSummary* summary = nullptr);

// The board poses of a calibration's used views (CalibrateCamera: rvecs, tvecs) with the
// covariance of each from the calibration's own Jacobian: the block of σ² (JᵀJ)⁻¹ over the
// estimated intrinsics (per `options`: k3, tangential and aspect ratio fixed or not) and every
// view's pose, so the intrinsics' uncertainty is included. σ² = Σ r² / (2N − P). `views` must
// hold the used views by name (the corners the calibration was run on).
std::vector<BoardPoseEstimate> BoardPosesFromCalibration(const CameraCalibrationResult& calibration,
                                                         const std::vector<ViewPoints>& views,
                                                         const CameraCalibrationOptions& options);

// Board-pose file (CSV with a header): pose (BoardPoseEstimate::pose, or the row number), image, x, y, z (mm), a, b, c (KUKA A,B,C deg), points,
// rms_px, then the 21 upper-triangle entries cov_ij (0 ≤ i ≤ j ≤ 5) of the covariance in
// [ω (deg); t (mm)]. The camera columns are those of the hand-eye pose files, which take the
// covariance columns as per-view weights (ReadFlangePoseObservations).
std::string FormatBoardPoseEstimates(const std::vector<BoardPoseEstimate>& poses, const std::string& comment = "");

}  // namespace ramtk::calib
