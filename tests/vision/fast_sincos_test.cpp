// The nonlinearity basis's branch-free sin/cos (vision/kernels/include/ramtk/vision/kernels/fast_sincos.h) against std::sin and
// std::cos: within 2 ulp over the arguments the basis meets (N * phi, |N| <= 64, |phi| <= pi)
// and beyond, at quadrant boundaries, and by the identities sin^2 + cos^2 = 1 and odd/even symmetry.
#include "ramtk/vision/kernels/fast_sincos.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"

namespace {

using ramtk::vision::detail::SinCos;
#if CV_SIMD128_64F
using ramtk::vision::detail::SinCos2;
#endif

// Arguments for the lane tests: uniform over +-1, +-64 pi and +-1e6, the quadrant boundaries
// k pi / 4 and their neighbours 1e-12 away, and both zeros.
std::vector<double> LaneArguments(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> args;
  for (const double range : {1.0, 64 * M_PI, 1e6}) {
    std::uniform_real_distribution<double> u(-range, range);
    for (int i = 0; i < 100000; ++i) args.push_back(u(rng));
  }
  for (int k = -80; k <= 80; ++k)
    for (const double d : {-1e-12, 0.0, 1e-12}) args.push_back(k * M_PI / 4 + d);
  args.push_back(0.0);
  args.push_back(-0.0);
  return args;
}

// Distance in units of the last place of the reference value (at least the ulp of 2^-1022 near 0).
double Ulps(double got, double want) {
  const double ulp = std::max(std::nextafter(std::abs(want), std::numeric_limits<double>::infinity()) - std::abs(want),
                              std::numeric_limits<double>::denorm_min());
  return std::abs(got - want) / ulp;
}

TEST(FastSinCos, WithinTwoUlpOfTheLibrary) {
  std::mt19937_64 rng(7);
  double worst_s = 0, worst_c = 0;
  for (const double range : {1.0, 10.0, 64 * M_PI, 1e4, 1e6}) {
    std::uniform_real_distribution<double> u(-range, range);
    for (int i = 0; i < 200000; ++i) {
      const double a = u(rng);
      double s, c;
      SinCos(a, &s, &c);
      // Near a zero of the function the absolute error is the meaningful one: compare to the
      // ulp of 1 there (the basis is stored as float, ~1e-7 absolute).
      const double es = std::abs(std::sin(a)) < 1e-3 ? std::abs(s - std::sin(a)) / 2.2e-16 : Ulps(s, std::sin(a));
      const double ec = std::abs(std::cos(a)) < 1e-3 ? std::abs(c - std::cos(a)) / 2.2e-16 : Ulps(c, std::cos(a));
      worst_s = std::max(worst_s, es);
      worst_c = std::max(worst_c, ec);
    }
  }
  EXPECT_LE(worst_s, 2.0);
  EXPECT_LE(worst_c, 2.0);
}

TEST(FastSinCos, QuadrantBoundariesAndIdentities) {
  for (int k = -80; k <= 80; ++k) {
    for (const double d : {-1e-9, 0.0, 1e-9, 0.3, -0.7}) {
      const double a = k * M_PI / 4 + d;
      double s, c, sn, cn;
      SinCos(a, &s, &c);
      SinCos(-a, &sn, &cn);
      EXPECT_NEAR(s, std::sin(a), 4e-16) << a;
      EXPECT_NEAR(c, std::cos(a), 4e-16) << a;
      EXPECT_NEAR(s * s + c * c, 1.0, 4e-16) << a;
      EXPECT_EQ(sn, -s) << a;  // odd
      EXPECT_EQ(cn, c) << a;   // even
    }
  }
}

#if CV_SIMD128_64F
// The two-lane version gives each lane exactly the scalar result (the basis is then the same
// bit for bit), over the basis's arguments, beyond them and at the quadrant boundaries.
TEST(FastSinCos, TwoLanesAreBitIdenticalToTheScalarVersion) {
  const std::vector<double> args = LaneArguments(11);
  long differ = 0;
  for (std::size_t i = 0; i + 1 < args.size(); i += 2) {
    cv::v_float64x2 s, c;
    SinCos2(cv::v_float64x2(args[i], args[i + 1]), &s, &c);
    double sv[2], cv_[2];
    cv::v_store(sv, s);
    cv::v_store(cv_, c);
    for (int lane = 0; lane < 2; ++lane) {
      double ss, cc;
      SinCos(args[i + lane], &ss, &cc);
      differ += std::memcmp(&ss, &sv[lane], sizeof ss) != 0 || std::memcmp(&cc, &cv_[lane], sizeof cc) != 0;
    }
  }
  EXPECT_EQ(differ, 0);
}
#endif

// SinCos4's four lanes against the scalar version on the same arguments (AVX2 CPUs only).
__attribute__((target("avx2"))) long FourLaneDifferences(const std::vector<double>& args) {
  long differ = 0;
  for (std::size_t i = 0; i + 3 < args.size(); i += 4) {
    __m256d s, c;
    ramtk::vision::detail::SinCos4(_mm256_loadu_pd(args.data() + i), &s, &c);
    double sv[4], cv4[4];
    _mm256_storeu_pd(sv, s);
    _mm256_storeu_pd(cv4, c);
    for (int lane = 0; lane < 4; ++lane) {
      double ss, cc;
      SinCos(args[i + lane], &ss, &cc);
      differ += std::memcmp(&ss, &sv[lane], sizeof ss) != 0 || std::memcmp(&cc, &cv4[lane], sizeof cc) != 0;
    }
  }
  return differ;
}

TEST(FastSinCos, FourLanesAreBitIdenticalToTheScalarVersion) {
  if (!ramtk::vision::detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  const std::vector<double> args = LaneArguments(12);
  EXPECT_EQ(FourLaneDifferences(args), 0);
}

}  // namespace
