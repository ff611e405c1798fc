#pragma once
// Differential kinematics with respect to the 30 MDH parameters (thesis eqs. 3-6, 3-7):
//   d(base_from_flange) = Σ_i Σ_q T_i^0 · A_qi · T_6^i · dq_i,
//   A_qi = (T_i^{i-1})^{-1} · ∂T_i^{i-1}/∂q_i   (closed form, see jacobian.cpp).
// Columns follow the ParamVector order [d1..d6, θ1..θ6, a1..a6, α1..α6, β1..β6]; derivatives are
// per mm for d and a, per radian for θ, α, β. Structural zeros are not removed: select the
// columns of RobotModel::FreeParams() where only those are wanted.

#include <array>

#include "ramtk/kinematics/forward.h"

namespace ramtk::kinematics {

using PointParamJacobian = Eigen::Matrix<double, 3, kNumParams>;
using PoseParamJacobian = Eigen::Matrix<double, 6, kNumParams>;
using JointJacobian = Eigen::Matrix<double, 6, kNumJoints>;

// A_qi of eq. (3-6) for one link and parameter kind, as a 4x4 matrix (last row zero).
Mat4 LinkDifferential(const LinkParams& link, double theta_in, ParamKind kind);

// ∂(base_from_flange)/∂p_k for all 30 parameters, each as a 4x4 matrix (last row zero).
std::array<Mat4, kNumParams> FlangeDifferentials(const RobotModel& model, const JointVector& q_controller);

// ∂(base_from_flange · point_in_flange)/∂p, 3x30, in base coordinates (the thesis's k_qi
// without T_b^s; pre-multiply by sensor_from_base's rotation to get eq. 3-7's M).
PointParamJacobian ComputePointParamJacobian(const RobotModel& model, const JointVector& q_controller,
                                             const Vec3& point_in_flange);

// 6x30: rows 0-2 the flange origin's velocity (mm per unit), rows 3-5 the flange's angular
// velocity (rad per unit), both in base coordinates.
PoseParamJacobian ComputePoseParamJacobian(const RobotModel& model, const JointVector& q_controller);

// 6x6 geometric Jacobian with respect to the controller joints (rad), same row layout as
// ComputePoseParamJacobian; includes each joint's sign.
JointJacobian ComputeJointJacobian(const RobotModel& model, const JointVector& q_controller);

}  // namespace ramtk::kinematics
