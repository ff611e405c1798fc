#include "ramtk/diagnose/engine/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ramtk::diagnose {
namespace {

std::vector<double> Gaussian(int n, double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<double> out(n);
  for (double& v : out) v = normal(rng);
  return out;
}

TEST(Statistics, ChiSquareTailMatchesClosedForms) {
  // dof 2: P(X ≥ x) = exp(−x/2); dof 1: P(X ≥ z²) = 2·P(Z ≥ z).
  for (double x : {0.1, 1.0, 4.0, 13.8155}) EXPECT_NEAR(ChiSquareUpperTail(x, 2), std::exp(-x / 2), 1e-14);
  for (double z : {0.5, 1.96, 3.0}) EXPECT_NEAR(ChiSquareUpperTail(z * z, 1), 2 * NormalUpperTail(z), 1e-14);
  EXPECT_NEAR(NormalUpperTail(1.959963984540054), 0.025, 1e-15);
}

TEST(Statistics, VarianceTestFalseAlarmRateMatchesAlpha) {
  // 400 white residual sets at the stated σ: the share with p < 0.01 is binomial(400, 0.01);
  // mean 4, standard deviation ≈ 2, so more than 12 would be a 4σ event.
  int alarms = 0;
  for (unsigned seed = 1; seed <= 400; ++seed) alarms += VarianceTest(Gaussian(200, 0.02, seed), {0.02}).p_value < 0.01;
  EXPECT_LE(alarms, 12);
}

TEST(Statistics, VarianceTestDetectsExcess) {
  // 20% more noise than stated over 2000 residuals: χ² ≈ 2880 on 2000 dof, z ≈ 14.
  EXPECT_LT(VarianceTest(Gaussian(2000, 0.024, 7), {0.02}).p_value, 1e-12);
}

TEST(Statistics, LjungBoxSeesSerialCorrelation) {
  std::vector<double> ar = Gaussian(500, 1.0, 3);
  for (size_t i = 1; i < ar.size(); ++i) ar[i] += 0.5 * ar[i - 1];
  EXPECT_LT(LjungBoxTest(ar, 10, "t").p_value, 1e-10);
  int alarms = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) alarms += LjungBoxTest(Gaussian(300, 1.0, seed), 10, "t").p_value < 0.01;
  EXPECT_LE(alarms, 9);  // binomial(200, 0.01): mean 2, sd 1.4
}

TEST(Statistics, AutocorrelationOfAlternatingSeriesIsMinusOne) {
  std::vector<double> s(100);
  for (size_t i = 0; i < s.size(); ++i) s[i] = (i % 2) ? 1.0 : -1.0;
  const auto acf = Autocorrelation(s, 2);
  EXPECT_DOUBLE_EQ(acf[0], 1.0);
  EXPECT_NEAR(acf[1], -0.99, 1e-12);  // (n−1)/n for the biased estimator
  EXPECT_NEAR(acf[2], 0.98, 1e-12);
}

TEST(Statistics, TrendTestExplainedSumOfSquaresIsExactForALine) {
  // Residual exactly r = s·x on a symmetric grid: the line explains Σ(s·x/σ)² beyond the constant.
  std::vector<double> x, r;
  const double slope = 0.003, sigma = 0.01;
  double expected = 0.0;
  for (int i = -50; i <= 50; ++i) {
    x.push_back(i * 0.1);
    r.push_back(slope * i * 0.1);
    expected += std::pow(slope * i * 0.1 / sigma, 2);
  }
  const TestResult t = TrendTest(r, {sigma}, x, 1, "x");
  EXPECT_NEAR(t.statistic, expected, 1e-9 * expected);
  EXPECT_EQ(t.dof, 1);
  // Noise alone: no trend at the 1e-3 level in 100 of 100 draws is expected ~90% of the time;
  // count alarms at p < 0.01 (binomial(100, 0.01)).
  int alarms = 0;
  for (unsigned seed = 1; seed <= 100; ++seed)
    alarms += TrendTest(Gaussian(101, sigma, seed), {sigma}, x, 2, "x").p_value < 0.01;
  EXPECT_LE(alarms, 6);
}

TEST(Statistics, HolmCorrectionMatchesHandComputedExample) {
  // Sorted p: 0.01 (×4), 0.02 (×3), 0.03 (×2), 0.5 (×1), kept monotone.
  const std::vector<double> corrected = HolmCorrection({0.03, 0.01, 0.5, 0.02});
  EXPECT_DOUBLE_EQ(corrected[1], 0.04);
  EXPECT_DOUBLE_EQ(corrected[3], 0.06);
  EXPECT_DOUBLE_EQ(corrected[0], 0.06);
  EXPECT_DOUBLE_EQ(corrected[2], 0.5);
}

TEST(Statistics, BadSigmaIsRejected) {
  EXPECT_THROW(VarianceTest({1, 2, 3}, {1, 2}), std::invalid_argument);
  EXPECT_THROW(VarianceTest({1, 2, 3}, {0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace ramtk::diagnose
