// The camera's sampling kernel in the renderer against closed forms: the nodes' moments, a
// projector step edge imaged through box ⊗ Gaussian against its CDF (erf), and a fringe's
// modulation against the kernel's characteristic function sinc(k·f/2)·exp(−k²σ²/2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ramtk/vision/sim/fringe_renderer.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

// CDF of box(f) ⊗ N(0, σ²), written out from the integral of Φ (not the renderer's).
double BoxGaussCdf(double f, double sigma, double x) {
  auto cdf = [](double z) { return 0.5 * (1.0 + std::erf(z / std::sqrt(2.0))); };
  if (sigma == 0.0) return f == 0.0 ? (x >= 0 ? 1.0 : 0.0) : std::clamp(x / f + 0.5, 0.0, 1.0);
  if (f == 0.0) return cdf(x / sigma);
  // (1/f)∫_{x−f/2}^{x+f/2} Φ(t/σ) dt with ∫Φ(t/σ)dt = t·Φ(t/σ) + σ·φ(t/σ).
  auto prim = [&](double t) { return t * cdf(t / sigma) + sigma * std::exp(-0.5 * t * t / (sigma * sigma)) / std::sqrt(2 * kPi); };
  return (prim(x + 0.5 * f) - prim(x - 0.5 * f)) / f;
}

TEST(SimKernel, NodesHaveTheKernelsVariance) {
  for (const camera::SamplingKernel k : {camera::SamplingKernel{0.5, 0.3}, camera::SamplingKernel{0.0, 0.7},
                                         camera::SamplingKernel{1.0, 0.2}}) {
    for (const int n : {4, 8, 16}) {
      const std::vector<double> off = KernelNodeOffsets(k, n);
      double mean = 0, var = 0;
      for (double o : off) mean += o / n;
      for (double o : off) var += (o - mean) * (o - mean) / n;
      EXPECT_NEAR(mean, 0.0, 1e-12);
      EXPECT_NEAR(var, k.VariancePx2(), 1e-9);
    }
  }
  // Without a PSF: the box's regular grid; one ray: the pixel centre.
  const std::vector<double> box = KernelNodeOffsets({0.5, 0.0}, 4);
  EXPECT_DOUBLE_EQ(box[0], 0.5 * (0.125 - 0.5));
  EXPECT_EQ(KernelNodeOffsets({1.0, 2.0}, 1), std::vector<double>{0.0});
}

// A plane at 700 mm seen by an ideal camera and lit by a projector at the same centre with the
// same focal length: projector x = camera u + shift on every pixel, whatever the depth.
struct Bench {
  Scene scene;
  PinholeView camera, projector;
  Bench(double shift) {
    scene.planes.push_back({"plane", Vec3(0, 0, 700), Vec3(0, 0, -1), 1.0});
    camera = {{2000.0, 2000.0, 63.5, 15.5, {}, 128, 32}, Isometry3::Identity()};
    projector = {{2000.0, 2000.0, 63.5 + shift, 15.5, {}, 912, 1140}, Isometry3::Identity()};
  }
  // Radiance over the plane's shading (n·l at the pixel centre, closed form).
  double Response(const RenderedView& view, int u, int v, int frame = 0) const {
    const Vec3 x(700.0 * (u - 63.5) / 2000.0, 700.0 * (v - 15.5) / 2000.0, 700.0);
    return view.radiance[frame].at<float>(v, u) / (700.0 / x.norm());
  }
};

TEST(SimKernel, StepEdgeThroughBoxAndGaussianIsItsCdf) {
  // The 1-bit Gray code is a step at projector x = 456 (white right of it): at camera u = 456 −
  // shift = 43.3. A pixel at u reads P(u + s > 43.3) = 1 − CDF(43.3 − u).
  const double shift = 412.7, edge = 456.0 - shift;
  const Bench b(shift);
  const std::vector<PatternFrame> frames = ExpandSequence({GrayCodeBlock(1, false)});
  const int n = 16;
  for (const camera::SamplingKernel k : {camera::SamplingKernel{1.0, 0.0}, camera::SamplingKernel{0.6, 0.0},
                                         camera::SamplingKernel{0.5, 0.5}, camera::SamplingKernel{0.0, 0.8}}) {
    RenderOptions o;
    o.supersampling = n;
    o.kernel = k;
    o.shadows = false;
    const RenderedView view = RenderView(b.scene, b.camera, b.projector, frames, o);
    double worst = 0;
    for (int u = 38; u <= 48; ++u) {
      const double want = 1.0 - BoxGaussCdf(k.fill_factor, k.psf_sigma_px, edge - u);
      worst = std::max(worst, std::abs(b.Response(view, u, 16) - want));
    }
    // n equal-weight nodes per axis resolve the CDF to 1/(2n); the PSF nodes' variance scaling
    // moves them by a few per cent of their spread.
    EXPECT_LT(worst, 1.0 / (2 * n) + 0.01) << k.fill_factor << " " << k.psf_sigma_px;
  }
}

TEST(SimKernel, FringeModulationIsTheKernelsCharacteristicFunction) {
  // A fringe of period P camera px (a linear coordinate) keeps its phase through a symmetric
  // kernel; its modulation falls to sinc(k f / 2)·exp(−k² σ² / 2), k = 2π/P.
  const Bench b(400.0);
  const double cycles = 912.0 / 6.0;  // P = 6 px
  const std::vector<PatternFrame> frames = ExpandSequence({PhaseShiftBlock(4, cycles, 0.0)});
  const double k = 2 * kPi / 6.0;
  for (const camera::SamplingKernel kernel : {camera::SamplingKernel{1.0, 0.0}, camera::SamplingKernel{0.7, 0.4}}) {
    RenderOptions o;
    o.supersampling = 16;
    o.kernel = kernel;
    o.shadows = false;
    const RenderedView view = RenderView(b.scene, b.camera, b.projector, frames, o);
    const double half = 0.5 * k * kernel.fill_factor;
    const double want = std::sin(half) / half * std::exp(-0.5 * k * k * kernel.psf_sigma_px * kernel.psf_sigma_px);
    for (int u = 40; u < 52; ++u) {
      double re = 0, im = 0;
      for (int i = 0; i < 4; ++i) {
        const double r = b.Response(view, u, 16, i);
        re += r * std::cos(2 * kPi * i / 4);
        im -= r * std::sin(2 * kPi * i / 4);
      }
      // I_i = 0.5 + 0.5·m·cos(φ + 2πi/4): Σ I_i e^{−i2πi/4} = m·e^{iφ}.
      const double modulation = std::hypot(re, im);
      const double phase = std::atan2(im, re);
      const double true_phase = 2 * kPi * cycles * (u + 400.0) / 912.0;
      EXPECT_NEAR(modulation, want, 3e-3) << u;
      EXPECT_NEAR(std::remainder(phase - true_phase, 2 * kPi), 0.0, 1e-4) << u;
    }
  }
}

}  // namespace
}  // namespace ramtk::vision
