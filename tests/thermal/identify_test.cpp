// Identification (eqs. 3-5..3-10) against finite differences and the simulator's truth.
#include "ramtk/thermal/identify.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/kinematics/forward.h"
#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using kinematics::kNumParams;
using kinematics::ParamIndexFromName;
using testing::Kr150;
using testing::Thesis;

Vec3 BallInSensor(const kinematics::ParamVector& params, const ThermalSetup& setup, const JointVector& q) {
  kinematics::RobotModel m = Kr150();
  m.SetParams(params);
  return setup.sensor_from_base * (kinematics::BaseFromFlange(m, q) * setup.ball_in_flange);
}

// Eq. (3-7)'s M_i against central differences of eq. (3-1) with perturbed MDH parameters.
TEST(ThermalIdentify, SensitivityMatchesFiniteDifferencesOfTheBallCentre) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const kinematics::ParamVector x0 = Kr150().Params();
  for (int i : {0, 7, 19}) {
    for (int p = 0; p < kNumParams; ++p) {
      const double h = kinematics::IsAngleParam(p) ? 1e-6 : 1e-3;
      kinematics::ParamVector plus = x0, minus = x0;
      plus[p] += h;
      minus[p] -= h;
      const Vec3 fd = (BallInSensor(plus, e.sim.setup, e.experiment.ball.taught[i]) -
                       BallInSensor(minus, e.sim.setup, e.experiment.ball.taught[i])) /
                      (2 * h);
      const Vec3 analytic = dm.FullSensitivity().block<3, 1>(3 * i, p);
      EXPECT_LT((fd - analytic).norm(), 1e-6 * (1 + analytic.norm())) << kinematics::ParamName(p) << " pose " << i;
    }
  }
}

// Noise-free data: the truth set is recovered up to the linearisation of eq. (3-5) (second order
// in the drift: < 1 % of it).
TEST(ThermalIdentify, NoiseFreeRecoversTheTrueDrift) {
  ThermalSimOptions o = ThesisPreset(2);
  o.cycles = 40;
  o.sensor_noise_mm = o.tool_sensor_noise_mm = o.repeatability_mm = 0.0;
  o.drift_changes_within_cycle = false;
  const ThermalSimResult r = SimulateThermal(Kr150(), o);
  const CycleSeries ball = GroupCycles(r.ball, "ball.csv");
  IdentificationOptions id;
  id.params = r.drifting_params;
  IdentificationSummary s;
  const Eigen::MatrixXd x = IdentifyCycles(Kr150(), r.setup, ball, id, &s);
  EXPECT_EQ(s.rank, 8);
  for (int p : r.drifting_params) {
    for (int c = 1; c < o.cycles; ++c) {
      const double slack = 0.01 * r.true_delta_x.row(p).cwiseAbs().maxCoeff();
      EXPECT_NEAR(x(p, c), r.true_delta_x(p, c), slack) << kinematics::ParamName(p) << " cycle " << c;
    }
  }
  EXPECT_LT(s.rms_residual_mm, 1e-4);
}

// Eq. (3-10) on noisy data: the error of each identified parameter agrees with the noise
// propagated through (AᵀA)⁻¹, σ_Y² = 2(σ_sensor² + σ_repeatability²) per coordinate (the warm and
// the cold measurement each carry both).
void CheckAgainstNoiseBound(int budget) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const std::vector<int> params = e.sim.drifting_params;
  IdentificationOptions id;
  id.params = params;
  if (budget < 20) id.poses = SelectPoses(dm, params, budget);
  std::vector<int> poses = id.poses;
  if (poses.empty()) {
    for (int i = 0; i < 20; ++i) poses.push_back(i);
  }
  IdentificationSummary s;
  const Eigen::MatrixXd x = dm.Solve(e.experiment.ball.DifferencesFromReference(id.poses), id, &s);
  ASSERT_EQ(s.num_poses, budget);
  Eigen::MatrixXd a(3 * budget, params.size());
  for (int i = 0; i < budget; ++i) {
    for (std::size_t c = 0; c < params.size(); ++c)
      a.block(3 * i, c, 3, 1) = dm.FullSensitivity().block(3 * poses[i], params[c], 3, 1);
  }
  const double s2 = 2 * (std::pow(e.options.sensor_noise_mm, 2) + std::pow(e.options.repeatability_mm, 2));
  const Eigen::MatrixXd cov = s2 * (a.transpose() * a).inverse();
  const Eigen::MatrixXd info = cov.inverse();
  double chi2 = 0.0;
  for (std::size_t c = 0; c < params.size(); ++c) {
    const int p = params[c];
    double sq = 0.0;
    for (int k = 1; k < 90; ++k) sq += std::pow(x(p, k) - e.sim.true_delta_x(p, k), 2);
    const double rms = std::sqrt(sq / 89);
    // The cold cycle's noise is shared by all cycles, so 89 cycles are far from 89 independent
    // draws: allow 2σ.
    EXPECT_LT(rms, 2.0 * std::sqrt(cov(c, c))) << kinematics::ParamName(p) << " budget " << budget;
    ::testing::Test::RecordProperty(kinematics::ParamName(p) + "_rms_over_sigma",
                                    std::to_string(rms / std::sqrt(cov(c, c))));
  }
  for (int k = 1; k < 90; ++k) {
    Eigen::VectorXd d(params.size());
    for (std::size_t c = 0; c < params.size(); ++c) d[c] = x(params[c], k) - e.sim.true_delta_x(params[c], k);
    chi2 += d.dot(info * d);
  }
  // E[χ²/k] = 1 for the right noise model; the shared cold-cycle noise widens its spread.
  EXPECT_GT(chi2 / 89 / params.size(), 0.25);
  EXPECT_LT(chi2 / 89 / params.size(), 2.5);
}

