// A fringe set and an edge image written from the physics alone, for the tests of the camera's
// sampling kernel (fringe diagnosis, kernel estimation): a projector of sharp box pixels (Gray-code
// edges on its pixel boundaries, half a pixel before the coded cell's first pixel centre) seen by a
// camera whose pixel response is a box of side `fill` camera px convolved with an isotropic Gaussian
// PSF of `psf` camera px. The projector coordinate is linear over each pixel, so a step edge seen
// through the kernel is the closed form of the double integral of the normal CDF over the box
// (EdgeResponse); neither the vision simulator nor the diagnosis's model is used.
#pragma once

#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::test_kernel {

constexpr double kPi = 3.14159265358979323846;

inline double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
inline double NormalPdf(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi); }

// First and second antiderivatives of Φ(t/σ) (σ > 0).
inline double G1(double t, double s) { return t * NormalCdf(t / s) + s * NormalPdf(t / s); }
inline double G2(double t, double s) { return 0.5 * (t * t + s * s) * NormalCdf(t / s) + 0.5 * t * s * NormalPdf(t / s); }

// A unit step at t = 0 seen at offset d through a box of width a, a second box of width b (the
// other image axis) and a Gaussian of std dev s, all along t: (1/ab)∬Φ((d + x + y)/s) dx dy.
inline double EdgeResponse(double d, double a, double b, double s) {
  s = std::max(s, 1e-6);
  if (a < 1e-6 && b < 1e-6) return NormalCdf(d / s);
  if (a < 1e-6 || b < 1e-6) {
    const double w = std::max(a, b);
    return (G1(d + w / 2, s) - G1(d - w / 2, s)) / w;
  }
  return (G2(d + a / 2 + b / 2, s) - G2(d + a / 2 - b / 2, s) - G2(d - a / 2 + b / 2, s) + G2(d - a / 2 - b / 2, s)) /
         (a * b);
}

struct PhysicsSet {
  vision::FringeManifest manifest;
  std::vector<cv::Mat> frames;  // CV_32F, 8-bit DN values
};

// A 12-step, 64-period phase shift and a 7-bit complementary Gray code (rendered as a 7-bit Gray code) on a 1280-px projector, seen on a plane
// whose projector coordinate is u = 640 + g·(x − 320) + 0.04·y + 1e-4·(x − 320)² (g projector px per
// camera px; g < 0.5 puts the projector's half pixel beyond one camera pixel), albedo varying slowly,
// read + shot noise and 8-bit rounding.
inline PhysicsSet RenderFringes(double fill, double psf, double g, unsigned seed) {
  const int width = 640, height = 240, extent = 1280, steps = 12, bits = 7;
  const double cycles = 64, period = extent / cycles, phase0 = -kPi, cell = extent / double(1 << bits);
  PhysicsSet out;
  out.manifest.projector_width = extent;
  out.manifest.projector_height = 800;
  out.manifest.direction = vision::FringeDirection::kVertical;
  out.manifest.sequence = {vision::PhaseShiftBlock(steps, cycles, phase0), vision::GrayCodeBlock(bits, true)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int f = 0; f < steps + bits; ++f) {
    out.manifest.cameras["left"].push_back(std::to_string(f) + ".png");
    out.frames.emplace_back(height, width, CV_32F);
  }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double u = 640 + g * (x - 320.0) + 0.04 * y + 1e-4 * (x - 320.0) * (x - 320.0);
      const double gx = g + 2e-4 * (x - 320.0), gy = 0.04;
      const double a = fill * std::abs(gx), b = fill * std::abs(gy), s = psf * std::hypot(gx, gy);
      const double albedo = 0.65 + 0.2 * std::sin(x / 97.0 + 0.4) * std::cos(y / 61.0);
      const double bright = 170.0 * albedo, ambient = 0.08 * bright;
      // The kernel attenuates the fringe (box: sinc per axis, PSF: Gaussian) and leaves its phase.
      const auto sinc = [](double v) { return std::abs(v) < 1e-12 ? 1.0 : std::sin(v) / v; };
      const double attenuation = sinc(kPi * a / period) * sinc(kPi * b / period) *
                                 std::exp(-2.0 * kPi * kPi * s * s / (period * period));
      for (int f = 0; f < steps + bits; ++f) {
        double pattern;
        if (f < steps) {
          pattern = 0.5 + 0.5 * attenuation * std::cos(2 * kPi * cycles * u / extent + phase0 + 2 * kPi * f / steps);
        } else {
          // Value of Gray bit j through the kernel: the bit of the cell left of the window plus
          // each jump within reach times the step response; edges at c·cell − 0.5.
          const int j = f - steps;
          const auto bit = [&](long c) {
            c = std::clamp<long>(c, 0, (1L << bits) - 1);
            return static_cast<double>(((c ^ (c >> 1)) >> (bits - 1 - j)) & 1L);
          };
          const long c0 = static_cast<long>(std::floor((u + 0.5) / cell));
          pattern = bit(c0 - 3);
          for (long c = c0 - 2; c <= c0 + 3; ++c) {
            const double jump = bit(c) - bit(c - 1);
            if (jump != 0) pattern += jump * EdgeResponse(u - (c * cell - 0.5), a, b, s);
          }
        }
        const double mean = ambient + bright * pattern;
        const double noisy = mean + std::sqrt(0.3 + 0.025 * mean) * normal(rng);
        out.frames[f].at<float>(y, x) = static_cast<float>(std::clamp(std::round(noisy), 0.0, 255.0));
      }
    }
  return out;
}

}  // namespace ramtk::test_kernel
