// The decode's branch-free atan2 (vision/kernels/include/ramtk/vision/kernels/fast_atan2.h) against std::atan2: within 1e-11 rad
// over random pairs of every sign and magnitude ratio, exact on the axes and diagonals and with
// IEEE's signed zeros, and rounded to float it is the correctly rounded phase.
#include "ramtk/vision/kernels/fast_atan2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace {

using ramtk::vision::detail::Atan2;

TEST(FastAtan2, WithinTenPicoradiansOfTheLibrary) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_radius(-20, 20);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const double a = angle(rng), r = std::exp(log_radius(rng));
    const double y = r * std::sin(a), x = r * std::cos(a);
    const double err = std::abs(Atan2(y, x) - std::atan2(y, x));
    worst = std::max(worst, err);
    ASSERT_LE(err, 1e-11) << "y " << y << " x " << x;
  }
  std::cout << "worst |Atan2 - std::atan2| " << worst << " rad\n";
}

TEST(FastAtan2, AxesDiagonalsAndSignedZerosAsIeee) {
  const double z = 0.0;
  for (const double y : {0.0, -0.0, 1.0, -1.0, 3.5, -2e-30, 7e30})
    for (const double x : {0.0, -0.0, 1.0, -1.0, 3.5, -2e-30, 7e30}) {
      const double want = std::atan2(y, x), got = Atan2(y, x);
      EXPECT_NEAR(got, want, 1e-15) << "y " << y << " x " << x;
      EXPECT_EQ(std::signbit(got), std::signbit(want)) << "y " << y << " x " << x;
    }
  EXPECT_EQ(Atan2(z, -z), M_PI);
  EXPECT_EQ(Atan2(-z, -z), -M_PI);
}

// Rounded to float, as the decode stores the phase: the correctly rounded value (std::atan2 in
// double, rounded) but for the rare pair within 1e-11 rad of a rounding boundary, and within one
// ulp of glibc's atan2f, which the decode used before (atan2f itself is correctly rounded for
// ~84 % of these pairs).
TEST(FastAtan2, RoundedToFloatIsTheCorrectlyRoundedPhase) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> v(-255.0f * 12, 255.0f * 12);  // the decode's S and C sums
  long not_rounded = 0, from_atan2f = 0;
  for (int i = 0; i < 1000000; ++i) {
    const float s = v(rng), c = v(rng);
    const float truth = static_cast<float>(std::atan2(-static_cast<double>(s), static_cast<double>(c)));
    const float got = static_cast<float>(Atan2(-static_cast<double>(s), c)), old = std::atan2(-s, c);
    const float ulp = std::nextafter(std::abs(truth), 4.0f) - std::abs(truth);
    ASSERT_LE(std::abs(got - truth), ulp) << "s " << s << " c " << c;
    ASSERT_LE(std::abs(got - old), ulp) << "s " << s << " c " << c;
    not_rounded += got != truth;
    from_atan2f += got != old;
  }
  std::cout << not_rounded << " of 1000000 not correctly rounded; " << from_atan2f << " differ from atan2f\n";
  EXPECT_LE(not_rounded, 10);
}

#if CV_SIMD128_64F
// The two-lane version gives each lane exactly the scalar result (the decode's wrapped phase is
// then the same bit for bit): random pairs of every sign and magnitude ratio, the axes, the
// diagonals, signed zeros, infinities and NaN.
TEST(FastAtan2, TwoLanesAreBitIdenticalToTheScalarVersion) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_radius(-20, 20);
  std::vector<std::pair<double, double>> pairs;
  for (int i = 0; i < 200000; ++i) {
    const double a = angle(rng), r = std::exp(log_radius(rng));
    pairs.emplace_back(r * std::sin(a), r * std::cos(a));
  }
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const double y : {0.0, -0.0, 1.0, -1.0, 2.5, -2.5, inf, -inf, nan})
    for (const double x : {0.0, -0.0, 1.0, -1.0, 2.5, -2.5, inf, -inf, nan}) pairs.emplace_back(y, x);
  long differ = 0;
  for (std::size_t i = 0; i + 1 < pairs.size(); i += 2) {
    const cv::v_float64x2 y(pairs[i].first, pairs[i + 1].first), x(pairs[i].second, pairs[i + 1].second);
    double lanes[2];
    cv::v_store(lanes, ramtk::vision::detail::Atan2x2(y, x));
    for (int lane = 0; lane < 2; ++lane) {
      const double want = Atan2(pairs[i + lane].first, pairs[i + lane].second);
      differ += std::memcmp(&want, &lanes[lane], sizeof want) != 0;
    }
  }
  EXPECT_EQ(differ, 0);
}
#endif

}  // namespace