TEST(ThermalIdentify, ErrorWithinNoiseBoundTwentyPoses) { CheckAgainstNoiseBound(20); }

// The σ_Y the reports use for the drift's ±1σ band (estimated from the residual, dof-corrected)
// against the simulated noise: sqrt(2(σ_sensor² + σ_repeatability²)) per coordinate. With 89 warm
// cycles × (18 − 8) degrees of freedom the estimate's relative standard error is ~2.4 %.
TEST(ThermalIdentify, ResidualSigmaMatchesTheSimulatedNoise) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  IdentificationOptions id;
  id.params = e.sim.drifting_params;
  id.poses = SelectPoses(dm, id.params, 6);
  IdentificationSummary s;
  dm.Solve(e.experiment.ball.DifferencesFromReference(id.poses), id, &s);
  const double truth =
      std::sqrt(2 * (std::pow(e.options.sensor_noise_mm, 2) + std::pow(e.options.repeatability_mm, 2)));
  EXPECT_NEAR(ResidualSigmaY(s), truth, 4 * 0.024 * truth) << "estimated " << ResidualSigmaY(s) << " mm";
  ::testing::Test::RecordProperty("sigma_y_estimated_over_true", std::to_string(ResidualSigmaY(s) / truth));
}
TEST(ThermalIdentify, ErrorWithinNoiseBoundSixPoseBudget) { CheckAgainstNoiseBound(6); }

// With all 24 free parameters the KR150 ball data cannot see one combination (θ6 with α6 and a6):
// moving the parameters along the reported null vector leaves every ball centre unchanged to
// first order — checked with the forward kinematics, not with the Jacobian.
TEST(ThermalIdentify, ReportsTheUnidentifiableCombination) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  IdentificationOptions id;
  IdentificationSummary s;
  dm.Solve(e.experiment.ball.DifferencesFromReference(), id, &s);
  EXPECT_EQ(s.params.size(), 24u);
  EXPECT_EQ(s.rank, 23);
  ASSERT_EQ(s.null_space.size(), 1u);
  ASSERT_EQ(s.dependent_params.size(), 1u);
  // Null vector in parameter units (columns were equilibrated: undo the scaling).
  kinematics::ParamVector v = kinematics::ParamVector::Zero();
  const auto& combo = s.null_space[0];
  for (std::size_t i = 0; i < combo.params.size(); ++i) {
    v[combo.params[i]] = combo.coefficients[i] / dm.FullSensitivity().col(combo.params[i]).norm();
  }
  v /= v.cwiseAbs().maxCoeff();
  const double eps = 1e-4;  // rad-scale step
  const kinematics::ParamVector x0 = Kr150().Params();
  double moved = 0.0, moved_random = 0.0;
  kinematics::ParamVector random = kinematics::ParamVector::Zero();
  random[ParamIndexFromName("alpha6")] = 1.0;
  for (int i = 0; i < 20; ++i) {
    const JointVector& q = e.experiment.ball.taught[i];
    const Vec3 base = BallInSensor(x0, e.sim.setup, q);
    moved = std::max(moved, (BallInSensor(x0 + eps * v, e.sim.setup, q) - base).norm());
    moved_random = std::max(moved_random, (BallInSensor(x0 + eps * random, e.sim.setup, q) - base).norm());
  }
  EXPECT_LT(moved, 1e-3 * moved_random);
  const std::string name = kinematics::ParamName(s.dependent_params[0]);
  EXPECT_TRUE(name == "theta6" || name == "alpha6" || name == "a6") << name;
  EXPECT_TRUE(std::isinf(s.condition_number) || s.condition_number > 1e8);
}

TEST(ThermalIdentify, FewerEquationsThanParametersIsAnInputError) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  IdentificationOptions id;          // 24 parameters
  id.poses = {0, 1, 2, 3, 4, 5, 6};  // 21 equations
  try {
    dm.Solve(e.experiment.ball.DifferencesFromReference(id.poses), id);
    FAIL() << "expected InputError";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("7 poses give 21 equations, fewer than the 24 parameters"),
              std::string::npos)
        << err.what();
  }
  id.poses.push_back(7);  // 24 equations: allowed
  EXPECT_NO_THROW(dm.Solve(e.experiment.ball.DifferencesFromReference(id.poses), id));
}

