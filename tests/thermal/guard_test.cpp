// The identifiability guard and the σ of the identified drift, against truths the identification
// does not produce: zero drift (the simulator with its drift removed), the scatter of repeated
// experiments, and a pose set whose geometry makes two parameters indistinguishable.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/monitoring.h"
#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using kinematics::ParamIndexFromName;
using testing::Kr150;

// The thesis experiment with no parameter drift: only sensor noise and repeatability.
ThermalSimResult NoDrift(std::uint64_t seed, int cycles) {
  ThermalSimOptions o = ThesisPreset(seed);
  o.drifts.clear();
  o.cycles = cycles;
  return SimulateThermal(Kr150(), o);
}

std::vector<int> Names(const std::vector<std::string>& names) {
  std::vector<int> out;
  for (const auto& n : names) out.push_back(ParamIndexFromName(n));
  std::sort(out.begin(), out.end());
  return out;
}

const std::vector<std::string> kThesisSet = {"d4", "d6", "a1", "a2", "a3", "alpha3", "alpha4", "beta2"};

// (a) Null test: measurements repeated minutes apart with zero drift. Every identified
// parameter of the warm cycle lies within 3σ of zero, for the thesis's 8 drifting parameters and
// the traditional set, on all 20 poses and on 6 D-optimal poses, over 5 fixed seeds.
TEST(ThermalGuard, ZeroDriftIsIdentifiedAsZeroWithinThreeSigma) {
  double worst_z = 0.0;
  int values = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const ThermalSimResult r = NoDrift(seed, 2);
    const CycleSeries ball = GroupCycles(r.ball, "ball.csv");
    const DriftModel dm(Kr150(), r.setup, ball.taught);
    for (const std::vector<int>& params : {Names(kThesisSet), TraditionalParams(Kr150())}) {
      for (int budget : {20, 6}) {
        IdentificationOptions id;
        id.params = params;
        if (budget < 20) id.poses = SelectPoses(dm, params, budget);
        const IdentifiabilitySummary g = CheckIdentifiability(dm, id.params, id.poses, {});
        ASSERT_TRUE(g.Identifiable()) << g.BriefReport();
        IdentificationSummary s;
        const Eigen::MatrixXd x = dm.Solve(ball.DifferencesFromReference(id.poses), id, &s);
        ASSERT_EQ(s.covariance.size(), 2u);
        for (std::size_t k = 0; k < params.size(); ++k) {
          EXPECT_EQ(s.Sigma(static_cast<int>(k), 0), 0.0);  // the reference cycle
          const double sigma = s.Sigma(static_cast<int>(k), 1);
          ASSERT_GT(sigma, 0.0);
          const double z = x(params[k], 1) / sigma;
          worst_z = std::max(worst_z, std::abs(z));
          ++values;
          EXPECT_LT(std::abs(z), 3.0) << kinematics::ParamName(params[k]) << " seed " << seed << " budget " << budget;
        }
      }
    }
  }
  RecordProperty("worst_abs_z", std::to_string(worst_z));
  RecordProperty("values", values);
}

// (b) Monte Carlo: over 100 seeds of the zero-drift experiment (8 parameters, 20 poses), each
// parameter's identified value divided by its predicted σ has an RMS within 0.8–1.25, and the
// RMS of the predicted σ matches the scatter of the values within the same band.
TEST(ThermalGuard, PredictedSigmaMatchesTheScatterOverSeeds) {
  const std::vector<int> params = Names(kThesisSet);
  const int n = 100;
  const std::size_t k = params.size();
  Eigen::MatrixXd z(k, n), value(k, n), sigma(k, n);
  for (int i = 0; i < n; ++i) {
    ThermalSimOptions o = ThesisPreset(1000 + static_cast<std::uint64_t>(i));
    o.drifts.clear();
    o.cycles = 2;
    o.monitoring_points = 1;
    const ThermalSimResult r = SimulateThermal(Kr150(), o);
    const CycleSeries ball = GroupCycles(r.ball, "ball.csv");
    IdentificationOptions id;
    id.params = params;
    IdentificationSummary s;
    const Eigen::MatrixXd x = IdentifyCycles(Kr150(), r.setup, ball, id, &s);
    for (std::size_t j = 0; j < k; ++j) {
      value(j, i) = x(params[j], 1);
      sigma(j, i) = s.Sigma(static_cast<int>(j), 1);
      z(j, i) = value(j, i) / sigma(j, i);
    }
  }
  for (std::size_t j = 0; j < k; ++j) {
    const double z_rms = std::sqrt(z.row(j).squaredNorm() / n);
    const double scatter = std::sqrt(value.row(j).squaredNorm() / n);  // the truth is zero
    const double predicted = std::sqrt(sigma.row(j).squaredNorm() / n);
    const std::string name = kinematics::ParamName(params[j]);
    EXPECT_GT(z_rms, 0.8) << name;
    EXPECT_LT(z_rms, 1.25) << name;
    EXPECT_GT(scatter / predicted, 0.8) << name;
    EXPECT_LT(scatter / predicted, 1.25) << name;
    RecordProperty("z_rms_" + name, std::to_string(z_rms));
    RecordProperty("scatter_over_predicted_" + name, std::to_string(scatter / predicted));
  }
}

