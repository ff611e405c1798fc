#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {
namespace {
const char* const kKindNames[] = {"d", "theta", "a", "alpha", "beta"};
}

std::string ParamName(int index) {
  return std::string(kKindNames[index / kNumJoints]) + std::to_string(index % kNumJoints + 1);
}

int ParamIndexFromName(const std::string& name) {
  for (int i = 0; i < kNumParams; ++i) {
    if (ParamName(i) == name) return i;
  }
  return -1;
}

ParamVector RobotModel::Params() const {
  ParamVector p;
  for (int j = 0; j < kNumJoints; ++j) {
    p[ParamIndex(ParamKind::kD, j)] = links[j].d;
    p[ParamIndex(ParamKind::kTheta, j)] = links[j].theta0;
    p[ParamIndex(ParamKind::kA, j)] = links[j].a;
    p[ParamIndex(ParamKind::kAlpha, j)] = links[j].alpha;
    p[ParamIndex(ParamKind::kBeta, j)] = links[j].beta;
  }
  return p;
}

void RobotModel::SetParams(const ParamVector& p) {
  for (int j = 0; j < kNumJoints; ++j) {
    links[j].d = p[ParamIndex(ParamKind::kD, j)];
    links[j].theta0 = p[ParamIndex(ParamKind::kTheta, j)];
    links[j].a = p[ParamIndex(ParamKind::kA, j)];
    links[j].alpha = p[ParamIndex(ParamKind::kAlpha, j)];
    links[j].beta = p[ParamIndex(ParamKind::kBeta, j)];
  }
}

std::vector<int> RobotModel::FreeParams() const {
  std::vector<int> out;
  for (int i = 0; i < kNumParams; ++i) {
    if (!structural_zero[i]) out.push_back(i);
  }
  return out;
}

JointVector RobotModel::ModelFromController(const JointVector& q) const {
  JointVector t;
  for (int j = 0; j < kNumJoints; ++j) t[j] = mapping[j].sign * q[j] + mapping[j].offset;
  return t;
}

JointVector RobotModel::ControllerFromModel(const JointVector& theta_in) const {
  JointVector q;
  for (int j = 0; j < kNumJoints; ++j) q[j] = (theta_in[j] - mapping[j].offset) / mapping[j].sign;
  return q;
}

}  // namespace ramtk::kinematics
