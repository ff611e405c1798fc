// Board corners in projector pixels (projector_corners.h) against closed-form truth: a flat board
// maps camera pixels to projector pixels by a known homography; the decoded (u, v) are that map
// plus Gaussian noise of known sigma (fixed seeds). Each corner's projector pixel must come back
// within the noise, and its predicted sigma must match the scatter over corners and seeds.
#include <gtest/gtest.h>

#include <random>

#include "ramtk/core/error.h"
#include "ramtk/vision/projector/projector_corners.h"

namespace ramtk::vision {
namespace {

Vec2 Apply(const Eigen::Matrix3d& H, const Vec2& x) {
  const Vec3 p = H * Vec3(x.x(), x.y(), 1.0);
  return p.head<2>() / p.z();
}

// A board plane's camera-to-projector homography (perspective, rotated, scaled ~1.4x).
Eigen::Matrix3d BoardHomography() {
  Eigen::Matrix3d H;
  H << 1.35, 0.12, 210.0, -0.08, 1.42, 95.0, 1.1e-4, -6e-5, 1.0;
  return H;
}

void Decode(const Eigen::Matrix3d& H, double sigma, std::uint64_t seed, DecodedCamera* u, DecodedCamera* v) {
  const int W = 320, Hgt = 240;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  u->coordinate.create(Hgt, W, CV_32F);
  v->coordinate.create(Hgt, W, CV_32F);
  u->sigma_coordinate = cv::Mat(Hgt, W, CV_32F, cv::Scalar(sigma));
  v->sigma_coordinate = cv::Mat(Hgt, W, CV_32F, cv::Scalar(sigma));
  for (int y = 0; y < Hgt; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 p = Apply(H, Vec2(x, y));
      u->coordinate.at<float>(y, x) = static_cast<float>(p.x() + noise(rng));
      v->coordinate.at<float>(y, x) = static_cast<float>(p.y() + noise(rng));
    }
  // An undecoded hole (a dark square of the board).
  u->coordinate(cv::Rect(20, 15, 50, 50)).setTo(std::numeric_limits<float>::quiet_NaN());
}

TEST(ProjectorCorners, LocalHomographyRecoversCornersWithHonestSigma) {
  const Eigen::Matrix3d H = BoardHomography();
  const double sigma = 0.08;  // projector px per pixel
  std::vector<cv::Point2f> corners;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 7; ++i) corners.emplace_back(40.3f + 38.7f * i, 35.6f + 41.1f * j);
  double sum_sq = 0, worst_noise_free = 0;
  long n = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    DecodedCamera u, v;
    Decode(H, sigma, seed, &u, &v);
    const std::vector<ProjectorCorner> pc = ProjectorCornersFromPhase(corners, u, v);
    ASSERT_EQ(pc.size(), corners.size());
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const Vec2 truth = Apply(H, Vec2(corners[k].x, corners[k].y));
      if (k == 0) {  // inside the hole's window: too few decoded pixels
        EXPECT_FALSE(pc[k].valid);
        continue;
      }
      ASSERT_TRUE(pc[k].valid) << k;
      EXPECT_GE(pc[k].pixels, 31 * 31 / 2);
      const Vec2 e = pc[k].projector_px - truth;
      sum_sq += e.x() * e.x() / (pc[k].sigma_px.x() * pc[k].sigma_px.x()) +
                e.y() * e.y() / (pc[k].sigma_px.y() * pc[k].sigma_px.y());
      n += 2;
      EXPECT_NEAR(pc[k].residual_rms_px, sigma, 0.1 * sigma);
    }
  }
  const double ratio = std::sqrt(sum_sq / n);  // scatter / predicted sigma
  std::cout << "corner error RMS / predicted sigma: " << ratio << " over " << n << " values\n";
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
  // Noise-free: the homography is the model, so corners are exact to float rounding.
  DecodedCamera u, v;
  Decode(H, 1e-12, 1, &u, &v);
  for (const ProjectorCorner& c : ProjectorCornersFromPhase({cv::Point2f(200.25f, 150.75f)}, u, v)) {
    worst_noise_free = (c.projector_px - Apply(H, Vec2(200.25, 150.75))).norm();
  }
  EXPECT_LT(worst_noise_free, 1e-4);
}

TEST(ProjectorCorners, RejectsMismatchedMapsAndCornersOffTheImage) {
  DecodedCamera u, v;
  Decode(BoardHomography(), 0.05, 3, &u, &v);
  const std::vector<ProjectorCorner> pc = ProjectorCornersFromPhase({cv::Point2f(3, 3), cv::Point2f(318, 120)}, u, v);
  EXPECT_FALSE(pc[0].valid);
  EXPECT_FALSE(pc[1].valid);
  v.coordinate = cv::Mat(10, 10, CV_32F);
  EXPECT_THROW(ProjectorCornersFromPhase({cv::Point2f(100, 100)}, u, v), InputError);
  ProjectorCornerOptions o;
  o.half_window_px = 1;
  EXPECT_THROW(ProjectorCornersFromPhase({}, u, u, o), InputError);
}

}  // namespace
}  // namespace ramtk::vision