// A UR10 (Universal Robots' DH) measured with the wrist held so that joint 5's axis is vertical,
// parallel to joint 1's, as in a pick-and-place program: d1 and d5 both move the ball along the
// same vertical line and only their sum is seen. Joint readings carry a 0.02° jitter, so the
// matrix is not exactly singular (its QR rank is full).
struct Ur10Case {
  kinematics::RobotModel model;
  ThermalSetup setup;
  std::vector<JointVector> poses;
};

// Angle (rad) between joint 1's and joint 5's axes.
double AxisAngle15(const kinematics::RobotModel& m, const JointVector& q) {
  const kinematics::ChainFrames f = kinematics::ComputeChainFrames(m, q);
  const Vec3 z0 = f.base_from_link[0].linear().col(2), z4 = f.base_from_link[4].linear().col(2);
  return std::atan2(z0.cross(z4).norm(), std::abs(z0.dot(z4)));
}

Ur10Case Ur10(bool wrist_vertical, std::uint64_t seed) {
  Ur10Case c;
  c.model = kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/ur10.yaml");
  c.setup.sensor_from_base = Isometry3::Identity();
  c.setup.sensor_from_base.linear() = RotZ(DegToRad(30)) * RotY(DegToRad(-20)) * RotX(DegToRad(170));
  c.setup.sensor_from_base.translation() = Vec3(200, -100, 900);
  c.setup.ball_in_flange = Vec3(20, -15, 150);
  // q2 + q3 + q4 that makes joint 5's axis parallel to joint 1's, found by bisection on the model.
  JointVector q0 = JointVector::Zero();
  q0 << 0, DegToRad(-90), DegToRad(90), 0, DegToRad(90), 0;
  double lo = DegToRad(-180), hi = DegToRad(0), best = 0.0, best_angle = 10.0;
  for (int i = 0; i <= 3600; ++i) {
    JointVector q = q0;
    q[3] = lo + (hi - lo) * i / 3600.0 - q[1] - q[2];
    const double a = AxisAngle15(c.model, q);
    if (a < best_angle) best_angle = a, best = q[1] + q[2] + q[3];
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, DegToRad(0.02));
  for (int i = 0; i < 39; ++i) {
    JointVector q;
    q[0] = DegToRad(-60 + 120 * u(rng));
    q[1] = DegToRad(-120 + 60 * u(rng));
    q[2] = DegToRad(40 + 80 * u(rng));
    q[3] = wrist_vertical ? best - q[1] - q[2] + jitter(rng) : DegToRad(-180 + 180 * u(rng));
    q[4] = DegToRad(30 + 120 * u(rng));
    q[5] = DegToRad(-180 + 360 * u(rng));
    c.poses.push_back(q);
  }
  return c;
}

TEST(ThermalGuard, Ur10WristVerticalPosesHaveParallelJointOneAndFiveAxes) {
  const Ur10Case c = Ur10(true, 7);
  for (const JointVector& q : c.poses) EXPECT_LT(RadToDeg(AxisAngle15(c.model, q)), 0.1);
}

