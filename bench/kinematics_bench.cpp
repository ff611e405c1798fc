// Forward kinematics and Jacobians: ramtk beside Orocos KDL (FK, joint Jacobian) and beside
// central finite differences (the 30-parameter Jacobian), all on the same 256 random
// configurations of the KR150 MDH model.
#include <benchmark/benchmark.h>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include <random>
#include <vector>

#include "ramtk/kinematics/jacobian.h"
#include "ramtk/kinematics/robot_io.h"

namespace {

using namespace ramtk;
using namespace ramtk::kinematics;

struct Data {
  RobotModel model;
  std::vector<JointVector> q;
  KDL::Chain chain;
  std::vector<KDL::JntArray> q_kdl;
};

const Data& GetData() {
  static const Data data = [] {
    Data d;
    d.model = ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
    ParamVector p = d.model.Params();
    p[ParamIndex(ParamKind::kBeta, 1)] = 1e-4;  // exercise the β factor
    d.model.SetParams(p);
    for (const LinkParams& l : d.model.links) {
      d.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                      KDL::Frame::DH(l.a, l.alpha, l.d, l.theta0) *
                                          KDL::Frame(KDL::Rotation::RotY(l.beta))));
    }
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int n = 0; n < 256; ++n) {
      JointVector q;
      for (int i = 0; i < kNumJoints; ++i) q[i] = u(rng);
      d.q.push_back(q);
      const JointVector t = d.model.ModelFromController(q);
      KDL::JntArray a(kNumJoints);
      for (int i = 0; i < kNumJoints; ++i) a(i) = t[i];
      d.q_kdl.push_back(a);
    }
    return d;
  }();
  return data;
}

void BM_Fk_Ramtk(benchmark::State& state) {
  const Data& d = GetData();
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(BaseFromFlange(d.model, d.q[n++ & 255]));
  }
}
BENCHMARK(BM_Fk_Ramtk);

void BM_Fk_Kdl(benchmark::State& state) {
  const Data& d = GetData();
  KDL::ChainFkSolverPos_recursive solver(d.chain);
  KDL::Frame f;
  std::size_t n = 0;
  for (auto _ : state) {
    solver.JntToCart(d.q_kdl[n++ & 255], f);
    benchmark::DoNotOptimize(f);
  }
}
BENCHMARK(BM_Fk_Kdl);

void BM_JointJacobian_Ramtk(benchmark::State& state) {
  const Data& d = GetData();
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ComputeJointJacobian(d.model, d.q[n++ & 255]));
  }
}
BENCHMARK(BM_JointJacobian_Ramtk);

void BM_JointJacobian_Kdl(benchmark::State& state) {
  const Data& d = GetData();
  KDL::ChainJntToJacSolver solver(d.chain);
  KDL::Jacobian jac(kNumJoints);
  std::size_t n = 0;
  for (auto _ : state) {
    solver.JntToJac(d.q_kdl[n++ & 255], jac);
    benchmark::DoNotOptimize(jac.data);
  }
}
BENCHMARK(BM_JointJacobian_Kdl);

const Vec3 kBallInFlange(12.0, -25.0, 160.0);

void BM_ParamJacobian_Analytic(benchmark::State& state) {
  const Data& d = GetData();
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ComputePointParamJacobian(d.model, d.q[n++ & 255], kBallInFlange));
  }
}
BENCHMARK(BM_ParamJacobian_Analytic);

void BM_ParamJacobian_CentralDifference(benchmark::State& state) {
  const Data& d = GetData();
  RobotModel m = d.model;
  const ParamVector p0 = m.Params();
  std::size_t n = 0;
  for (auto _ : state) {
    const JointVector& q = d.q[n++ & 255];
    PointParamJacobian jac;
    for (int k = 0; k < kNumParams; ++k) {
      const double h = IsAngleParam(k) ? 1e-6 : 1e-3;
      ParamVector p = p0;
      p[k] += h;
      m.SetParams(p);
      const Vec3 plus = BaseFromFlange(m, q) * kBallInFlange;
      p[k] -= 2 * h;
      m.SetParams(p);
      jac.col(k) = (plus - BaseFromFlange(m, q) * kBallInFlange) / (2 * h);
    }
    benchmark::DoNotOptimize(jac);
  }
}
BENCHMARK(BM_ParamJacobian_CentralDifference);

}  // namespace

BENCHMARK_MAIN();
