// The sampling kernel's variance estimated from the stereo data (StereoMatchOptions::
// kernel_estimate, detail::EstimateKernelVariance) against kernels it did not produce:
// synthetic decoded maps whose modulation carries a Gaussian kernel's closed-form MTF, and the
// simulator's renders with known kernels (point sampling, the 4×4 box pixel, box + lens PSF).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <random>
#include <utility>

#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/sim/fringe_renderer.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "ramtk/vision/stereo/detail/stereo_kernel_estimate.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// A synthetic pair: the right pixel (x, y) matches the left pixel (s_y·x + 3, y), the scale s_y
// running 0.7 … 1.4 over the rows, so the left fringe's frequency along u is the right one's over
// s_y (and the left map has a gradient along v that grows with u).
// Coordinate c_R = f·x + 0.1·y (projector px), the true modulation 100 DN (the left camera's gain
// 1.2), each camera's modulation times its Gaussian kernel's MTF exp(−½·k·|g|²), plus noise of
// relative σ `noise` (fixed seed).
struct Synthetic {
  DecodedCamera left, right;
  cv::Mat back_u, back_v;
  double period = 16;
};

Synthetic MakeSynthetic(double k_left, double k_right, double noise) {
  const int w = 200, h = 160;
  const double f = 2.0;  // projector px per right px: g_R = 2π·2/16 ≈ 0.79 rad/px
  Synthetic s;
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto make = [&](DecodedCamera* d) {
    d->coordinate = cv::Mat(h, w, CV_32F, cv::Scalar(NAN));
    d->modulation = cv::Mat(h, w, CV_32F, cv::Scalar(0));
    d->sigma_coordinate = cv::Mat(h, w, CV_32F, cv::Scalar(0));
    d->mask = cv::Mat(h, w, CV_8U, cv::Scalar(255));
  };
  make(&s.left);
  make(&s.right);
  s.back_u = cv::Mat(h, w, CV_32F, cv::Scalar(NAN));
  s.back_v = cv::Mat(h, w, CV_32F, cv::Scalar(NAN));
  const double scale2 = std::pow(kTwoPi / s.period, 2);
  for (int y = 0; y < h; ++y) {
    const double sy = 0.7 + 0.7 * y / (h - 1.0), dsy = 0.7 / (h - 1.0);
    const double gr2 = scale2 * (f * f + 0.01);
    for (int x = 0; x < w; ++x) {
      // The left map's gradient at left pixel (x, y): (f / s_y, 0.1 − f·(x − 3)·s_y' / s_y²).
      const double gl2 = scale2 * (std::pow(f / sy, 2) + std::pow(0.1 - f * (x - 3) * dsy / (sy * sy), 2));
      s.right.coordinate.at<float>(y, x) = static_cast<float>(f * x + 0.1 * y);
      s.right.modulation.at<float>(y, x) =
          static_cast<float>(100.0 * std::exp(-0.5 * k_right * gr2) * (1 + noise * n01(rng)));
      // The left map: c_L(u, v) = c_R((u − 3)/s_v, v).
      s.left.coordinate.at<float>(y, x) = static_cast<float>(f * (x - 3) / sy + 0.1 * y);
      s.left.modulation.at<float>(y, x) =
          static_cast<float>(120.0 * std::exp(-0.5 * k_left * gl2) * (1 + noise * n01(rng)));
      const double u = sy * x + 3;
      if (u < w - 1) s.back_u.at<float>(y, x) = static_cast<float>(u), s.back_v.at<float>(y, x) = y;
    }
  }
  return s;
}

TEST(KernelEstimate, RecoversAGaussianKernelFromSyntheticMaps) {
  for (double k : {0.0, 1.0 / 12, 1.0 / 3}) {
    const Synthetic s = MakeSynthetic(k, k, 0.0);
    const KernelVarianceEstimate e = detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period,
                                                                   std::nullopt, std::nullopt);
    ASSERT_EQ(e.status, "estimated");
    // Noise-free and linear maps: the central differences are exact, and the model's only
    // error is the Gaussian's fourth-order term (~k²·|g|⁴/8 against k·|g|²/2).
    EXPECT_NEAR(e.variance_px2, k, 0.01 * k + 1e-6) << "k " << k;
  }
}

TEST(KernelEstimate, SigmaCoversTheErrorWithNoise) {
  const double k = 1.0 / 12;
  const Synthetic s = MakeSynthetic(k, k, 0.005);
  const KernelVarianceEstimate e =
      detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period, std::nullopt, std::nullopt);
  ASSERT_EQ(e.status, "estimated");
  EXPECT_GT(e.sigma_px2, 0.0);
  EXPECT_LT(e.sigma_px2, 0.02);
  EXPECT_NEAR(e.variance_px2, k, 3 * e.sigma_px2);
}

