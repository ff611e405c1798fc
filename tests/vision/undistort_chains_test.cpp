// The match's undistortion chains (undistort_chains.h) against UndistortNormalized called pixel by
// pixel with the seeding rule the match used before the chains existed, and their rays against
// Eigen's 3 x 3 products: bit for bit, on lanes
// (AVX2) and without, for rows of different lengths with gaps, for a lens whose Gauss-Newton does
// not converge at the corners, and for a lens term that is not a number (the lanes hand such
// pixels back to the scalar function).
#include "ramtk/vision/stereo/detail/undistort_chains.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision {
namespace {

// The seeding rule of the match's walk, written out here: the previous two solutions' linear
// extrapolation when they were the row's two pixels before, else the previous one, else the
// distorted point.
std::vector<Vec2> PixelByPixel(const CameraIntrinsics& cam, int y, const std::vector<int>& xs) {
  std::vector<Vec2> out;
  Vec2 prev(NAN, NAN), prev2(NAN, NAN);
  int xp = -10, xp2 = -10;
  for (const int x : xs) {
    const Vec2 distorted((x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy);
    Vec2 seed = distorted;
    if (xp == x - 1 && xp2 == x - 2)
      seed = 2.0 * prev - prev2;
    else if (std::isfinite(prev.x()))
      seed = prev;
    out.push_back(UndistortNormalized(cam.distortion, distorted, seed));
    prev2 = prev, xp2 = xp;
    prev = out.back(), xp = x;
  }
  return out;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void ExpectChainsMatch(const CameraIntrinsics& cam, bool lanes) {
  detail::SetAvx2Kernels(lanes);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // Eleven rows (two groups of four and three left over), lengths 0 .. full, with gaps.
  const int width = 640;
  std::vector<std::vector<int>> xs(11);
  for (int r = 0; r < 11; ++r) {
    const double keep = r == 0 ? 0.0 : r == 1 ? 1.0 : uni(rng);
    for (int x = 0; x < width; ++x)
      if (uni(rng) < keep || (r == 2 && x == 7)) xs[r].push_back(x);
  }
  // The rays turned by a verging rig's rotation and a rectifying one (Eigen's products are the truth).
  detail::ChainRays turn;
  turn.rotation = Eigen::AngleAxisd(0.31, Vec3(0.1, 0.9, -0.2).normalized()).toRotationMatrix();
  turn.rectified = true;
  turn.rect_from_camera = Eigen::AngleAxisd(-0.17, Vec3(0.7, 0.1, 0.3).normalized()).toRotationMatrix();
  turn.rect_f = 812.5;
  std::vector<std::vector<double>> out(11 * 8);
  std::vector<detail::UndistortChain> chains(11);
  for (int r = 0; r < 11; ++r) {
    double* v[8];
    for (int j = 0; j < 8; ++j) v[j] = (out[8 * r + j] = std::vector<double>(xs[r].size(), 0.0)).data();
    chains[r] = {xs[r].data(), static_cast<int>(xs[r].size()), 37 * r, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]};
  }
  detail::UndistortChains(cam, chains.data(), 11, &turn);
  long compared = 0;
  for (int r = 0; r < 11; ++r) {
    const std::vector<Vec2> truth = PixelByPixel(cam, 37 * r, xs[r]);
    const detail::UndistortChain& c = chains[r];
    for (std::size_t k = 0; k < truth.size(); ++k, ++compared) {
      ASSERT_TRUE(SameBits(c.ideal_x[k], truth[k].x()) && SameBits(c.ideal_y[k], truth[k].y()))
          << "row " << r << " pixel " << xs[r][k] << ": " << c.ideal_x[k] << ", " << c.ideal_y[k] << " against "
          << truth[k].x() << ", " << truth[k].y();
      const Vec3 ray(truth[k].x(), truth[k].y(), 1.0);
      const Vec3 a = turn.rotation * ray, q = turn.rect_from_camera * ray;
      ASSERT_TRUE(SameBits(c.a_x[k], a.x()) && SameBits(c.a_y[k], a.y()) && SameBits(c.a_z[k], a.z()))
          << "row " << r << " pixel " << xs[r][k] << ": a";
      ASSERT_TRUE(SameBits(c.rs_z[k], q.z()) && SameBits(c.rs_u[k], turn.rect_f * q.x() / q.z()) &&
                  SameBits(c.rs_v[k], turn.rect_f * q.y() / q.z()))
          << "row " << r << " pixel " << xs[r][k] << ": rectified ray, lanes " << lanes << ": " << c.rs_u[k] << " " << turn.rect_f * q.x() / q.z() << " " << c.rs_v[k] << " " << turn.rect_f * q.y() / q.z() << " " << c.rs_z[k] << " " << q.z();
    }
  }
  EXPECT_GT(compared, 2000);
  detail::SetAvx2Kernels(true);
}

CameraIntrinsics Lens(double k1, double k2, double k3) {
  CameraIntrinsics c;
  c.fx = 800, c.fy = 801, c.cx = 319.5, c.cy = 239.5, c.width = 640, c.height = 480;
  c.distortion = {k1, k2, 1.2e-3, -7e-4, k3};
  return c;
}

// A moderate lens, and a strong one whose Gauss-Newton does not converge at the image corners in
// its 30 iterations (the lanes must stop where the scalar loop stops).
TEST(UndistortChains, LanesAndScalarGiveUndistortNormalizedBitForBit) {
  const CameraIntrinsics strong = Lens(-9.0, 40.0, -60.0);
  const Vec2 corner(-319.5 / 800, -239.5 / 801);
  ASSERT_GT((DistortNormalized(strong.distortion, UndistortNormalized(strong.distortion, corner)) - corner).norm(),
            1e-12)
      << "the strong lens should not converge at the corner";
  for (const CameraIntrinsics& lens : {Lens(-0.21, 0.13, -0.02), strong}) {
    ExpectChainsMatch(lens, false);
    if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0): lanes not tested";
    ExpectChainsMatch(lens, true);
  }
}

// A lens term that is not a number (a damaged calibration that slipped through): every residual is
// NaN, the lanes hand every pixel back to the scalar function, whose result (NaN) is kept.
TEST(UndistortChains, NonFiniteLensTermKeepsTheScalarResult) {
  const CameraIntrinsics lens = Lens(std::numeric_limits<double>::quiet_NaN(), 0.13, -0.02);
  ExpectChainsMatch(lens, false);
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0): lanes not tested";
  ExpectChainsMatch(lens, true);
}

}  // namespace
}  // namespace ramtk::vision
