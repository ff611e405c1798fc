#pragma once
// Pieces of the simulators' truth files that several simulators write the same way.

#include <nlohmann/json.hpp>

#include "ramtk/camera/camera_model.h"

namespace ramtk::vision {

// A camera's (or projector's) intrinsics as truth files hold them: fx fy cx cy width height and
// `distortion_k1_k2_p1_p2_k3`; a lens of another model than the 5-coefficient one adds its name
// (`lens_model`) and OpenCV's coefficient vector (`distortion_opencv`).
nlohmann::json IntrinsicsTruthJson(const camera::CameraIntrinsics& c);

}  // namespace ramtk::vision
