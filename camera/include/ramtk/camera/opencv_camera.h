#pragma once
// The camera model in OpenCV's types, for the calls into calib3d (calibrateCamera,
// stereoCalibrate, projectPoints): K as cv::Matx33d, distortion as the 5 coefficients
// (k1, k2, p1, p2, k3), the image size as cv::Size.

#include <opencv2/core.hpp>
#include <vector>

#include "ramtk/camera/camera_model.h"

namespace ramtk::camera {

cv::Matx33d CameraMatrix(const CameraIntrinsics& camera);
cv::Vec<double, 5> DistortionCoefficients(const CameraIntrinsics& camera);
cv::Size ImageSize(const CameraIntrinsics& camera);
// From OpenCV's K (skew ignored: it must be zero), up to 5 coefficients (missing ones are zero;
// OpenCV's extra rational and thin-prism terms are not part of this model and must be zero) and
// the image size.
CameraIntrinsics IntrinsicsFromOpenCv(const cv::Matx33d& camera_matrix, const std::vector<double>& distortion,
                                      cv::Size image_size);

}  // namespace ramtk::camera
