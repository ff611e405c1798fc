#pragma once
// Test-only analytic fringe synthesis from a known projector-coordinate map (the truth the
// decoder never sees): I = ambient + K * f(pattern), with f = pattern^gamma, a Gaussian
// projector blur at Gray-code edges (and the matching modulation loss of the sinusoids),
// Gaussian intensity noise with a fixed seed, and 8-bit quantisation with clipping.

#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/fringe/patterns.h"

namespace ramtk::vision::testing {

struct SynthOptions {
  int width = 400, height = 300;  // camera image
  double ambient = 20;            // DN
  double gain = 180;              // DN for a white projector pixel
  double gamma = 1.0;             // projector response exponent
  double noise_dn = 1.0;          // Gaussian intensity noise (DN)
  double blur_px = 1.5;           // projector-side Gaussian blur sigma (projector px)
  double full_scale = 255;        // camera quantisation: 255 (8 bit) or 65535 (16 bit)
  unsigned seed = 7;
};

// Smooth truth: projector coordinate (px) per camera pixel, inside [40, 1000) for a 1024 extent.
inline cv::Mat TruthCoordinate(const SynthOptions& o, int extent) {
  cv::Mat u(o.height, o.width, CV_64F);
  const double sx = (extent - 120.0) / o.width;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const double dx = x - o.width / 2.0, dy = y - o.height / 2.0;
      u.at<double>(y, x) = 60 + sx * x * 0.97 + 0.0004 * sx * (dx * dx + dy * dy) + 6 * std::sin(y / 37.0);
    }
  return u;
}

inline double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Frames in the manifest's sequence order (CV_32F, DN, quantised to 8 bit).
inline std::vector<cv::Mat> SynthesizeFrames(const FringeManifest& m, const cv::Mat& truth, const SynthOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> noise(0.0, o.noise_dn);
  const int extent = m.Extent();
  std::vector<cv::Mat> frames;
  auto emit = [&](auto value_at) {
    cv::Mat f(truth.size(), CV_32F);
    for (int y = 0; y < f.rows; ++y)
      for (int x = 0; x < f.cols; ++x) {
        const double p = value_at(truth.at<double>(y, x));  // projected light in [0, 1], gamma and blur applied
        double v = o.ambient + o.gain * p + (o.noise_dn > 0 ? noise(rng) : 0.0);
        f.at<float>(y, x) = static_cast<float>(std::clamp(std::round(v), 0.0, o.full_scale));
      }
    frames.push_back(f);
  };
  for (const SequenceBlock& b : m.sequence) {
    if (b.type == BlockType::kGrayCode) {
      for (int j = 0; j < b.bits; ++j) {
        const double stripe = static_cast<double>(extent) / (1 << (j + 1));  // edges at odd multiples
        emit([&](double u) {
          auto bit = [&](double uu) {
            const int cell = GrayCodeCell(uu, b.bits, extent);
            return static_cast<double>(((cell ^ (cell >> 1)) >> (b.bits - 1 - j)) & 1);
          };
          const double k = std::round((u / stripe - 1) / 2);
          const double edge = (2 * k + 1) * stripe;
          const double left = bit(edge - 1e-6), right = bit(edge + 1e-6);
          return left + (right - left) * NormalCdf((u - edge) / o.blur_px);
        });
      }
      continue;
    }
    for (double cycles : b.cycles) {
      const double period = extent / cycles;
      const double attenuation = std::exp(-0.5 * std::pow(2 * M_PI * o.blur_px / period, 2));
      // Gauss-Hermite nodes/weights (7 points, weights normalised) for blurring a non-linear profile.
      static const double kNodes[7] = {-2.651961356835233, -1.673551628767471, -0.816287882858965, 0.0,
                                       0.816287882858965,  1.673551628767471,  2.651961356835233};
      static const double kWeights[7] = {0.000971781245100, 0.054515582819127, 0.425607252610128, 0.810264617556807,
                                         0.425607252610128, 0.054515582819127, 0.000971781245100};
      for (int k = 0; k < b.steps; ++k)
        emit([&](double u) {
          auto light = [&](double uu) {
            return std::pow(
                0.5 + 0.5 * std::cos(PatternPhase(uu, cycles, extent, b.phase_at_origin_rad) + 2 * M_PI * k / b.steps),
                o.gamma);
          };
          if (o.gamma == 1.0)
            return 0.5 + 0.5 * attenuation *
                             std::cos(PatternPhase(u, cycles, extent, b.phase_at_origin_rad) + 2 * M_PI * k / b.steps);
          // The projector's response comes first, then the optics blur the emitted light.
          double sum = 0, wsum = 0;
          for (int i = 0; i < 7; ++i) {
            sum += kWeights[i] * light(u + std::sqrt(2.0) * o.blur_px * kNodes[i]);
            wsum += kWeights[i];
          }
          return sum / wsum;
        });
    }
  }
  return frames;
}

inline FringeManifest GrayManifest(int steps, double cycles, bool complementary, int extent = 1024) {
  FringeManifest m;
  m.projector_width = extent;
  m.projector_height = 768;
  SequenceBlock ps;
  ps.type = BlockType::kPhaseShift;
  ps.steps = steps;
  ps.cycles = {cycles};
  m.sequence.push_back(ps);
  SequenceBlock gc;
  gc.type = BlockType::kGrayCode;
  gc.bits = static_cast<int>(std::lround(std::log2(cycles))) + (complementary ? 1 : 0);
  gc.complementary = complementary;
  m.sequence.push_back(gc);
  m.cameras["cam"].resize(m.ImageCount());
  return m;
}

inline FringeManifest HeterodyneManifest(int steps, std::vector<double> cycles, int extent = 1024) {
  FringeManifest m;
  m.projector_width = extent;
  m.projector_height = 768;
  SequenceBlock h;
  h.type = BlockType::kHeterodyne;
  h.steps = steps;
  h.cycles = std::move(cycles);
  m.sequence.push_back(h);
  m.cameras["cam"].resize(m.ImageCount());
  return m;
}

// Counts valid pixels whose decoded coordinate is off by more than half a period (order errors)
// and the RMS coordinate error of the others (px).
struct TruthComparison {
  long valid = 0, order_errors = 0;
  double rms_px = 0;
};
inline TruthComparison CompareToTruth(const cv::Mat& coord, const cv::Mat& mask, const cv::Mat& truth, double period) {
  TruthComparison c;
  double ss = 0;
  for (int y = 0; y < coord.rows; ++y)
    for (int x = 0; x < coord.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      ++c.valid;
      const double d = coord.at<float>(y, x) - truth.at<double>(y, x);
      if (std::abs(d) > period / 2) {
        ++c.order_errors;
      } else {
        ss += d * d;
      }
    }
  const long good = c.valid - c.order_errors;
  c.rms_px = good ? std::sqrt(ss / good) : 0;
  return c;
}

}  // namespace ramtk::vision::testing
