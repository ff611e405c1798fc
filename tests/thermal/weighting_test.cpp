// Covariance weighting of the drift identification: centre noise that varies across the sensor's
// field (10× larger at its edge, 3× along the line of sight), weighted vs unweighted, against the
// simulator's true drift over noise seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/thermal/identify.h"
#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using testing::Kr150;

TEST(ThermalWeighting, CovarianceWeightingBeatsUnweightedWhenNoiseVariesAcrossTheField) {
  ThermalSimOptions o = ThesisPreset(4);
  o.cycles = 30;
  o.sensor_noise_mm = o.tool_sensor_noise_mm = o.repeatability_mm = 0.0;
  o.drift_changes_within_cycle = false;
  const ThermalSimResult r = SimulateThermal(Kr150(), o);
  // Field centre and radius from the (noise-free) cold cycle.
  Vec3 centre = Vec3::Zero();
  int n0 = 0;
  for (const auto& row : r.ball.rows) {
    if (row.cycle == 0) {
      centre += row.position_mm;
      ++n0;
    }
  }
  centre /= n0;
  double radius = 0.0;
  for (const auto& row : r.ball.rows) radius = std::max(radius, (row.position_mm - centre).norm());

  const std::vector<int>& params = r.drifting_params;
  std::vector<double> sq_w(params.size(), 0.0), sq_u(params.size(), 0.0);
  const int seeds = 8;
  for (int seed = 1; seed <= seeds; ++seed) {
    kinematics::RobotMeasurementSet set = r.ball;
    kinematics::AddCentreCovarianceColumns(&set);
    std::mt19937_64 rng(100 + seed);
    std::normal_distribution<double> n01;
    for (auto& row : set.rows) {
      const double u = (row.position_mm - centre).norm() / radius;
      const double s = 0.002 * (1.0 + 9.0 * u * u);
      const Mat3 cov = Vec3(s * s, s * s, 9.0 * s * s).asDiagonal();
      kinematics::SetCentreCovariance(cov, &row);
      row.position_mm += cov.llt().matrixL() * Vec3(n01(rng), n01(rng), n01(rng));
    }
    const CycleSeries ball = GroupCycles(set, "ball.csv");
    ASSERT_TRUE(ball.has_covariance);
    IdentificationOptions plain;
    plain.params = params;
    IdentificationOptions weighted = plain;
    weighted.difference_covariance_mm2 = ball.DifferenceCovariances();
    IdentificationSummary sw, su;
    const Eigen::MatrixXd xw = IdentifyCycles(Kr150(), r.setup, ball, weighted, &sw);
    const Eigen::MatrixXd xu = IdentifyCycles(Kr150(), r.setup, ball, plain, &su);
    EXPECT_TRUE(sw.weighted);
    EXPECT_FALSE(su.weighted);
    EXPECT_NE(sw.BriefReport().find("weighted by its covariance"), std::string::npos);
    for (std::size_t k = 0; k < params.size(); ++k) {
      for (int c = 1; c < o.cycles; ++c) {
        sq_w[k] += std::pow(xw(params[k], c) - r.true_delta_x(params[k], c), 2);
        sq_u[k] += std::pow(xu(params[k], c) - r.true_delta_x(params[k], c), 2);
      }
    }
  }
  // Generalised least squares (the best linear unbiased estimator under this noise) must cut the
  // error of every parameter, and by at least 1.5× in the geometric mean.
  double log_ratio = 0.0;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const double ratio = std::sqrt(sq_w[k] / sq_u[k]);
    EXPECT_LT(ratio, 1.0) << kinematics::ParamName(params[k]);
    ::testing::Test::RecordProperty("gain_" + kinematics::ParamName(params[k]), std::to_string(1.0 / ratio));
    log_ratio += std::log(ratio);
  }
  EXPECT_LT(std::exp(log_ratio / params.size()), 1.0 / 1.5);
}

TEST(ThermalWeighting, PredictedCovarianceMatchesMonteCarloScatter) {
  // Differences Y = A x + noise with a different covariance at every pose (as the scan gives):
  // the weighted solution's scatter over 400 draws against (A^T C^-1 A)^-1. An observed sd
  // from 400 draws is uncertain by ~3.5 %: 15 % bound.
  const auto& e = testing::Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  IdentificationOptions id;
  id.params = e.sim.drifting_params;
  const int poses = dm.NumPoses(), k = static_cast<int>(id.params.size());
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u(0.002, 0.02);
  std::vector<Mat3> blocks(poses);
  for (Mat3& c : blocks) {
    Mat3 l = Mat3::Zero();
    for (int i = 0; i < 3; ++i) {
      l(i, i) = u(rng);
      for (int j = 0; j < i; ++j) l(i, j) = 0.3 * u(rng);
    }
    c = l * l.transpose();
  }
  id.difference_covariance_mm2.assign(1, blocks);
  const Eigen::MatrixXd predicted = dm.WeightedCovariances(id).at(0);
  ASSERT_EQ(predicted.rows(), k);
  const int draws = 400;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(k), sum2 = Eigen::VectorXd::Zero(k);
  for (int d = 0; d < draws; ++d) {
    Eigen::MatrixXd y(3 * poses, 1);
    for (int p = 0; p < poses; ++p)
      y.block<3, 1>(3 * p, 0) = blocks[p].llt().matrixL() * Vec3(n01(rng), n01(rng), n01(rng));  // x = 0
    const Eigen::MatrixXd x = dm.Solve(y, id);
    for (int j = 0; j < k; ++j) sum(j) += x(id.params[j], 0), sum2(j) += std::pow(x(id.params[j], 0), 2);
  }
  for (int j = 0; j < k; ++j) {
    const double mean = sum(j) / draws;
    const double observed = std::sqrt(sum2(j) / draws - mean * mean);
    const double pred = std::sqrt(predicted(j, j));
    ::testing::Test::RecordProperty("ratio_" + kinematics::ParamName(id.params[j]), std::to_string(pred / observed));
    EXPECT_NEAR(pred / observed, 1.0, 0.15) << kinematics::ParamName(id.params[j]);
  }
  // Unweighted, with the same sigma everywhere, it is Covariance(options, sigma).
  IdentificationOptions flat = id;
  flat.difference_covariance_mm2.assign(1, std::vector<Mat3>(poses, 0.01 * 0.01 * Mat3::Identity()));
  const Eigen::MatrixXd a = dm.WeightedCovariances(flat).at(0), b = dm.Covariance(flat, 0.01);
  EXPECT_LT((a - b).norm(), 1e-9 * b.norm());
}

TEST(ThermalWeighting, MismatchedCovarianceIsAnInputError) {
  const auto& e = testing::Thesis(1);
  IdentificationOptions id;
  id.params = e.sim.drifting_params;
  id.difference_covariance_mm2.assign(3, std::vector<Mat3>(20, Mat3::Identity()));
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  EXPECT_THROW(dm.Solve(e.experiment.ball.DifferencesFromReference(), id), InputError);
}

}  // namespace
}  // namespace ramtk::thermal
