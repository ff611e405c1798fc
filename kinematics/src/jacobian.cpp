#include "ramtk/kinematics/jacobian.h"

#include <cmath>

namespace ramtk::kinematics {
namespace {

// A_qi = [hat(omega) v; 0 0] in the coordinates of link frame i.
struct LocalTwist {
  Vec3 omega = Vec3::Zero();
  Vec3 v = Vec3::Zero();
};

// With T = [R t] = Trans(Z,d)·Rot(Z,θ)·Trans(X,a)·Rot(X,α)·Rot(Y,β), A = T^{-1}∂T = [Rᵀ∂R, Rᵀ∂t]:
//   d: Rᵀ∂R = 0,            Rᵀ∂t = Rᵀ·e_z
//   θ: Rᵀ∂R = hat(Rᵀ·e_z),  Rᵀ∂t = Rᵀ·(e_z × t)
//   a: Rᵀ∂R = 0,            Rᵀ∂t = Rᵀ·(cos θ, sin θ, 0) = (cos β, 0, sin β)
//   α: Rᵀ∂R = hat(Rot(Y,β)ᵀ·e_x) = hat(cos β, 0, sin β),  Rᵀ∂t = 0
//   β: Rᵀ∂R = hat(e_y),     Rᵀ∂t = 0
LocalTwist LinkTwist(const LinkParams& link, const Isometry3& link_from_previous, ParamKind kind) {
  const Mat3& r = link_from_previous.linear();
  const Vec3& t = link_from_previous.translation();
  LocalTwist tw;
  switch (kind) {
    case ParamKind::kD:
      tw.v = r.row(2).transpose();
      break;
    case ParamKind::kTheta:
      tw.omega = r.row(2).transpose();
      tw.v = r.transpose() * Vec3(-t.y(), t.x(), 0.0);
      break;
    case ParamKind::kA:
      // Rᵀ·(cos θ, sin θ, 0) = Rᵀ·Rot(Z,θ)·e_x = Rot(Y,β)ᵀ·e_x.
      tw.v = Vec3(std::cos(link.beta), 0.0, std::sin(link.beta));
      break;
    case ParamKind::kAlpha:
      tw.omega = Vec3(std::cos(link.beta), 0.0, std::sin(link.beta));
      break;
    case ParamKind::kBeta:
      tw.omega = Vec3::UnitY();
      break;
  }
  return tw;
}


}  // namespace

Mat4 LinkDifferential(const LinkParams& link, double theta_in, ParamKind kind) {
  const LocalTwist tw = LinkTwist(link, LinkTransform(link, theta_in), kind);
  Mat4 a = Mat4::Zero();
  a.topLeftCorner<3, 3>() = Skew(tw.omega);
  a.topRightCorner<3, 1>() = tw.v;
  return a;
}

std::array<Mat4, kNumParams> FlangeDifferentials(const RobotModel& model, const JointVector& q_controller) {
  const ChainFrames f = ComputeChainFrames(model, q_controller);
  const Isometry3& base_from_flange = f.base_from_link[kNumJoints];
  std::array<Mat4, kNumParams> out;
  for (int k = 0; k < kNumParams; ++k) {
    const int i = ParamJointOf(k) + 1;
    const LocalTwist tw = LinkTwist(model.links[i - 1], f.link_from_previous[i], ParamKindOf(k));
    Mat4 a = Mat4::Zero();
    a.topLeftCorner<3, 3>() = Skew(tw.omega);
    a.topRightCorner<3, 1>() = tw.v;
    const Isometry3 link_from_flange = f.base_from_link[i].inverse() * base_from_flange;  // T_6^i
    out[k] = f.base_from_link[i].matrix() * a * link_from_flange.matrix();
  }
  return out;
}

PointParamJacobian ComputePointParamJacobian(const RobotModel& model, const JointVector& q_controller,
                                             const Vec3& point_in_flange) {
  const ChainFrames f = ComputeChainFrames(model, q_controller);
  const Vec3 point_in_base = f.base_from_link[kNumJoints] * point_in_flange;
  PointParamJacobian jac;
  for (int i = 1; i <= kNumJoints; ++i) {
    const Isometry3& base_from_link = f.base_from_link[i];
    const Vec3 point_in_link = base_from_link.inverse() * point_in_base;  // T_6^i · p
    for (int kind = 0; kind < 5; ++kind) {
      const ParamKind k = static_cast<ParamKind>(kind);
      const LocalTwist tw = LinkTwist(model.links[i - 1], f.link_from_previous[i], k);
      jac.col(ParamIndex(k, i - 1)) = base_from_link.linear() * (tw.omega.cross(point_in_link) + tw.v);
    }
  }
  return jac;
}

PoseParamJacobian ComputePoseParamJacobian(const RobotModel& model, const JointVector& q_controller) {
  const ChainFrames f = ComputeChainFrames(model, q_controller);
  const Vec3 flange_in_base = f.base_from_link[kNumJoints].translation();
  PoseParamJacobian jac;
  for (int i = 1; i <= kNumJoints; ++i) {
    const Isometry3& base_from_link = f.base_from_link[i];
    const Vec3 flange_in_link = base_from_link.inverse() * flange_in_base;
    for (int kind = 0; kind < 5; ++kind) {
      const ParamKind k = static_cast<ParamKind>(kind);
      const LocalTwist tw = LinkTwist(model.links[i - 1], f.link_from_previous[i], k);
      const int col = ParamIndex(k, i - 1);
      jac.block<3, 1>(0, col) = base_from_link.linear() * (tw.omega.cross(flange_in_link) + tw.v);
      jac.block<3, 1>(3, col) = base_from_link.linear() * tw.omega;
    }
  }
  return jac;
}

JointJacobian ComputeJointJacobian(const RobotModel& model, const JointVector& q_controller) {
  // ∂/∂q_i = sign_i · ∂/∂θ_i; θ_i turns about Z_{i-1} through the origin of frame i-1.
  const ChainFrames f = ComputeChainFrames(model, q_controller);
  const Vec3 flange_in_base = f.base_from_link[kNumJoints].translation();
  JointJacobian jac;
  for (int i = 0; i < kNumJoints; ++i) {
    const Vec3 axis = f.base_from_link[i].linear().col(2);
    const Vec3 origin = f.base_from_link[i].translation();
    const double s = model.mapping[i].sign;
    jac.block<3, 1>(0, i) = s * axis.cross(flange_in_base - origin);
    jac.block<3, 1>(3, i) = s * axis;
  }
  return jac;
}

}  // namespace ramtk::kinematics
