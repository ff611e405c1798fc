#include "ramtk/calib/robot_model_eval.h"

#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "ramtk/kinematics/forward.h"

namespace ramtk::calib {

using kinematics::ChainParamIndex;
using kinematics::ParamKind;

UnknownLayout::UnknownLayout(int joints, int num_targets_in, bool rotation_in, int harmonics_in)
    : num_joints(joints), num_targets(num_targets_in), harmonics(harmonics_in), rotation(rotation_in) {
  kin = 0;
  base = kin + kinematics::kParamsPerLink * joints;
  targets = base + 6;
  tool = targets + 3 * num_targets;
  cyclic = tool + (rotation ? 3 : 0);
  compliance = cyclic + 2 * harmonics * joints;
  size = compliance + joints;
}

kinematics::RobotChain ChainFromUnknowns(const ModelFrame& frame, const Eigen::VectorXd& x) {
  kinematics::RobotChain chain = *frame.chain;
  chain.SetParams(x.segment(frame.layout.kin, chain.NumParams()));
  return chain;
}

void EvaluatePose(const ModelFrame& frame, const Eigen::VectorXd& x, const PoseInput& pose, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian) {
  const UnknownLayout& L = frame.layout;
  const kinematics::RobotChain& chain = *frame.chain;
  const int n = L.num_joints;
  // Joint angles with the non-geometric terms; dθ_j/d(term) kept for the chain rule.
  Eigen::VectorXd theta_in = chain.ModelFromController(pose.q);
  for (int j = 0; j < n; ++j) {
    for (int h = 1; h <= L.harmonics; ++h) {
      const int c = L.cyclic + 2 * (L.harmonics * j + h - 1);
      theta_in[j] += x[c] * std::sin(h * pose.q[j]) + x[c + 1] * std::cos(h * pose.q[j]);
    }
    theta_in[j] += x[L.compliance + j] * pose.torque[j];
  }
  // Frames: before[i] = base_from_link i (the frame whose Z is joint i+1's axis).
  // On the stack: this runs once per pose and solver iteration.
  std::array<Isometry3, kinematics::kMaxChainJoints + 1> frames;
  frames[0] = Isometry3::Identity();
  for (int i = 0; i < n; ++i) {
    kinematics::LinkParams link;
    link.d = x[L.kin + ChainParamIndex(ParamKind::kD, i)];
    link.theta0 = x[L.kin + ChainParamIndex(ParamKind::kTheta, i)];
    link.a = x[L.kin + ChainParamIndex(ParamKind::kA, i)];
    link.alpha = x[L.kin + ChainParamIndex(ParamKind::kAlpha, i)];
    link.beta = x[L.kin + ChainParamIndex(ParamKind::kBeta, i)];
    frames[i + 1] = frames[i] * kinematics::LinkTransform(link, theta_in[i]);
  }
  const Mat3 r_tb = ExpSO3(x.segment<3>(L.base)) * frame.base_rotation;
  const Vec3 t_tb = x.segment<3>(L.base + 3);
  const Isometry3& flange = frames[n];
  const int rows = L.RowsPerPose();
  residual->resize(rows);
  std::vector<Vec3> p_base(L.num_targets);
  for (int k = 0; k < L.num_targets; ++k) {
    p_base[k] = flange * Vec3(x.segment<3>(L.targets + 3 * k));
    residual->segment<3>(3 * k) = r_tb * p_base[k] + t_tb - pose.measured[k];
  }
  Mat3 r_ft = Mat3::Identity();
  if (L.rotation) {
    r_ft = frame.tool_rotation * ExpSO3(x.segment<3>(L.tool));
    const Mat3 predicted = r_tb * flange.linear() * r_ft;
    residual->segment<3>(3 * L.num_targets) = LogSO3(predicted * pose.measured_rotation.transpose());
  }
  if (jacobian == nullptr) return;

  Eigen::MatrixXd& J = *jacobian;
  J.setZero(rows, L.size);
  const int rot_row = 3 * L.num_targets;
  // d(point)/d(angle about axis w through o) = w × (p − o); rotation rows get w.
  auto add_rotation = [&](int col, const Vec3& axis_base, const Vec3& origin_base, double scale) {
    for (int k = 0; k < L.num_targets; ++k) {
      J.block<3, 1>(3 * k, col) += scale * (r_tb * axis_base.cross(p_base[k] - origin_base));
    }
    if (L.rotation) J.block<3, 1>(rot_row, col) += scale * (r_tb * axis_base);
  };
  auto add_translation = [&](int col, const Vec3& direction_base) {
    for (int k = 0; k < L.num_targets; ++k) J.block<3, 1>(3 * k, col) += r_tb * direction_base;
  };
  for (int i = 0; i < n; ++i) {
    const Mat3& r_prev = frames[i].linear();
    const Vec3 origin_prev = frames[i].translation();
    const Vec3 z = r_prev.col(2);
    const double alpha = x[L.kin + ChainParamIndex(ParamKind::kAlpha, i)];
    const double theta = x[L.kin + ChainParamIndex(ParamKind::kTheta, i)] + theta_in[i];
    const Mat3 r_theta = r_prev * RotZ(theta);
    const Vec3 x_axis = r_theta.col(0);
    const Vec3 y_axis = (r_theta * RotX(alpha)).col(1);
    const Vec3 origin_next = frames[i + 1].translation();
    add_translation(L.kin + ChainParamIndex(ParamKind::kD, i), z);
    add_rotation(L.kin + ChainParamIndex(ParamKind::kTheta, i), z, origin_prev, 1.0);
    add_translation(L.kin + ChainParamIndex(ParamKind::kA, i), x_axis);
    add_rotation(L.kin + ChainParamIndex(ParamKind::kAlpha, i), x_axis, origin_next, 1.0);
    add_rotation(L.kin + ChainParamIndex(ParamKind::kBeta, i), y_axis, origin_next, 1.0);
    for (int h = 1; h <= L.harmonics; ++h) {
      const int c = L.cyclic + 2 * (L.harmonics * i + h - 1);
      add_rotation(c, z, origin_prev, std::sin(h * pose.q[i]));
      add_rotation(c + 1, z, origin_prev, std::cos(h * pose.q[i]));
    }
    add_rotation(L.compliance + i, z, origin_prev, pose.torque[i]);
  }
  // tracker_from_base: a left rotation φ and the translation.
  for (int k = 0; k < L.num_targets; ++k) {
    J.block<3, 3>(3 * k, L.base) = -Skew(r_tb * p_base[k]);
    J.block<3, 3>(3 * k, L.base + 3) = Mat3::Identity();
    J.block<3, 3>(3 * k, L.targets + 3 * k) = r_tb * flange.linear();
  }
  if (L.rotation) {
    J.block<3, 3>(rot_row, L.base) = Mat3::Identity();
    J.block<3, 3>(rot_row, L.tool) = r_tb * flange.linear() * r_ft;
  }
}

}  // namespace ramtk::calib
