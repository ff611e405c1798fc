#include "kdl_peer.h"

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include <random>

#include "ramtk/kinematics/robot_io.h"

namespace ramtk::kinematics::testing {
namespace {

KDL::Chain MakeChain(const RobotModel& model) {
  KDL::Chain chain;
  for (const LinkParams& l : model.links) {
    const KDL::Frame tip = KDL::Frame::DH(l.a, l.alpha, l.d, l.theta0) * KDL::Frame(KDL::Rotation::RotY(l.beta));
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), tip));
  }
  return chain;
}

KDL::JntArray ModelAngles(const RobotModel& model, const JointVector& q) {
  const JointVector t = model.ModelFromController(q);
  KDL::JntArray a(kNumJoints);
  for (int i = 0; i < kNumJoints; ++i) a(i) = t[i];
  return a;
}

}  // namespace

Isometry3 KdlBaseFromFlange(const RobotModel& model, const JointVector& q) {
  const KDL::Chain chain = MakeChain(model);
  KDL::ChainFkSolverPos_recursive solver(chain);
  KDL::Frame f;
  solver.JntToCart(ModelAngles(model, q), f);
  Isometry3 out = Isometry3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.linear()(r, c) = f.M(r, c);
    out.translation()[r] = f.p(r);
  }
  return out;
}

Eigen::Matrix<double, 6, 6> KdlJointJacobian(const RobotModel& model, const JointVector& q) {
  const KDL::Chain chain = MakeChain(model);
  KDL::ChainJntToJacSolver solver(chain);
  KDL::Jacobian jac(kNumJoints);
  solver.JntToJac(ModelAngles(model, q), jac);
  Eigen::Matrix<double, 6, 6> out = jac.data;
  for (int i = 0; i < kNumJoints; ++i) out.col(i) *= model.mapping[i].sign;
  return out;
}

RobotModel PerturbedModel(const RobotModel& model, unsigned seed, double length_mm, double angle_rad,
                          bool all_params) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ParamVector p = model.Params();
  for (int k = 0; k < kNumParams; ++k) {
    if (model.structural_zero[k] && !all_params) continue;
    p[k] += u(rng) * (IsAngleParam(k) ? angle_rad : length_mm);
  }
  RobotModel out = model;
  out.SetParams(p);
  return out;
}

RobotModel LoadShippedRobot(const std::string& file_name) {
  return ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/" + file_name);
}

}  // namespace ramtk::kinematics::testing
