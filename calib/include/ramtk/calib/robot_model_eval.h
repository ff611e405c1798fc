#pragma once
// The measurement model of the robot calibration (public for tests and pose planning): the layout of the unknown vector, one pose's
// predicted measurement and its analytic Jacobian (robot_calibration.h has the equations).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::calib {

// Where each group of unknowns sits in the vector x (every group always present; which are free
// is decided elsewhere).
struct UnknownLayout {
  int num_joints = 0;
  int num_targets = 0;
  int harmonics = 0;
  bool rotation = false;  // 6-D data used: the tool rotation block exists
  int kin = 0, base = 0, targets = 0, tool = 0, cyclic = 0, compliance = 0, size = 0;

  UnknownLayout(int joints, int targets, bool rotation, int harmonics);
  int RowsPerPose() const { return 3 * num_targets + (rotation ? 3 : 0); }
};

// Fixed parts of the model around x: the joint mapping and the reference rotations the small
// rotation unknowns perturb (tracker_from_base = Exp(φ)·base_rotation, flange_from_tool =
// tool_rotation·Exp(ψ)).
struct ModelFrame {
  const kinematics::RobotChain* chain = nullptr;  // mapping, structure
  UnknownLayout layout{0, 0, false, 0};
  Mat3 base_rotation = Mat3::Identity();
  Mat3 tool_rotation = Mat3::Identity();
};

// Per-pose inputs the model needs beyond x.
struct PoseInput {
  Eigen::VectorXd q;        // controller joints (rad)
  Eigen::VectorXd torque;   // gravity torque per joint (kg·mm), for compliance
  std::vector<Vec3> measured;       // per target (mm)
  Mat3 measured_rotation = Mat3::Identity();
  Eigen::MatrixXd whitening;        // rows × rows: residual whitening (upper-triangular)
};

// Residual (predicted − measured; positions mm then rotation rad) of one pose and, when
// jacobian is not null, d residual / d x (rows × layout.size).
void EvaluatePose(const ModelFrame& frame, const Eigen::VectorXd& x, const PoseInput& pose, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian);

// The chain with its link parameters from x.
kinematics::RobotChain ChainFromUnknowns(const ModelFrame& frame, const Eigen::VectorXd& x);

}  // namespace ramtk::calib
