// The phase-domain coordinate filter against closed forms and Monte Carlo: exact on quadratic
// surfaces, its reported sigma equal to the scatter it leaves, the ripple not averaged away, and
// a depth step left alone.
#include "ramtk/vision/decode/coordinate_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A coordinate map: a quadratic surface (projector px) over a 160x120 image, sigma per pixel.
double Surface(int x, int y) { return 300.0 + 1.7 * x - 0.4 * y + 2e-3 * x * x - 1.5e-3 * x * y + 3e-3 * y * y; }

DecodedCamera MakeCamera(double sigma, unsigned seed, bool step = false) {
  DecodedCamera d;
  d.coordinate.create(120, 160, CV_32F);
  d.sigma_coordinate.create(120, 160, CV_32F);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const double offset = step && x >= 80 ? 40.0 : 0.0;  // a depth edge: the coordinate jumps
      d.coordinate.at<float>(y, x) = static_cast<float>(Surface(x, y) + offset + sigma * g(rng));
      d.sigma_coordinate.at<float>(y, x) = static_cast<float>(sigma);
    }
  d.summary.period_px = 32;
  return d;
}

// Largest |coordinate - truth(x, y)| over the finite pixels at least `border` from the edge, in
// projector px, or in units of each pixel's sigma with `per_sigma`.
template <typename Truth>
double WorstError(const DecodedCamera& d, Truth truth, int border, bool per_sigma) {
  double worst = 0;
  for (int y = border; y < d.coordinate.rows - border; ++y)
    for (int x = border; x < d.coordinate.cols - border; ++x) {
      const double c = d.coordinate.at<float>(y, x);
      if (!std::isfinite(c)) continue;
      const double e = std::abs(c - truth(x, y));
      worst = std::max(worst, per_sigma ? e / d.sigma_coordinate.at<float>(y, x) : e);
    }
  return worst;
}

TEST(CoordinateFilter, ExactOnAQuadraticSurfaceWithHoles) {
  DecodedCamera d = MakeCamera(0.0, 1);
  d.sigma_coordinate.setTo(0.05);
  // Holes: every 7th pixel of every 5th row invalid, so windows are partial too.
  for (int y = 0; y < 120; y += 5)
    for (int x = 0; x < 160; x += 7) d.coordinate.at<float>(y, x) = d.sigma_coordinate.at<float>(y, x) = kNaN;
  CoordinateFilterOptions o;
  o.radius_px = 2;
  const CoordinateFilterSummary s = FilterCoordinate(o, 0.0, &d);
  EXPECT_GT(s.filtered, 18000);
  const double worst = WorstError(d, Surface, 0, false);
  // A quadratic fit reproduces a quadratic: only float rounding of values ~600 px (6e-5 px).
  EXPECT_LT(worst, 2e-4);
}

TEST(CoordinateFilter, ThreeByThreeKernelMatchesItsClosedForm) {
  // The centre weights of a 3x3 quadratic fit are [-1 2 -1; 2 5 2; -1 2 -1] / 9: sigma shrinks by
  // sqrt(sum k^2) = sqrt(45) / 9.
  DecodedCamera d = MakeCamera(0.1, 2);
  CoordinateFilterOptions o;
  o.radius_px = 1;
  const CoordinateFilterSummary s = FilterCoordinate(o, 0.0, &d);
  EXPECT_NEAR(d.sigma_coordinate.at<float>(60, 80), 0.1 * std::sqrt(45.0) / 9.0, 1e-6);
  EXPECT_NEAR(s.median_sigma_ratio, std::sqrt(45.0) / 9.0, 1e-5);
}

TEST(CoordinateFilter, ReportedSigmaIsTheScatterItLeaves) {
  // Monte Carlo over the interior pixels of 8 noise draws: RMS(filtered − truth) / reported sigma.
  for (int radius : {1, 2, 3}) {
    double sum_sq = 0, sum_sigma_sq = 0, raw_sq = 0;
    long n = 0;
    for (unsigned seed = 10; seed < 18; ++seed) {
      DecodedCamera d = MakeCamera(0.08, seed);
      const cv::Mat raw = d.coordinate.clone();
      CoordinateFilterOptions o;
      o.radius_px = radius;
      FilterCoordinate(o, 0.0, &d);
      // Every 2R+1-th pixel, so the sampled errors are independent of each other.
      for (int y = 10; y < 110; y += 2 * radius + 1)
        for (int x = 10; x < 150; x += 2 * radius + 1) {
          sum_sq += std::pow(d.coordinate.at<float>(y, x) - Surface(x, y), 2);
          sum_sigma_sq += std::pow(d.sigma_coordinate.at<float>(y, x), 2);
          raw_sq += std::pow(raw.at<float>(y, x) - Surface(x, y), 2);
          ++n;
        }
    }
    const double ratio = std::sqrt(sum_sq / sum_sigma_sq);
    // n >= 1800 independent samples: the ratio's standard error is < 1/sqrt(2n) < 1.7 %; 4 of them.
    EXPECT_NEAR(ratio, 1.0, 4.0 / std::sqrt(2.0 * n)) << "R = " << radius << ", " << n << " samples";
    EXPECT_LT(sum_sq, 0.6 * raw_sq) << "R = " << radius;
  }
}

TEST(CoordinateFilter, RippleIsNotAveragedAway) {
  // sigma = hypot(random 0.06, ripple 0.08): only the random part shrinks.
  DecodedCamera d = MakeCamera(0.0, 3);
  d.sigma_coordinate.setTo(0.1);
  CoordinateFilterOptions o;
  o.radius_px = 3;
  FilterCoordinate(o, 0.08, &d);
  const double s = d.sigma_coordinate.at<float>(60, 80);
  EXPECT_GT(s, 0.08);
  EXPECT_LT(s, 0.1);
  // The 7x7 quadratic centre weights' sum of squares, from the sigma without ripple.
  DecodedCamera e = MakeCamera(0.0, 3);
  e.sigma_coordinate.setTo(0.06);
  FilterCoordinate(o, 0.0, &e);
  const double random_part = e.sigma_coordinate.at<float>(60, 80);
  EXPECT_NEAR(s, std::hypot(random_part, 0.08), 1e-6);
}

TEST(CoordinateFilter, DepthStepIsLeftAlone) {
  // Pixels whose window straddles a 40 px jump: the filtered value would be far off, so they keep
  // their own; none ends up more than 5 sigma from the truth.
  DecodedCamera d = MakeCamera(0.05, 4, true);
  CoordinateFilterOptions o;
  o.radius_px = 2;
  const CoordinateFilterSummary s = FilterCoordinate(o, 0.0, &d);
  EXPECT_GT(s.kept_departure, 0);
  const double worst = WorstError(
      d, [](int x, int y) { return Surface(x, y) + (x >= 80 ? 40.0 : 0.0); }, 5, true);
  EXPECT_LT(worst, 5.5);
}

TEST(CoordinateFilter, BadOptionsAreRefused) {
  DecodedCamera d = MakeCamera(0.05, 5);
  CoordinateFilterOptions o;
  o.radius_px = 7;
  EXPECT_FALSE(o.Validate().empty());
  EXPECT_THROW(FilterCoordinate(o, 0.0, &d), std::exception);
}

}  // namespace
}  // namespace ramtk::vision