TEST(KernelEstimate, OneStatedKernelFitsTheOther) {
  // The right camera's kernel stated (0.1 px²), the left one's (0.3 px²) estimated (the right
  // map's frequency is the same everywhere: only the left one's varies).
  const Synthetic s = MakeSynthetic(0.3, 0.1, 0.0);
  const KernelVarianceEstimate e =
      detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period, std::nullopt, 0.1);
  ASSERT_EQ(e.status, "estimated");
  EXPECT_NEAR(e.variance_px2, 0.3, 0.003);
  // The left camera's kernel stated instead (0.3 px²): the right one's term is a constant here,
  // so the fit has no leverage and its σ says so.
  const KernelVarianceEstimate blind =
      detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period, 0.3, std::nullopt);
  EXPECT_FALSE(blind.sigma_px2 < 0.03) << blind.variance_px2 << " +- " << blind.sigma_px2;
  // Both stated: nothing to estimate.
  EXPECT_EQ(detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period, 0.3, 0.1).status, "stated");
}

TEST(KernelEstimate, TooFewPixels) {
  Synthetic s = MakeSynthetic(0.1, 0.1, 0.0);
  s.back_u = cv::Scalar(NAN);
  EXPECT_EQ(
      detail::EstimateKernelVariance(s.left, s.right, s.back_u, s.back_v, s.period, std::nullopt, std::nullopt).status,
      "too few pixels");
}

// The variance of the kernel the simulator renders camera 0 with (its sub-ray nodes).
double RenderedVariance(const FringeSimulationConfig& c) {
  const std::vector<double> nodes = KernelNodeOffsets(RenderedKernel(c, 0), c.supersampling);
  double v = 0;
  for (double t : nodes) v += t * t / nodes.size();
  return v;
}

struct KernelScan {
  KernelVarianceEstimate kernel;
  Vec3 error_um = Vec3::Zero();
  Vec3 sigma_um = Vec3::Zero();
  bool found = false;
};

// A noise-free render of SLMaster's rig (the "small" scene around its calibration), rendered once
// per kernel and kept for the tests: `ss` rays per pixel axis, `psf` the lens PSF σ (px, < 0 none).
struct Render {
  FringeSimulationConfig config;
  SimulatedCamera left, right;
  double truth_k = 0;  // the rendered kernel's variance, px²
};

const Render& SlmasterRender(const std::string& calib_path, int ss, double psf) {
  static std::map<std::pair<int, double>, Render> cache;
  auto it = cache.find({ss, psf});
  if (it != cache.end()) return it->second;
  Render r;
  FringeSimulationConfig& c = r.config;
  c = MakeFringeConfigForCalibration(ReadStereoCalibration(calib_path));
  c.supersampling = ss;
  if (psf >= 0)
    c.cameras.left.sampling_kernel = c.cameras.right.sampling_kernel = camera::SamplingKernel{1.0, psf};
  c.sensor.noise = false;
  r.truth_k = RenderedVariance(c);
  r.left = SimulateCamera(c, 0);
  r.right = SimulateCamera(c, 1);
  return cache.emplace(std::make_pair(ss, psf), std::move(r)).first->second;
}

// Scans the render sensed with `bits` and, with `noise`, seed 1000's sensor noise; its
// calibration states no kernel.
KernelScan ScanRender(const Render& render, bool noise, int bits, StereoMatchOptions::KernelEstimate mode) {
  FringeSimulationConfig c = render.config;
  c.sensor.noise = noise;
  c.sensor.bits = bits;
  c.seed = 1000;
  const SimulatedCamera l = ResenseCamera(c, render.left, 0), r = ResenseCamera(c, render.right, 1);
  StereoCalibration calib = WrittenCalibration(c);
  calib.left.sampling_kernel = calib.right.sampling_kernel = std::nullopt;
  ScanOptions o;
  o.roi.mode = ScanRoiOptions::Mode::kAuto;
  o.match.kernel_estimate = mode;
  const ScanResult res = ScanFrames(testing::ManifestForConfig(c), calib, l.images, r.images, (1 << bits) - 1.0, o);
  KernelScan out;
  out.kernel = res.summary.match.kernel;
  if (res.summary.spheres.spheres.empty()) return out;
  const SphereResult& s = res.summary.spheres.spheres[0];
  out.found = true;
  out.error_um = 1e3 * (s.centre_mm - c.scene.spheres.at(0).centre_in_left);
  out.sigma_um = 1e3 * s.CentreSigma();
  std::printf("ss %d noise %d bits %d: k = %.4f +- %.4f px^2 (truth %.4f, %s), centre error (%+.2f, %+.2f, %+.2f) um, "
              "sigma (%.2f, %.2f, %.2f) um\n",
              c.supersampling, noise, bits, out.kernel.variance_px2, out.kernel.sigma_px2, render.truth_k,
              out.kernel.status.c_str(), out.error_um.x(), out.error_um.y(), out.error_um.z(), out.sigma_um.x(),
              out.sigma_um.y(), out.sigma_um.z());
  return out;
}

std::string SlmasterCalibration() {
  return std::string(RAMTK_SHARED_DIR) + "/data/slmaster-binocular/caliInfo.yml";
}

