// EstimateNeighbourCorrelation against closed forms: white noise filtered by a bx x by box has
// rho(du, dv) = (bx - |du|)(by - |dv|) / (bx by) and the sum of rho over all lags is bx * by, the
// factor by which the variance of a large-area mean exceeds the independent-point one; white
// noise gives 1.
#include <gtest/gtest.h>

#include <random>

#include "ramtk/core/error.h"
#include "ramtk/vision/stereo/cloud_noise.h"

namespace ramtk::vision {
namespace {

struct Field {
  std::vector<Eigen::Vector2f> pixels;
  std::vector<double> z;
};

// White noise on a w x h grid, filtered by a box of bx x by pixels (normalised to unit variance),
// every pixel a point except a hole in the middle.
Field BoxFiltered(int w, int h, int bx, int by, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  std::vector<double> white(static_cast<size_t>((w + bx) * (h + by)));
  for (double& v : white) v = n01(rng);
  Field f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (std::abs(x - w / 2) < 10 && std::abs(y - h / 2) < 10) continue;
      double sum = 0;
      for (int j = 0; j < by; ++j)
        for (int i = 0; i < bx; ++i) sum += white[static_cast<size_t>((y + j) * (w + bx) + x + i)];
      f.pixels.emplace_back(static_cast<float>(x), static_cast<float>(y));
      f.z.push_back(sum / std::sqrt(bx * by));
    }
  return f;
}

TEST(NeighbourCorrelation, IndependentNoiseHasFactorOne) {
  const Field f = BoxFiltered(300, 200, 1, 1, 1);
  const NeighbourCorrelation c = EstimateNeighbourCorrelation(f.pixels, f.z, cv::Size(300, 200));
  // 12 lags of ~60k pairs each: each rho has sd ~1/sqrt(60k) = 0.004, the sum of 24 terms ~0.04.
  EXPECT_NEAR(c.factor, 1.0, 0.1);
  EXPECT_NEAR(c.rho_right, 0.0, 0.02);
}

TEST(NeighbourCorrelation, MovingAverageAlongRowsDoublesTheVariance) {
  // For a box of bx x by the variance of a large-area mean is bx * by times the independent one:
  // the factor is the sum of rho over all lags, which for the box is exactly bx * by.
  const Field f = BoxFiltered(300, 200, 2, 1, 2);
  const NeighbourCorrelation c = EstimateNeighbourCorrelation(f.pixels, f.z, cv::Size(300, 200));
  EXPECT_NEAR(c.rho_right, 0.5, 0.02);
  EXPECT_NEAR(c.rho_down, 0.0, 0.02);
  EXPECT_NEAR(c.factor, 2.0, 0.1);
  const Field g = BoxFiltered(300, 200, 2, 2, 3);
  const NeighbourCorrelation d = EstimateNeighbourCorrelation(g.pixels, g.z, cv::Size(300, 200));
  EXPECT_NEAR(d.rho_down, 0.5, 0.02);
  EXPECT_NEAR(d.factor, 4.0, 0.15);
}

TEST(NeighbourCorrelation, MismatchedSizesAreAnInputError) {
  EXPECT_THROW(EstimateNeighbourCorrelation({Eigen::Vector2f(0, 0)}, {}, cv::Size(4, 4)), InputError);
}

}  // namespace
}  // namespace ramtk::vision
