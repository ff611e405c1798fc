// The drift identified in time (each centre at its own instant, piecewise linear between the
// cycles' mean pose times) against the simulator's true drift at those instants, with the drift
// moving inside every cycle as the simulator makes it; and against the per-cycle solve where the
// two models coincide.
#include "ramtk/thermal/drift_in_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/kinematics/measurements_io.h"
#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using testing::Kr150;

// The campaign twin's experiment: 4 cycles 30 min apart over the warm-up, 8 ball poses measured
// one after another over 13 min of each cycle, no noise (the tests add it).
ThermalSimOptions CampaignLike(std::uint64_t seed) {
  ThermalSimOptions o = ThesisPreset(seed);
  o.cycles = 4;
  o.cycle_period_s = 1800.0;
  o.ball_poses = 8;
  o.monitoring_points = 8;
  o.sensor_field_mm = Vec3(240.0, 180.0, 100.0);
  o.sensor_noise_mm = o.tool_sensor_noise_mm = o.repeatability_mm = 0.0;
  return o;
}

constexpr double kCentreSigmaMm = 0.004;  // per axis, the twin's scan σ at 160×128 px
constexpr double kRobotNoiseMm = 0.015;   // repeatability σ per axis

// The ball rows with the scan covariance kCentreSigmaMm²·I in their cov columns, and (with rng)
// the centre noise plus the repeatability drawn onto their positions.
kinematics::RobotMeasurementSet WithNoise(const kinematics::RobotMeasurementSet& clean, std::mt19937_64* rng) {
  kinematics::RobotMeasurementSet set = clean;
  kinematics::AddCentreCovarianceColumns(&set);
  std::normal_distribution<double> n01;
  const double sigma = std::hypot(kCentreSigmaMm, kRobotNoiseMm);
  for (auto& row : set.rows) {
    kinematics::SetCentreCovariance(kCentreSigmaMm * kCentreSigmaMm * Mat3::Identity(), &row);
    if (rng != nullptr) row.position_mm += sigma * Vec3(n01(*rng), n01(*rng), n01(*rng));
  }
  return set;
}

// True D(T_c) = X(T_c) − X(T_0) at the series' cycle times.
Eigen::MatrixXd TrueDrift(const ThermalSimOptions& o, const CycleSeries& series) {
  Eigen::MatrixXd x(kinematics::kNumParams, series.NumCycles());
  const kinematics::ParamVector x0 = TrueDriftAt(o, series.cycles[0].time_s);
  for (int c = 0; c < series.NumCycles(); ++c) x.col(c) = TrueDriftAt(o, series.cycles[c].time_s) - x0;
  return x;
}

TEST(DriftInTime, OneDeltaXPerCycleOnTwoCyclesEqualsTheWeightedPerCycleSolve) {
  ThermalSimOptions o = CampaignLike(2);
  o.cycles = 2;
  const ThermalSimResult sim = SimulateThermal(Kr150(), o);
  std::mt19937_64 rng(5);
  const CycleSeries series = GroupCycles(WithNoise(sim.ball, &rng), "ball.csv");
  const DriftModel dm(Kr150(), sim.setup, series.taught);
  IdentificationOptions id;
  id.params = sim.drifting_params;
  id.difference_covariance_mm2 = series.DifferenceCovariances(kRobotNoiseMm);
  const Eigen::MatrixXd per_cycle = dm.Solve(series.DifferencesFromReference(), id);
  const Eigen::MatrixXd per_cycle_cov = dm.WeightedCovariances(id).at(1);
  DriftInTimeOptions to;
  to.params = sim.drifting_params;
  to.robot_noise_mm = kRobotNoiseMm;
  to.model = DriftTimeModel::kConstantPerCycle;
  const DriftInTimeResult r = IdentifyDriftInTime(dm, series, to);
  EXPECT_TRUE(r.weighted);
  EXPECT_EQ(r.residual_dof, 3 * 8 - 8);
  for (std::size_t j = 0; j < to.params.size(); ++j) {
    const int p = to.params[j];
    const double sigma = std::sqrt(per_cycle_cov(j, j));
    EXPECT_NEAR(r.delta_x(p, 1), per_cycle(p, 1), 1e-6 * sigma) << kinematics::ParamName(p);
    for (std::size_t i = 0; i < to.params.size(); ++i)
      EXPECT_NEAR(r.covariance[1](i, j), per_cycle_cov(i, j), 1e-6 * per_cycle_cov.diagonal().maxCoeff());
  }
}

