#pragma once
// The calibration calls of each lens model (not installed): cv::calibrateCamera /
// cv::stereoCalibrate with the rational and thin-prism flags, and cv::fisheye::calibrate /
// cv::fisheye::stereoCalibrate with what cv::calibrateCamera gives besides (per-view RMS, σ of the
// intrinsics and of each view's pose) computed here for the fisheye model.
#include <opencv2/core.hpp>
#include <vector>

#include "ramtk/calib/camera_calibration.h"

namespace ramtk::calib::internal {

using ObjectPoints = std::vector<std::vector<cv::Point3f>>;
using ImagePoints = std::vector<std::vector<cv::Point2f>>;

// OpenCV's coefficient vector of `camera` as the model's calibration call takes it: 5, 8
// (rational), 12 (thin prism) or 4 (fisheye) values, as an n×1 CV_64F matrix.
cv::Mat CalibrationDistortion(const camera::CameraIntrinsics& camera, CalibrationModel model);

// cv::calibrateCamera's outputs for options.model: K, the distortion vector, each view's pose,
// σ of fx fy cx cy and the distortion vector (std_in, 4 + its length), σ of each view's pose
// (std_ex, 6 per view), RMS per view (per_view); returns the overall RMS (px).
double CalibrateCameraModel(const ObjectPoints& object, const ImagePoints& image, cv::Size image_size,
                            const CameraCalibrationOptions& options, const cv::TermCriteria& criteria, cv::Mat* k,
                            cv::Mat* d, std::vector<cv::Mat>* rvecs, std::vector<cv::Mat>* tvecs, cv::Mat* std_in,
                            cv::Mat* std_ex, cv::Mat* per_view);

// cv::stereoCalibrate from both cameras' intrinsics (refined jointly, except for the fisheye
// model, whose intrinsics stay fixed): R, T and the RMS per pair (per_view: n × 2, left, right);
// returns the stereo RMS (px).
double StereoCalibrateModel(const ObjectPoints& object, const ImagePoints& left, const ImagePoints& right,
                            cv::Size image_size, const CameraCalibrationOptions& options,
                            const cv::TermCriteria& criteria, cv::Mat* k1, cv::Mat* d1, cv::Mat* k2, cv::Mat* d2,
                            cv::Mat* rotation, cv::Mat* translation, cv::Mat* per_view);

}  // namespace ramtk::calib::internal