// (c) The degenerate set is refused, naming d1 and d5 and the parallel axes, although the plain
// solve calls it full rank; with reduce one of them is dropped and the rest is identified.
TEST(ThermalGuard, ParallelAxesMakeD1AndD5UnobservableAndReduceDropsOne) {
  const Ur10Case c = Ur10(true, 7);
  const DriftModel dm(c.model, c.setup, c.poses);
  const std::vector<int> params = TraditionalParams(c.model);
  ASSERT_EQ(ParamListToString(params), "d1,d4,d5,d6,a2,a3");
  // Zero drift, 0.03 mm noise per coordinate of a difference.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.03);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(3 * dm.NumPoses(), 2);
  for (Eigen::Index r = 0; r < y.rows(); ++r) y(r, 1) = noise(rng);

  IdentificationOptions id;
  id.params = params;
  IdentificationSummary plain;
  dm.Solve(y, id, &plain);
  EXPECT_EQ(plain.rank, 6);  // what the unguarded solve reported
  EXPECT_GT(plain.condition_number, 1e3);

  const IdentifiabilitySummary g = CheckIdentifiability(dm, params, {}, {});
  EXPECT_FALSE(g.Identifiable());
  EXPECT_EQ(g.termination, Termination::kNoResult);
  ASSERT_EQ(g.combinations.size(), 1u);
  EXPECT_EQ(Names({"d1", "d5"}), [&] {
    std::vector<int> p = g.combinations[0].params;
    std::sort(p.begin(), p.end());
    return p;
  }());
  // Both move the ball along the same axis: opposite signs cancel.
  EXPECT_LT(g.combinations[0].coefficients[0] * g.combinations[0].coefficients[1], 0.0);
  EXPECT_NE(g.message.find("not observable"), std::string::npos) << g.message;
  EXPECT_NE(g.message.find("joints 1 and 5 axes parallel"), std::string::npos) << g.message;

  IdentifiabilityOptions reduce;
  reduce.reduce = true;
  const IdentifiabilitySummary r = CheckIdentifiability(dm, params, {}, reduce);
  ASSERT_TRUE(r.Identifiable()) << r.BriefReport();
  EXPECT_EQ(r.termination, Termination::kPartial);
  ASSERT_EQ(r.dropped.size(), 1u);
  const int d1 = ParamIndexFromName("d1"), d5 = ParamIndexFromName("d5");
  EXPECT_TRUE(r.dropped[0] == d1 || r.dropped[0] == d5);
  EXPECT_EQ(r.params.size(), 5u);
  EXPECT_LE(r.condition_number, 1e3);
  // The reduced set is identified, zero within 3σ.
  id.params = r.params;
  IdentificationSummary s;
  const Eigen::MatrixXd x = dm.Solve(y, id, &s);
  EXPECT_EQ(s.rank, 5);
  for (std::size_t k = 0; k < r.params.size(); ++k) {
    EXPECT_LT(std::abs(x(r.params[k], 1)), 3.0 * s.Sigma(static_cast<int>(k), 1)) << kinematics::ParamName(r.params[k]);
  }
}

// The same robot with the wrist turned freely: the traditional set passes the guard.
TEST(ThermalGuard, Ur10WithFreeWristPasses) {
  const Ur10Case c = Ur10(false, 7);
  const DriftModel dm(c.model, c.setup, c.poses);
  const IdentifiabilitySummary g = CheckIdentifiability(dm, TraditionalParams(c.model), {}, {});
  EXPECT_TRUE(g.Identifiable()) << g.BriefReport();
  EXPECT_EQ(g.termination, Termination::kSuccess);
}

// Every free KR150 parameter from 20 ball poses: the flange's rotation about its own axis
// (θ6 with α6) is invisible to a ball centre; the guard names it.
TEST(ThermalGuard, AllFreeKr150ParametersAreRefusedNamingTheta6AndAlpha6) {
  const auto& e = testing::Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const IdentifiabilitySummary g = CheckIdentifiability(dm, {}, {}, {});
  ASSERT_FALSE(g.Identifiable());
  std::vector<int> p = g.combinations[0].params;
  std::sort(p.begin(), p.end());
  EXPECT_EQ(p, Names({"theta6", "alpha6"}));
  IdentifiabilityOptions reduce;
  reduce.reduce = true;
  const IdentifiabilitySummary r = CheckIdentifiability(dm, {}, {}, reduce);
  ASSERT_TRUE(r.Identifiable());
  EXPECT_TRUE(r.dropped[0] == ParamIndexFromName("theta6") || r.dropped[0] == ParamIndexFromName("alpha6"));
  EXPECT_LE(r.condition_number, 1e3);
}

// The covariance of a compensated point is J Σ Jᵀ of the identified drift's covariance: its
// diagonal agrees with the existing σ propagation (CompensatedMonitoringSigma) when both use the
// same σ_Y.
TEST(ThermalGuard, CompensatedPointCovarianceIsTheDriftCovarianceCarriedThroughTheJacobian) {
  const auto& e = testing::Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const MonitoringModel mon(Kr150(), e.sim.setup, e.experiment.monitoring);
  IdentificationOptions id;
  id.params = Names(kThesisSet);
  IdentificationSummary s;
  dm.Solve(e.experiment.ball.DifferencesFromReference({}), id, &s);
  const std::vector<Mat3> cov = CompensatedPointCovariances(mon, id.params, s.covariance[1]);
  const Eigen::VectorXd sigma = CompensatedMonitoringSigma(mon, dm, id, std::sqrt(s.covariance_scale));
  ASSERT_EQ(static_cast<int>(cov.size()), mon.NumPoints());
  for (int k = 0; k < mon.NumPoints(); ++k) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::sqrt(cov[k](a, a)), sigma[3 * k + a], 1e-9 + 1e-6 * sigma[3 * k + a]);
    EXPECT_LT((cov[k] - cov[k].transpose()).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace ramtk::thermal
