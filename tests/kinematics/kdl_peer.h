#pragma once
// Orocos KDL as an independent peer: the same robot built as a KDL chain from its own DH frame
// constructor (Frame::DH) plus Rot(Y, β).

#include "ramtk/kinematics/robot_model.h"
#include "ramtk/core/rotation.h"

#include <string>

namespace ramtk::kinematics::testing {

Isometry3 KdlBaseFromFlange(const RobotModel& model, const JointVector& q_controller);
// KDL's geometric Jacobian (reference point: flange origin, base frame) w.r.t. controller joints.
Eigen::Matrix<double, 6, 6> KdlJointJacobian(const RobotModel& model, const JointVector& q_controller);

// Random parameter perturbations for tests: uniform in ±length_mm / ±angle_rad on every free
// parameter, and on the structural zeros too when `all_params` (to exercise every formula).
RobotModel PerturbedModel(const RobotModel& model, unsigned seed, double length_mm, double angle_rad,
                          bool all_params = false);

// The robot files shipped in datasets/robots/.
RobotModel LoadShippedRobot(const std::string& file_name);

}  // namespace ramtk::kinematics::testing
