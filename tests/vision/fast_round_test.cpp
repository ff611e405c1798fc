// The rounding helpers of the per-pixel loops (vision/kernels/include/ramtk/vision/kernels/fast_round.h) against the standard
// functions they replace: the same value, bit for bit, on edge cases and on random values.
#include "ramtk/vision/kernels/fast_round.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace ramtk::vision::detail {
namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<double> EdgeCases() {
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::vector<double> v = {0.0,
                           -0.0,
                           tiny,
                           -tiny,
                           0.5,
                           -0.5,
                           1.5,
                           -1.5,
                           2.5,
                           -2.5,
                           0.49999999999999994,
                           -0.49999999999999994,
                           1.0 - 1e-16,
                           -(1.0 - 1e-16),
                           1e9 - 0.5,
                           -1e9 + 0.5,
                           4503599627370495.5,
                           -4503599627370495.5,
                           4503599627370496.0,
                           9007199254740993.0,
                           1e300,
                           -1e300};
  for (int k = -40; k <= 40; ++k) v.push_back(k * 0.25);
  return v;
}

// The edge cases and 200 000 random values, half within +-`wide`, half within +-`narrow`.
std::vector<double> TestValues(unsigned seed, double wide, double narrow) {
  std::vector<double> values = EdgeCases();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> w(-wide, wide), n(-narrow, narrow);
  for (int i = 0; i < 200000; ++i) values.push_back(i % 2 ? w(rng) : n(rng));
  return values;
}

TEST(FastRound, FloorEqualsStdFloorBitForBit) {
  std::vector<double> values = TestValues(7, 1e6, 3);
  values.push_back(std::numeric_limits<double>::infinity());
  values.push_back(-std::numeric_limits<double>::infinity());
  for (const double v : values) EXPECT_TRUE(SameBits(Floor(v), std::floor(v))) << v;
  EXPECT_TRUE(std::isnan(Floor(std::numeric_limits<double>::quiet_NaN())));
}

TEST(FastRound, FloorToIntEqualsTheFloorInItsRange) {
  for (const double v : TestValues(8, 9e8, 70)) {
    if (!(std::abs(v) < 1e9)) {
      EXPECT_LT(FloorToInt(v), -1000000) << v;  // no image index
      continue;
    }
    EXPECT_EQ(FloorToInt(v), static_cast<int>(std::floor(v))) << v;
  }
  EXPECT_LT(FloorToInt(std::numeric_limits<double>::quiet_NaN()), -1000000);
  for (int a = -100; a <= 100; ++a)
    for (const int b : {1, 3, 8, 64}) EXPECT_EQ(FloorDiv(a, b), static_cast<int>(std::floor(double(a) / b)));
}

TEST(FastRound, LRoundEqualsStdLround) {
  for (const double v : TestValues(9, 1e12, 70)) {
    if (std::abs(v) < 4503599627370496.0) {
      EXPECT_EQ(LRound(v), std::lround(v)) << v;
    }
  }
}

TEST(FastRound, PeriodFractionIsTheWrappedFractionInZeroOne) {
  // t - floor(t) with t = (phi - origin) / 2 pi, as the std::floor form computes it.
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> phi(-4 * M_PI, 4 * M_PI);
  for (int i = 0; i < 100000; ++i) {
    const double p = phi(rng), origin = i % 3 == 0 ? -M_PI : 0.25;
    const double t = (p - origin) / 6.283185307179586476925;
    const double f = PeriodFractionOf(p, origin);
    EXPECT_TRUE(SameBits(f, t - std::floor(t))) << p;
    EXPECT_GE(f, 0.0);
    EXPECT_LT(f, 1.0);
  }
}

}  // namespace
}  // namespace ramtk::vision::detail
