#pragma once
// A 6-joint serial robot in the DH (thesis eq. 2-15) or 5-parameter MDH (eq. 2-18) convention.
//
// Link transform of joint i (i = 1..6), thesis eq. (2-18):
//   T_i^{i-1} = Trans(Z, d_i) · Rot(Z, θ_i) · Trans(X, a_i) · Rot(X, α_i) · Rot(Y, β_i)
// with θ_i = θ_i0 + θ_in (eq. 2-16). DH is the same with every β_i = 0.
//
// Controller joint values q_i map to the model's variable part by a sign and an offset:
//   θ_in = sign_i · q_i + offset_i.
//
// The 30 kinematic parameters are ordered as the thesis's ΔX (eq. 3-7): by kind, then joint:
//   [d1..d6, θ1..θ6, a1..a6, α1..α6, β1..β6]; lengths in mm, angles in radians (θ means θ_i0).

#include <array>
#include <vector>
#include <string>

#include <Eigen/Core>

namespace ramtk::kinematics {

inline constexpr int kNumJoints = 6;
inline constexpr int kNumParams = 5 * kNumJoints;

using JointVector = Eigen::Matrix<double, kNumJoints, 1>;  // radians
using ParamVector = Eigen::Matrix<double, kNumParams, 1>;  // mm and radians

enum class Convention { kDh, kMdh };

enum class ParamKind { kD = 0, kTheta = 1, kA = 2, kAlpha = 3, kBeta = 4 };

// Index of parameter `kind` of joint `joint` (0-based joint) in a ParamVector.
constexpr int ParamIndex(ParamKind kind, int joint) { return static_cast<int>(kind) * kNumJoints + joint; }
constexpr ParamKind ParamKindOf(int index) { return static_cast<ParamKind>(index / kNumJoints); }
constexpr int ParamJointOf(int index) { return index % kNumJoints; }
constexpr bool IsAngleParam(int index) { return ParamKindOf(index) != ParamKind::kD && ParamKindOf(index) != ParamKind::kA; }

// "d1", "theta3", "beta2", ...; ParamIndexFromName returns -1 for an unknown name.
std::string ParamName(int index);
int ParamIndexFromName(const std::string& name);

struct LinkParams {
  double d = 0.0;       // mm, along Z_{i-1}
  double theta0 = 0.0;  // rad, constant part of the rotation about Z_{i-1}
  double a = 0.0;       // mm, along X_i
  double alpha = 0.0;   // rad, about X_i
  double beta = 0.0;    // rad, about Y_i (MDH only)
};

struct JointMapping {
  double sign = 1.0;    // +1 or -1
  double offset = 0.0;  // rad, added after the sign
};

struct RobotModel {
  std::string name;
  std::string source;  // where the numbers come from
  Convention convention = Convention::kMdh;
  std::array<LinkParams, kNumJoints> links{};
  std::array<JointMapping, kNumJoints> mapping{};
  // Parameters fixed at zero by construction (e.g. β1, d2, β3..β6 for the KUKA MDH example; all
  // β for a DH model). They are never identified.
  std::array<bool, kNumParams> structural_zero{};

  ParamVector Params() const;
  void SetParams(const ParamVector& params);
  // Indices of the parameters that are not structural zeros, in ParamVector order.
  std::vector<int> FreeParams() const;

  // θ_in (model variable part, rad) from controller joints (rad), and back.
  JointVector ModelFromController(const JointVector& q_controller) const;
  JointVector ControllerFromModel(const JointVector& theta_in) const;
};

}  // namespace ramtk::kinematics
