#pragma once
// Stereo camera calibration: two cameras with OpenCV lens models and the rigid transform between
// them, in OpenCV's calibration files (YAML, JSON or XML): written with cv::FileStorage, read with
// yaml-cpp / nlohmann-json / cv::FileStorage's XML parser (camera/src/calibration_tree.h;
// FileStorage's YAML parser can hang on a damaged file).
//
// Read layouts (docs/formats.md, "Stereo calibration"):
//  * standard keys: K1 D1 K2 D2 R T (D: OpenCV's 4, 5, 8, 12 or 14 coefficients, or the fisheye
//    model's 4 with `distortion_model1` / `distortion_model2` / `distortion_model` naming the
//    model: pinhole5, rational, thin-prism, fisheye, or ROS's plumb_bob, rational_polynomial,
//    equidistant) and the image size as `image_size: [w, h]` (or `S`, or
//    `image_width` + `image_height`); an optional `image_size2` when the right camera differs;
//    optional `sampling_kernel1` / `sampling_kernel2` / `sampling_kernel` (both cameras), each a
//    map {fill_factor, psf_sigma_px} (CameraIntrinsics::sampling_kernel; absent = not stated);
//  * SLMaster's caliInfo.yml: M1 D1 M2 D2 Rlr Tlr S (S = [w, h]); its rectification extras
//    (R1 R2 P1 P2 Q E F epilines*) are ignored.
// R, T follow cv::stereoCalibrate: x_in_right = R·x_in_left + T, T in millimetres.
// Written with the standard keys (plus rms_px, per_view_errors_px and parameter_std when known;
// distortion_model1 / distortion_model2 for a camera that is not the 5-coefficient model;
// sampling_kernel1 / sampling_kernel2 for a camera whose kernel is stated).

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ramtk/camera/camera_model.h"
#include "ramtk/core/rotation.h"

namespace cv {
class FileStorage;
}  // namespace cv

namespace ramtk::camera {

// Largest OrthonormalityError accepted for R in a calibration file (stored rotations round to
// ~1e-16 relative; a file edited by hand or stored with few digits fails this).
inline constexpr double kMaxRotationOrthonormalityError = 1e-6;

struct StereoCalibration {
  CameraIntrinsics left;                              // camera 1 (the reference frame of every 3-D result)
  CameraIntrinsics right;                             // camera 2
  Isometry3 right_from_left = Isometry3::Identity();  // R, T; translation in mm

  // Quality figures from a calibration session; NaN / empty when unknown (e.g. simulated).
  double rms_px = std::numeric_limits<double>::quiet_NaN();  // reprojection RMS, pixels
  std::vector<double> per_view_errors_px;                    // RMS per calibration view, pixels
  std::vector<double> parameter_std;                         // std devs of the estimated parameters
                                                             // (from `ramtk calib cameras`: kCalibParameterStdOrder)
  // The file it was read from (ReadStereoCalibration, ParseStereoCalibration's `path`): errors
  // about it name this file. Empty when built in memory.
  std::string source_path;
};

// The order of parameter_std when it comes from a `ramtk calib cameras` file (its std_intrinsics1,
// std_intrinsics2, std_R, std_T keys): 24 values, intrinsics in px, rotation vector in rad, T in mm.
inline constexpr const char* kCalibParameterStdOrder =
    "fx1 fy1 cx1 cy1 k1_1 k2_1 p1_1 p2_1 k3_1 fx2 fy2 cx2 cy2 k1_2 k2_2 p1_2 p2_2 k3_2 rx ry rz tx ty tz";

// Reads either layout. Throws InputError naming the file, the key and (YAML) its line for: an unreadable or
// unparsable file, a missing key, a matrix of the wrong size, a K that is not a pinhole matrix,
// a coefficient vector its lens model does not take, an unknown lens model, an R that is not a rotation (its
// orthonormality error is reported), a non-positive image size.
StereoCalibration ReadStereoCalibration(const std::string& path);
// The same from the file's text; `path` only names it in errors.
StereoCalibration ParseStereoCalibration(const std::string& text, const std::string& path);

// One camera from a calibration file: K1 (or M1) and D1, or OpenCV's sample keys camera_matrix
// and distortion_coefficients, and the image size (image_size, S, or image_width + image_height).
// A stereo file gives its left camera. The same checks and errors as ReadStereoCalibration.
CameraIntrinsics ReadCameraCalibration(const std::string& path);

// Writes the standard keys; JSON if `path` ends in ".json", XML if ".xml", YAML otherwise. Atomic (temporary
// file + rename). Throws InputError if the file cannot be written.
void WriteStereoCalibration(const std::string& path, const StereoCalibration& calibration);

// The one writer of calibration files (WriteStereoCalibration and `ramtk calib cameras` use it):
// image_size [image_size2] K1 D1 K2 D2 R T, then rms_px, per_view_errors_px and parameter_std when
// known, then whatever `extra_keys` adds (a calibration session's views, rejections, board).
// `comment` heads a YAML file.
using ExtraCalibrationKeys = std::function<void(cv::FileStorage&)>;
std::string StereoCalibrationText(const StereoCalibration& calibration, bool json, const std::string& comment = "",
                                  const ExtraCalibrationKeys& extra_keys = {});
// The text formats cv::FileStorage writes; a path's extension names one (.json, .xml, else YAML).
enum class CalibrationFormat { kYaml, kJson, kXml };
CalibrationFormat CalibrationFormatOf(const std::string& path);
std::string StereoCalibrationText(const StereoCalibration& calibration, CalibrationFormat format,
                                  const std::string& comment = "", const ExtraCalibrationKeys& extra_keys = {});
// One camera in the same dialect: image_size K1 D1, then rms_px, per_view_errors_px and
// parameter_std (9 values, fx fy cx cy k1 k2 p1 p2 k3) when known, then `extra_keys`.
std::string CameraCalibrationText(const CameraIntrinsics& camera, double rms_px,
                                  const std::vector<double>& per_view_errors_px,
                                  const std::vector<double>& parameter_std, const std::string& comment = "",
                                  const ExtraCalibrationKeys& extra_keys = {},
                                  CalibrationFormat format = CalibrationFormat::kYaml);

}  // namespace ramtk::camera
