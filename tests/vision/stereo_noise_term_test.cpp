// The matcher's noise term (StereoMatchOptions::noise_bias_term, stereo_kernel_terms.h) against
// a closed form. A rectified pair (f = 1000 px, baseline 100 mm) views the plane z = 1000 mm; the
// projector coordinate is quadratic across it, c(X) = 500 + a·(X − X0) + b·(X − X0)², so the
// right map's slope h' along each row runs from 0.2 to 1 projector px per px and its curvature
// is h'' = 2b everywhere. The left map is perturbed by +ε and by −ε (each pixel's coordinate σ
// is ε): the mean of the two roots is the root of a zero-mean noise of variance ε², which sits off
// the true crossing by −½·h''·ε²/h'³ px (the inverse function's curvature). The noise term must
// take that mean back to the plane; without it the mean disparity must be off by the closed form.
// The right map is exact (σ 0) and the sampling kernel is stated as a point (fill factor 0), so
// the interpolation term makes a noise-free match exact on this quadratic map.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/stereo/stereo_match.h"

namespace ramtk::vision {
namespace {

constexpr int kWidth = 400, kHeight = 60;
constexpr double kF = 1000, kCx = 199.5, kCy = 29.5, kBaseline = 100, kDepth = 1000;
constexpr double kA = 0.2, kB = 0.002, kX0 = -98;  // c'(X) = a + 2b(X − X0): 0.2 at X0, 1 at X0 + 200
constexpr double kEps = 0.1;                       // projector px

double Coordinate(double x_mm) { return 500 + kA * (x_mm - kX0) + kB * (x_mm - kX0) * (x_mm - kX0); }

StereoCalibration Rig() {
  StereoCalibration c;
  for (CameraIntrinsics* cam : {&c.left, &c.right}) {
    cam->fx = cam->fy = kF;
    cam->cx = kCx;
    cam->cy = kCy;
    cam->width = kWidth;
    cam->height = kHeight;
    cam->sampling_kernel = camera::SamplingKernel{0.0, 0.0};
  }
  c.right_from_left.translation() = Vec3(-kBaseline, 0, 0);
  return c;
}

// A camera seeing the plane: pixel u sees X = (u − cx)·z/f + offset_mm (the left camera: 0;
// the right one: the baseline).
DecodedCamera View(double offset_mm, double shift, double sigma) {
  DecodedCamera d;
  d.coordinate.create(kHeight, kWidth, CV_32F);
  d.modulation = cv::Mat(kHeight, kWidth, CV_32F, cv::Scalar(100));
  d.mask = cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(255));
  d.sigma_coordinate = cv::Mat(kHeight, kWidth, CV_32F, cv::Scalar(sigma));
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
      d.coordinate.at<float>(v, u) = static_cast<float>(Coordinate((u - kCx) * kDepth / kF + offset_mm) + shift);
  return d;
}

// Mean over rows of (the mean disparity of the ±ε matches − the true disparity), px, for left
// pixels whose right map slope lies in [lo, hi]; and the closed form's mean over the same pixels.
struct Bias {
  double measured = 0, closed_form = 0;
  long pixels = 0;
};

Bias MeasureBias(bool noise_term, double lo, double hi) {
  const StereoCalibration rig = Rig();
  const DecodedCamera right = View(kBaseline, 0, 0);
  StereoMatchOptions o;
  o.min_depth_mm = 500;
  o.max_depth_mm = 2000;
  o.lr_tolerance_px = 0;  // the ±ε matches lie ε/h' px off the noise-free one: no left-right check
  o.noise_bias_term = noise_term;
  const StereoMatch plus = MatchStereo(rig, View(0, kEps, kEps), right, 100.0, o);
  const StereoMatch minus = MatchStereo(rig, View(0, -kEps, kEps), right, 100.0, o);
  const double d_true = kF * kBaseline / kDepth;
  Bias b;
  for (int v = 2; v < kHeight - 2; ++v)
    for (int u = 0; u < kWidth; ++u) {
      const float zp = plus.depth_mm.at<float>(v, u), zm = minus.depth_mm.at<float>(v, u);
      if (!std::isfinite(zp) || !std::isfinite(zm) || !(zp > 0) || !(zm > 0)) continue;
      const double x_mm = (u - kCx) * kDepth / kF;  // the point's X (left camera frame)
      const double slope = (kA + 2 * kB * (x_mm - kX0)) * kDepth / kF;
      if (slope < lo || slope > hi) continue;
      // Disparity is linear in the curve's parameter w = 1/z: average it, not the depth.
      const double d_mean = 0.5 * (kF * kBaseline / zp + kF * kBaseline / zm);
      b.measured += d_mean - d_true;
      // The right pixel's mean lies −½·h''·ε²/h'³ off: the disparity +½·h''·ε²/h'³.
      b.closed_form += 0.5 * (2 * kB * kDepth * kDepth / (kF * kF)) * kEps * kEps / (slope * slope * slope);
      ++b.pixels;
    }
  if (b.pixels > 0) {
    b.measured /= b.pixels;
    b.closed_form /= b.pixels;
  }
  return b;
}

TEST(StereoNoiseTerm, TakesTheMeanOfNoisyMatchesBackToTheTrueCrossing) {
  // Low slopes, where the term is largest: 0.2–0.3 projector px per px (closed form 7e-4 to
  // 2.5e-3 px; measured within 1e-4 of it, and within 1e-3 of zero with the term); and the rest.
  for (const auto& [lo, hi] : {std::pair{0.2, 0.3}, std::pair{0.3, 1.0}}) {
    const Bias off = MeasureBias(false, lo, hi);
    const Bias on = MeasureBias(true, lo, hi);
    std::cout << "slopes " << lo << "-" << hi << ": off " << off.measured << " closed form " << off.closed_form << " on " << on.measured << " (" << on.pixels << " px)\n";
    ASSERT_GT(off.pixels, 1000);
    ASSERT_GT(on.pixels, 1000);
    // Without the term the mean sits where the closed form says. The next order, (h''ε/h'²)²
    // ~ 1e-2 of it, and the float maps' rounding (coordinates ~500 as float: 3e-5 projector px,
    // ≤ 1.5e-4 px at these slopes, averaged over the pixels) bound the agreement: 5 %.
    EXPECT_NEAR(off.measured, off.closed_form, 0.05 * off.closed_form) << "slopes " << lo << "–" << hi;
    // With it the mean is the true crossing, to the same next order.
    EXPECT_LT(std::abs(on.measured), 0.05 * off.closed_form) << "slopes " << lo << "–" << hi;
  }
}

TEST(StereoNoiseTerm, LeavesANoiseFreeMatchAlone) {
  // σ = 0 on both maps: the term is zero and the outputs are those without it, bit for bit.
  const StereoCalibration rig = Rig();
  const DecodedCamera left = View(0, 0, 0), right = View(kBaseline, 0, 0);
  StereoMatchOptions o;
  o.min_depth_mm = 500;
  o.max_depth_mm = 2000;
  const StereoMatch with = MatchStereo(rig, left, right, 100.0, o);
  o.noise_bias_term = false;
  const StereoMatch without = MatchStereo(rig, left, right, 100.0, o);
  ASSERT_GT(with.summary.matched, 10000);
  long differ = 0;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      const float a = with.depth_mm.at<float>(v, u), b = without.depth_mm.at<float>(v, u);
      if (!(a == b || (std::isnan(a) && std::isnan(b)))) ++differ;
    }
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace ramtk::vision
