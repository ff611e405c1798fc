#pragma once
// Forward kinematics: base_from_flange(q) = T_1^0 · T_2^1 · … · T_6^5 (thesis eq. 2-17).

#include <array>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {

// T_i^{i-1} for one link at model angle theta_in (rad; θ_i = theta0 + theta_in). Eq. (2-18).
Isometry3 LinkTransform(const LinkParams& link, double theta_in);

// Every frame of the chain at one configuration.
struct ChainFrames {
  // base_from_link[i] = T_i^0, i = 0..6 (T_0^0 = identity, T_6^0 = base_from_flange).
  std::array<Isometry3, kNumJoints + 1> base_from_link;
  // link_from_previous[i] = T_i^{i-1}, i = 1..6 (index 0 unused, identity).
  std::array<Isometry3, kNumJoints + 1> link_from_previous;
};

// All frames for controller joints q (rad).
ChainFrames ComputeChainFrames(const RobotModel& model, const JointVector& q_controller);

// base_from_flange (T_e^b) for controller joints q (rad).
Isometry3 BaseFromFlange(const RobotModel& model, const JointVector& q_controller);

}  // namespace ramtk::kinematics
