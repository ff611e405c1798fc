#pragma once
// The refinement block of both hand-eye result files (not installed).
#include <nlohmann/json.hpp>

#include "ramtk/calib/hand_eye_flange_refine.h"

namespace ramtk::calib::internal {

// `pose` names the refined pose whose covariance is reported ("flange_from_camera" or
// "camera_from_base"), `frame` the frame its rotation perturbation lives in.
nlohmann::json RefinementJson(const EyeInHandRefinement& refinement, const std::string& pose, const std::string& frame);

}  // namespace ramtk::calib::internal
