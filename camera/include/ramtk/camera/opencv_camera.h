#pragma once
// The camera model in OpenCV's types, for the calls into calib3d (calibrateCamera,
// stereoCalibrate, projectPoints, cv::fisheye): K as cv::Matx33d, distortion as OpenCV's
// coefficient vector, the image size as cv::Size.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/camera/camera_model.h"

namespace ramtk::camera {

cv::Matx33d CameraMatrix(const CameraIntrinsics& camera);
// The 5 coefficients (k1, k2, p1, p2, k3) of the 5-coefficient model. Throws InputError for the
// other models (use DistortionVector).
cv::Vec<double, 5> DistortionCoefficients(const CameraIntrinsics& camera);
cv::Size ImageSize(const CameraIntrinsics& camera);

// OpenCV's coefficient vector of any model, in its order: 5 for the 5-coefficient model; 8, 12 or
// 14 for the rational model (the shortest that holds every non-zero coefficient; τx, τy in
// radians); 4 (k1..k4) for the fisheye model.
std::vector<double> DistortionVector(const Distortion& distortion);
// From OpenCV's coefficient vector of `model`. The 5-coefficient and rational models take 4, 5, 8,
// 12 or 14 values; a vector whose coefficients beyond the fifth are all zero is the 5-coefficient
// model whichever of the two is named. The fisheye model takes 4. Returns "" or what is wrong.
std::string DistortionFromVector(const std::vector<double>& coefficients, LensModel model, Distortion* distortion);

// OpenCV's projection of `points` (object frame; camera_from_object as the rotation vector `rvec`
// and translation `tvec`, mm) through `camera`: cv::projectPoints for the 5-coefficient and
// rational models, cv::fisheye::projectPoints for the fisheye model.
std::vector<cv::Point2d> ProjectPointsOpenCv(const std::vector<cv::Point3d>& points, const cv::Vec3d& rvec,
                                             const cv::Vec3d& tvec, const CameraIntrinsics& camera);

// From OpenCV's K (skew ignored: it must be zero), OpenCV's coefficient vector (up to 5, missing
// ones zero; 8, 12 or 14 for the rational model; 4 for the fisheye model) and the image size.
// Throws InputError for a vector `model` does not take.
CameraIntrinsics IntrinsicsFromOpenCv(const cv::Matx33d& camera_matrix, const std::vector<double>& distortion,
                                      cv::Size image_size, LensModel model = LensModel::kPinhole5);

}  // namespace ramtk::camera