TEST(ThermalIdentify, TraditionalSetIsTheThesisNonZeroLengths) {
  // Thesis §3.2: for the KR150R3100 the non-zero length parameters are d1 d4 d6 a1 a2 a3.
  EXPECT_EQ(ParamListToString(TraditionalParams(Kr150())), "d1,d4,d6,a1,a2,a3");
  EXPECT_EQ(Kr150().FreeParams().size(), 24u);
  EXPECT_EQ(ParamListToString(ParseParamList("beta2, alpha3,d4", Kr150(), "--params")), "d4,alpha3,beta2");
  EXPECT_THROW(ParseParamList("d4,gamma2", Kr150(), "--params"), InputError);
  EXPECT_THROW(ParseParamList("d2", Kr150(), "--params"), InputError);  // structural zero
  EXPECT_THROW(ParseParamList("d4,d4", Kr150(), "--params"), InputError);
}

TEST(ThermalIdentify, DOptimalSelectionBeatsTheFirstPoses) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const std::vector<int> params = e.sim.drifting_params;
  auto logdet = [&](const std::vector<int>& poses) {
    Eigen::MatrixXd a(3 * poses.size(), params.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
      for (std::size_t c = 0; c < params.size(); ++c) {
        a.block(3 * i, c, 3, 1) =
            dm.FullSensitivity().block(3 * poses[i], params[c], 3, 1) / dm.FullSensitivity().col(params[c]).norm();
      }
    }
    return std::log((a.transpose() * a).determinant());
  };
  const std::vector<int> chosen = SelectPoses(dm, params, 6);
  ASSERT_EQ(chosen.size(), 6u);
  EXPECT_GT(logdet(chosen), logdet({0, 1, 2, 3, 4, 5}));
}

}  // namespace
}  // namespace ramtk::thermal

namespace ramtk::thermal {
namespace {

// The compensation's uncertainty at the monitoring points (issue 14: each stage propagates the
// covariance it receives): CompensatedMonitoringSigma against Monte-Carlo. 30 simulated thesis
// experiments (20 cycles, drift constant within a cycle so that only the noise separates the
// identification from the truth), the 8 drifting parameters from 6 D-optimal poses. For every
// monitoring direction and warm cycle, z = J (ΔX̂ − ΔX) / σ_predicted; the RMS of z over all of
// them must be 1 within 10 % (the cycles of one experiment share the reference cycle's noise, so
// the effective sample is far smaller than the 30 · 19 · 102 values).
TEST(ThermalMonitoringSigma, PredictedCompensationSigmaMatchesMonteCarlo) {
  double sum_z2 = 0;
  long count = 0;
  for (int seed = 1; seed <= 30; ++seed) {
    ThermalSimOptions o = ThesisPreset(1000 + seed);
    o.cycles = 20;
    o.drift_changes_within_cycle = false;
    const ThermalSimResult sim = SimulateThermal(Kr150(), o);
    const ThermalExperiment ex = MakeExperiment(Kr150(), sim.setup, GroupCycles(sim.ball, "ball.csv"),
                                                GroupCycles(sim.monitoring, "monitoring.csv"));
    const DriftModel dm(Kr150(), sim.setup, ex.ball.taught);
    IdentificationOptions id;
    id.params = sim.drifting_params;
    id.poses = SelectPoses(dm, id.params, 6);
    const Eigen::MatrixXd x = dm.Solve(ex.ball.DifferencesFromReference(id.poses), id);
    const MonitoringModel mon(Kr150(), sim.setup, ex.monitoring);
    const double sigma_y = std::sqrt(2 * (o.sensor_noise_mm * o.sensor_noise_mm + o.repeatability_mm * o.repeatability_mm));
    const Eigen::VectorXd sigma = CompensatedMonitoringSigma(mon, dm, id, sigma_y);
    for (int c = 1; c < x.cols(); ++c) {
      const Eigen::VectorXd dx = x.col(c) - sim.true_delta_x.col(c);
      for (int k = 0; k < mon.NumPoints(); ++k) {
        const Eigen::Vector3d e = mon.Jacobian(k) * dx;
        for (int a = 0; a < 3; ++a) {
          sum_z2 += std::pow(e[a] / sigma[3 * k + a], 2);
          ++count;
        }
      }
    }
  }
  const double rms_z = std::sqrt(sum_z2 / count);
  ::testing::Test::RecordProperty("rms_z", std::to_string(rms_z));
  EXPECT_NEAR(rms_z, 1.0, 0.1) << count << " values";
}

}  // namespace
}  // namespace ramtk::thermal
