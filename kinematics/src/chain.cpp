#include "ramtk/kinematics/chain.h"

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::kinematics {
namespace {
const char* const kKindNames[] = {"d", "theta", "a", "alpha", "beta"};
}

std::string ChainParamName(int index) {
  return std::string(kKindNames[index % kParamsPerLink]) + std::to_string(index / kParamsPerLink + 1);
}

int ChainParamIndexFromName(const std::string& name, int num_joints) {
  for (int i = 0; i < kParamsPerLink * num_joints; ++i) {
    if (ChainParamName(i) == name) return i;
  }
  return -1;
}

bool IsChainAngleParam(int index) {
  const auto kind = static_cast<ParamKind>(index % kParamsPerLink);
  return kind != ParamKind::kD && kind != ParamKind::kA;
}

Eigen::VectorXd RobotChain::Params() const {
  Eigen::VectorXd p(NumParams());
  for (int j = 0; j < NumJoints(); ++j) {
    p[ChainParamIndex(ParamKind::kD, j)] = links[j].d;
    p[ChainParamIndex(ParamKind::kTheta, j)] = links[j].theta0;
    p[ChainParamIndex(ParamKind::kA, j)] = links[j].a;
    p[ChainParamIndex(ParamKind::kAlpha, j)] = links[j].alpha;
    p[ChainParamIndex(ParamKind::kBeta, j)] = links[j].beta;
  }
  return p;
}

void RobotChain::SetParams(const Eigen::VectorXd& p) {
  for (int j = 0; j < NumJoints(); ++j) {
    links[j].d = p[ChainParamIndex(ParamKind::kD, j)];
    links[j].theta0 = p[ChainParamIndex(ParamKind::kTheta, j)];
    links[j].a = p[ChainParamIndex(ParamKind::kA, j)];
    links[j].alpha = p[ChainParamIndex(ParamKind::kAlpha, j)];
    links[j].beta = p[ChainParamIndex(ParamKind::kBeta, j)];
  }
}

Eigen::VectorXd RobotChain::ModelFromController(const Eigen::VectorXd& q) const {
  Eigen::VectorXd t(NumJoints());
  for (int j = 0; j < NumJoints(); ++j) t[j] = mapping[j].sign * q[j] + mapping[j].offset;
  return t;
}

Isometry3 ChainBaseFromFlange(const RobotChain& chain, const Eigen::VectorXd& q_controller) {
  const Eigen::VectorXd theta_in = chain.ModelFromController(q_controller);
  Isometry3 t = Isometry3::Identity();
  for (int i = 0; i < chain.NumJoints(); ++i) t = t * LinkTransform(chain.links[i], theta_in[i]);
  return t;
}

std::vector<Isometry3> ChainLinkFrames(const RobotChain& chain, const Eigen::VectorXd& q_controller) {
  const Eigen::VectorXd theta_in = chain.ModelFromController(q_controller);
  std::vector<Isometry3> frames(chain.NumJoints() + 1, Isometry3::Identity());
  for (int i = 0; i < chain.NumJoints(); ++i) frames[i + 1] = frames[i] * LinkTransform(chain.links[i], theta_in[i]);
  return frames;
}

RobotChain ChainFromRobotModel(const RobotModel& model) {
  RobotChain chain;
  chain.name = model.name;
  chain.source = model.source;
  chain.convention = model.convention;
  chain.links.assign(model.links.begin(), model.links.end());
  chain.mapping.assign(model.mapping.begin(), model.mapping.end());
  chain.structural_zero.assign(chain.NumParams(), false);
  for (int k = 0; k < kNumParams; ++k) {
    chain.structural_zero[ChainParamIndex(ParamKindOf(k), ParamJointOf(k))] = model.structural_zero[k];
  }
  return chain;
}

RobotModel RobotModelFromChain(const RobotChain& chain, const std::string& path, const std::string& field) {
  if (chain.NumJoints() != kNumJoints) {
    throw InputError({path, 0, field}, "this command needs a 6-joint robot; the file has " +
                                           std::to_string(chain.NumJoints()) + " joints");
  }
  RobotModel model;
  model.name = chain.name;
  model.source = chain.source;
  model.convention = chain.convention;
  for (int j = 0; j < kNumJoints; ++j) {
    model.links[j] = chain.links[j];
    model.mapping[j] = chain.mapping[j];
  }
  for (int k = 0; k < kNumParams; ++k) {
    model.structural_zero[k] = chain.structural_zero[ChainParamIndex(ParamKindOf(k), ParamJointOf(k))];
  }
  return model;
}

double ChainReachMm(const RobotChain& chain) {
  double reach = 0.0;
  for (const LinkParams& l : chain.links) reach += std::abs(l.a) + std::abs(l.d);
  return reach;
}

Eigen::VectorXd GravityTorques(const RobotChain& chain, const Eigen::VectorXd& q_controller) {
  const int n = chain.NumJoints();
  Eigen::VectorXd torque = Eigen::VectorXd::Zero(n);
  if (!chain.HasMasses()) return torque;
  const std::vector<Isometry3> frames = ChainLinkFrames(chain, q_controller);
  // Each mass's weight (kg, direction of gravity) and where it acts, in the base frame.
  std::vector<std::pair<double, Vec3>> loads;
  for (int i = 0; i < n; ++i) loads.emplace_back(chain.masses[i].mass_kg, frames[i + 1] * chain.masses[i].com_mm);
  loads.emplace_back(chain.payload.mass_kg, frames[n] * chain.payload.com_mm);
  const Vec3 g = chain.gravity_in_base.normalized();
  for (int j = 0; j < n; ++j) {
    // Joint j turns about Z of frame j (the frame before its link transform): the model's θ_j.
    const Vec3 axis = frames[j].linear().col(2);
    const Vec3 origin = frames[j].translation();
    // Loads carried by joint j: those of links j+1..N and the payload.
    for (std::size_t k = static_cast<std::size_t>(j); k < loads.size(); ++k) {
      torque[j] += axis.dot((loads[k].second - origin).cross(loads[k].first * g));
    }
  }
  return torque;
}

}  // namespace ramtk::kinematics