// Noise-free centres with the drift moving inside every cycle (10 pose sets): what is left of each
// parameter's error is the model's own, in units of its σ under the twin's noise. One ΔX per
// cycle leaves a bias of the order of σ on the wrist tilt α4 (its time constant is the shortest,
// and the cold cycle is measured while it moves fastest); the drift in time leaves a small
// fraction of σ on every parameter.
TEST(DriftInTime, HiddenWithinCycleDriftLeavesNoBiasBeyondAFractionOfSigma) {
  double worst_timed = 0.0, alpha4_per_cycle2 = 0.0, alpha4_per_cycle_worst = 0.0;
  int alpha4_terms = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const ThermalSimOptions o = CampaignLike(seed);
    const ThermalSimResult sim = SimulateThermal(Kr150(), o);
    const CycleSeries series = GroupCycles(WithNoise(sim.ball, nullptr), "ball.csv");
    const DriftModel dm(Kr150(), sim.setup, series.taught);
    const Eigen::MatrixXd truth = TrueDrift(o, series);
    DriftInTimeOptions to;
    to.params = sim.drifting_params;
    to.robot_noise_mm = kRobotNoiseMm;
    const DriftInTimeResult timed = IdentifyDriftInTime(dm, series, to);
    IdentificationOptions id;
    id.params = sim.drifting_params;
    id.difference_covariance_mm2 = series.DifferenceCovariances(kRobotNoiseMm);
    const Eigen::MatrixXd per_cycle = dm.Solve(series.DifferencesFromReference(), id);
    const std::vector<Eigen::MatrixXd> per_cycle_cov = dm.WeightedCovariances(id);
    for (int c = 1; c < o.cycles; ++c) {
      EXPECT_NEAR(timed.time_s[c], sim.truth_time_s[c], 1e-9);
      for (std::size_t j = 0; j < to.params.size(); ++j) {
        const int p = to.params[j];
        const double z = (timed.delta_x(p, c) - truth(p, c)) / std::sqrt(timed.covariance[c](j, j));
        worst_timed = std::max(worst_timed, std::abs(z));
        if (p == kinematics::ParamIndex(kinematics::ParamKind::kAlpha, 3)) {
          const double zc = (per_cycle(p, c) - truth(p, c)) / std::sqrt(per_cycle_cov[c](j, j));
          alpha4_per_cycle2 += zc * zc;
          alpha4_per_cycle_worst = std::max(alpha4_per_cycle_worst, std::abs(zc));
          ++alpha4_terms;
        }
      }
    }
  }
  ::testing::Test::RecordProperty("worst_timed_bias_sigma", std::to_string(worst_timed));
  ::testing::Test::RecordProperty("alpha4_per_cycle_rms_bias_sigma",
                                  std::to_string(std::sqrt(alpha4_per_cycle2 / alpha4_terms)));
  // Measured: the drift in time 0.18 σ at worst over the 8 parameters; one ΔX per cycle 0.53 σ
  // RMS on α4, 1.40 σ at worst (seed 10, last cycle).
  EXPECT_LT(worst_timed, 0.25);
  EXPECT_GT(std::sqrt(alpha4_per_cycle2 / alpha4_terms), 0.4);
  EXPECT_GT(alpha4_per_cycle_worst, 1.0);
}

