#pragma once
// The camera model and the stereo calibration files live in ramtk::camera (one model for vision
// and calib); these using-declarations name them in vision's namespace for the scan and the
// fringe simulator. They are the same types, not copies.

#include "ramtk/camera/camera_model.h"
#include "ramtk/camera/stereo_calibration.h"

namespace ramtk::vision {

using camera::CameraIntrinsics;
using camera::Distortion;
using camera::DistortNormalized;
using camera::DistortNormalizedJacobian;
using camera::kMaxRotationOrthonormalityError;
using camera::ParseStereoCalibration;
using camera::PixelRay;
using camera::ProjectPoint;
using camera::ReadStereoCalibration;
using camera::StereoCalibration;
using camera::UndistortNormalized;
using camera::Vec2;
using camera::WriteStereoCalibration;

}  // namespace ramtk::vision
