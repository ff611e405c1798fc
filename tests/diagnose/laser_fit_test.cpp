// The laser diagnosis' least-squares fit (diagnose/laser/src/laser_fit.h, Ceres Levenberg–Marquardt with
// central-difference Jacobians and ceres::Covariance): against the normal equations of a linear
// model, with fixed parameters and masked rows, and its sigma against a Monte-Carlo re-solve of a
// non-linear circle fit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>

#include "ramtk/diagnose/laser/detail/laser_fit.h"

namespace ramtk::diagnose::laser_detail {
namespace {

TEST(LaserFit, LinearModelGivesTheNormalEquationsSolutionAndSigma) {
  // y = a + b t + c t^2 with noise; c held at its start value 0.3 (not free); rows 3 and 7 masked.
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.05);
  const int n = 40;
  Eigen::VectorXd t(n), y(n);
  for (int i = 0; i < n; ++i) {
    t(i) = -2.0 + 4.0 * i / (n - 1);
    y(i) = 1.5 - 0.7 * t(i) + 0.3 * t(i) * t(i) + noise(rng);
  }
  ResidualModel m;
  m.names = {"a", "b", "c"};
  m.initial = Eigen::Vector3d(0.0, 0.0, 0.3);
  m.step = Eigen::Vector3d::Constant(1e-4);
  m.residuals = [&](const Eigen::VectorXd& p) -> Eigen::VectorXd {
    return (p(0) + p(1) * t.array() + p(2) * t.array().square() - y.array()).matrix();
  };
  std::vector<bool> use(n, true);
  use[3] = use[7] = false;
  const FitResult f = Fit(m, {0, 1}, use, m.initial);
  ASSERT_TRUE(f.ok);
  // The normal equations on the used rows, with c fixed.
  Eigen::MatrixXd a(n - 2, 2);
  Eigen::VectorXd b(n - 2);
  for (int i = 0, k = 0; i < n; ++i) {
    if (!use[i]) continue;
    a(k, 0) = 1.0, a(k, 1) = t(i);
    b(k++) = y(i) - 0.3 * t(i) * t(i);
  }
  const Eigen::Vector2d x = (a.transpose() * a).ldlt().solve(a.transpose() * b);
  const double s2 = (a * x - b).squaredNorm() / (n - 2 - 2);
  const Eigen::Matrix2d cov = (a.transpose() * a).inverse() * s2;
  // The solver stops at a relative cost change of 1e-12: the parameters are then within
  // sqrt(1e-12 cost / lambda_min(A^T A)) ~ 1e-8 of the minimum, far inside 1e-4 of their sigma.
  EXPECT_NEAR(f.params(0), x(0), 1e-4 * std::sqrt(cov(0, 0)));
  EXPECT_NEAR(f.params(1), x(1), 1e-4 * std::sqrt(cov(1, 1)));
  EXPECT_EQ(f.params(2), 0.3);  // fixed
  EXPECT_NEAR(f.sigma(0), std::sqrt(cov(0, 0)), 1e-6 * std::sqrt(cov(0, 0)));
  EXPECT_NEAR(f.sigma(1), std::sqrt(cov(1, 1)), 1e-6 * std::sqrt(cov(1, 1)));
  EXPECT_EQ(f.sigma(2), 0.0);
  EXPECT_NEAR(f.rms, std::sqrt((a * x - b).squaredNorm() / (n - 2)), 1e-9);
}

TEST(LaserFit, CircleSigmaMatchesMonteCarloScatter) {
  // A 100 mm circle seen over 120 deg of arc with 0.02 mm radial noise: centre and radius are
  // non-linear in the data and correlated; the predicted sigma must match the scatter of 400
  // re-solves (an observed sd from 400 draws is itself uncertain by ~3.5 %: 15 % bound).
  const double cx = 3.0, cy = -2.0, radius = 100.0, sd = 0.02;
  const int n = 60, draws = 400;
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, sd);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum2 = Eigen::Vector3d::Zero(), predicted = Eigen::Vector3d::Zero();
  for (int d = 0; d < draws; ++d) {
    Eigen::MatrixXd pts(n, 2);
    for (int i = 0; i < n; ++i) {
      const double a = (-60.0 + 120.0 * i / (n - 1)) * M_PI / 180.0;
      const double r = radius + noise(rng);
      pts(i, 0) = cx + r * std::cos(a), pts(i, 1) = cy + r * std::sin(a);
    }
    ResidualModel m;
    m.names = {"cx", "cy", "r"};
    m.initial = Eigen::Vector3d(0.0, 0.0, 90.0);
    m.step = Eigen::Vector3d::Constant(1e-5);
    m.residuals = [&pts](const Eigen::VectorXd& p) -> Eigen::VectorXd {
      return ((pts.rowwise() - Eigen::RowVector2d(p(0), p(1))).rowwise().norm().array() - p(2)).matrix();
    };
    const FitResult f = Fit(m, {0, 1, 2}, std::vector<bool>(n, true), m.initial);
    ASSERT_TRUE(f.ok);
    const Eigen::Vector3d e = f.params - Eigen::Vector3d(cx, cy, radius);
    sum += e, sum2 += e.cwiseAbs2(), predicted += f.sigma;
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = sum(k) / draws;
    const double observed = std::sqrt(sum2(k) / draws - mean * mean);
    const double pred = predicted(k) / draws;
    std::cout << "parameter " << k << ": predicted/observed sigma " << pred / observed << "\n";
    EXPECT_NEAR(pred / observed, 1.0, 0.15) << "parameter " << k << ": predicted " << pred << ", observed " << observed;
    EXPECT_LT(std::abs(mean), 4 * observed / std::sqrt(draws));  // unbiased at this noise
  }
}

TEST(LaserFit, AnUnconstrainedDirectionHasNoSigma) {
  // Two parameters that enter only as their sum: the rows cannot separate them.
  ResidualModel m;
  m.names = {"u", "v"};
  m.initial = Eigen::Vector2d(0.0, 0.0);
  m.step = Eigen::Vector2d::Constant(1e-4);
  m.residuals = [](const Eigen::VectorXd& p) -> Eigen::VectorXd {
    Eigen::VectorXd r(5);
    for (int i = 0; i < 5; ++i) r(i) = p(0) + p(1) - (1.0 + 0.01 * (i % 2));
    return r;
  };
  const FitResult f = Fit(m, {0, 1}, std::vector<bool>(5, true), m.initial);
  EXPECT_NEAR(f.params(0) + f.params(1), 1.004, 1e-9);  // the mean of 1, 1.01, 1, 1.01, 1
  EXPECT_TRUE(std::isnan(f.sigma(0)));
  EXPECT_TRUE(std::isnan(f.sigma(1)));
}

}  // namespace
}  // namespace ramtk::diagnose::laser_detail