TEST(KernelEstimate, RecoversTheRenderedKernelWithNoise) {
  const std::string path = SlmasterCalibration();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  struct Case {
    int ss;
    double psf;
  };
  // Point sampling (0), the 4×4 box pixel (0.078), box + a 0.5 px PSF (0.333).
  for (const Case& k : {Case{1, -1}, Case{4, -1}, Case{4, 0.5}}) {
    const Render& render = SlmasterRender(path, k.ss, k.psf);
    const double truth = render.truth_k;
    const KernelScan s = ScanRender(render, true, 8, StereoMatchOptions::KernelEstimate::kAuto);
    EXPECT_EQ(s.kernel.status, "applied");
    EXPECT_GT(s.kernel.pixels, 5000);
    // Within 3σ of its own jackknife σ (0.005–0.013 px² here), and the σ small enough to apply.
    EXPECT_LT(s.kernel.sigma_px2, 0.02);
    EXPECT_NEAR(s.kernel.variance_px2, truth, 3 * s.kernel.sigma_px2 + 0.002) << "ss " << k.ss << " psf " << k.psf;
  }
}

TEST(KernelEstimate, ScanWithoutAStatedKernelLandsOnTheTruth) {
  const std::string path = SlmasterCalibration();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  for (int ss : {1, 4}) {
    const Render& render = SlmasterRender(path, ss, -1);
    // Noise-free 16-bit renders: without the estimate the centre is off by (+1.8, 0.0, −4.3) µm
    // (point sampling) and (+0.9, +0.2, −1.2) µm (box pixel); with it, within 0.5 µm.
    const KernelScan off = ScanRender(render, false, 16, StereoMatchOptions::KernelEstimate::kOff);
    const KernelScan on = ScanRender(render, false, 16, StereoMatchOptions::KernelEstimate::kAuto);
    ASSERT_TRUE(off.found && on.found);
    EXPECT_EQ(off.kernel.status, "off");
    EXPECT_FALSE(off.kernel.applied);
    EXPECT_FALSE(std::isfinite(off.kernel.variance_px2));
    EXPECT_GT(off.error_um.cwiseAbs().maxCoeff(), 1.0) << "ss " << ss;
    EXPECT_EQ(on.kernel.status, "applied");
    EXPECT_LT(on.error_um.cwiseAbs().maxCoeff(), 0.5) << "ss " << ss;
    // With noise (one seed): within 3σ of the truth on every axis.
    const KernelScan noisy = ScanRender(render, true, 8, StereoMatchOptions::KernelEstimate::kAuto);
    ASSERT_TRUE(noisy.found);
    for (int a = 0; a < 3; ++a) EXPECT_LT(std::abs(noisy.error_um[a]), 3 * noisy.sigma_um[a]) << "ss " << ss;
  }
}

TEST(KernelEstimate, StatedKernelWinsAndOffKeepsTheUnstatedScan) {
  // The small rig (no shared data): with both kernels stated the estimate is not run; with none
  // stated and the estimate off the match summary says so and nothing is estimated.
  FringeSimulationConfig c = MakeFringePreset("small");
  c.sensor.noise = false;
  const testing::DecodedStereo d = testing::SimulateAndDecode(c);
  const StereoCalibration unstated = WrittenCalibration(c);
  const StereoCalibration stated = WrittenCalibration(StateRenderedKernel(c));
  auto scan = [&](const StereoCalibration& calib, StereoMatchOptions::KernelEstimate mode) {
    ScanOptions o;
    o.match.kernel_estimate = mode;
    return ScanDecoded(calib, d.left, d.right, d.period, o);
  };
  const ScanResult stated_auto = scan(stated, StereoMatchOptions::KernelEstimate::kAuto);
  const ScanResult stated_off = scan(stated, StereoMatchOptions::KernelEstimate::kOff);
  EXPECT_EQ(stated_auto.summary.match.kernel.status, "stated");
  EXPECT_DOUBLE_EQ(stated_auto.summary.match.kernel.left_px2, RenderedKernel(c, 0).VariancePx2());
  ASSERT_FALSE(stated_auto.summary.spheres.spheres.empty());
  ASSERT_FALSE(stated_off.summary.spheres.spheres.empty());
  EXPECT_EQ(stated_auto.summary.spheres.spheres[0].centre_mm, stated_off.summary.spheres.spheres[0].centre_mm);
  const ScanResult off = scan(unstated, StereoMatchOptions::KernelEstimate::kOff);
  const ScanResult on = scan(unstated, StereoMatchOptions::KernelEstimate::kAuto);
  EXPECT_EQ(off.summary.match.kernel.status, "off");
  EXPECT_NE(on.summary.match.kernel.status, "off");
  EXPECT_TRUE(std::isfinite(on.summary.match.kernel.variance_px2));
  ASSERT_FALSE(off.summary.spheres.spheres.empty());
  // Off: no kernel terms, so not the stated scan's centre.
  EXPECT_NE(off.summary.spheres.spheres[0].centre_mm, stated_off.summary.spheres.spheres[0].centre_mm);
}

}  // namespace
}  // namespace ramtk::vision