// The covariance the joint solve returns against the scatter of its estimates over noise draws,
// the drift moving inside every cycle: RMS of (error / σ) per parameter over 300 draws × 3 warm
// cycles. An RMS of 900 unit normals is uncertain by ~2.4 %; the model error above adds < 5 %.
TEST(DriftInTime, ErrorOverNoiseDrawsMatchesItsCovariance) {
  const ThermalSimOptions o = CampaignLike(3);
  const ThermalSimResult sim = SimulateThermal(Kr150(), o);
  const CycleSeries clean = GroupCycles(sim.ball, "ball.csv");
  const DriftModel dm(Kr150(), sim.setup, clean.taught);
  const Eigen::MatrixXd truth = TrueDrift(o, clean);
  DriftInTimeOptions to;
  to.params = sim.drifting_params;
  to.robot_noise_mm = kRobotNoiseMm;
  const int k = static_cast<int>(to.params.size());
  Eigen::VectorXd z2 = Eigen::VectorXd::Zero(k);
  double chi2 = 0.0;
  std::mt19937_64 rng(11);
  const int draws = 300;
  for (int d = 0; d < draws; ++d) {
    const CycleSeries series = GroupCycles(WithNoise(sim.ball, &rng), "ball.csv");
    const DriftInTimeResult r = IdentifyDriftInTime(dm, series, to);
    chi2 += r.reduced_chi2;
    for (int c = 1; c < o.cycles; ++c)
      for (int j = 0; j < k; ++j)
        z2[j] += std::pow(r.delta_x(to.params[j], c) - truth(to.params[j], c), 2) / r.covariance[c](j, j);
  }
  for (int j = 0; j < k; ++j) {
    const double rms = std::sqrt(z2[j] / (draws * (o.cycles - 1)));
    EXPECT_GT(rms, 0.9) << kinematics::ParamName(to.params[j]);
    EXPECT_LT(rms, 1.1) << kinematics::ParamName(to.params[j]);
  }
  EXPECT_NEAR(chi2 / draws, 1.0, 0.05);
}

// The cubic interpolant reproduces a drift quadratic in time exactly, between knots and past the
// end knots, on unevenly spaced knots; the piecewise-linear one only at the knots.
TEST(DriftInTime, CubicInterpolationReproducesAQuadraticInTime) {
  auto quadratic = [](double t) { return 0.3 - 2e-3 * t + 4e-6 * t * t; };
  DriftInTimeResult r;
  r.time_s = {100.0, 1000.0, 1500.0, 3100.0};
  r.delta_x = Eigen::MatrixXd::Zero(kinematics::kNumParams, 4);
  for (int c = 0; c < 4; ++c) r.delta_x(7, c) = quadratic(r.time_s[c]);
  for (double t : {-200.0, 100.0, 400.0, 1200.0, 2000.0, 3100.0, 3500.0})
    EXPECT_NEAR(r.At(t)[7], quadratic(t), 1e-9 * (1.0 + std::abs(quadratic(t)))) << t;
  r.model = DriftTimeModel::kPiecewiseLinear;
  EXPECT_NEAR(r.At(1500.0)[7], quadratic(1500.0), 1e-12);
  EXPECT_GT(std::abs(r.At(2000.0)[7] - quadratic(2000.0)), 0.1);
}

TEST(DriftInTime, RefusesASingleCycleAndMissingTimes) {
  ThermalSimOptions o = CampaignLike(1);
  o.cycles = 2;
  const ThermalSimResult sim = SimulateThermal(Kr150(), o);
  CycleSeries series = GroupCycles(sim.ball, "ball.csv");
  const DriftModel dm(Kr150(), sim.setup, series.taught);
  DriftInTimeOptions to;
  to.params = sim.drifting_params;
  CycleSeries one = series;
  one.cycles.resize(1);
  EXPECT_THROW(IdentifyDriftInTime(dm, one, to), InputError);
  CycleSeries same_time = series;
  same_time.cycles[1].time_s = same_time.cycles[0].time_s;
  EXPECT_THROW(IdentifyDriftInTime(dm, same_time, to), InputError);
  series.cycles[1].pose_time_s.clear();
  EXPECT_THROW(IdentifyDriftInTime(dm, series, to), InputError);
}

}  // namespace
}  // namespace ramtk::thermal
