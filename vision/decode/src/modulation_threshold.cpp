// ModulationRule::kSigma (decode.h): the threshold on a pixel's modulation B below which its
// phase is not usable given its own noise, and its application to a decoded mask. Both decode
// paths (decode_fast.cpp, decode_reference.cpp) call the same functions.
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/fringe/codec.h"

namespace ramtk::vision::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Upper tail of the standard normal, P(Z > z).
double UpperTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

}  // namespace

OrderDecision OrderDecisionOf(const FringeManifest& m) {
  OrderDecision d;
  for (const SequenceBlock& b : m.sequence) {
    if (CodecOf(b).role == CodecRole::kOrder) {
      d.gray_bits = b.bits;
      d.complementary = b.complementary;
    } else if (b.type == BlockType::kHeterodyne && b.cycles.size() >= 2 && b.cycles[0] > b.cycles[1]) {
      d.heterodyne_ratio = b.cycles[0] / (b.cycles[0] - b.cycles[1]);
    }
  }
  return d;
}

double OrderErrorProbability(const OrderDecision& d, int n, double b_over_sigma) {
  if (!(b_over_sigma > 0)) return 1.0;
  const double sigma_phi = std::sqrt(2.0 / n) / b_over_sigma;
  double p = 0;
  if (d.gray_bits > 0) {
    p += d.gray_bits * UpperTail(d.gray_contrast * b_over_sigma / std::sqrt(1.0 + 1.0 / n));
    if (d.complementary) p += 2 * UpperTail(kPi / 2 / sigma_phi);
  }
  if (d.heterodyne_ratio > 0) {
    const double sigma_periods = sigma_phi * std::sqrt(1 + 2 * d.heterodyne_ratio * d.heterodyne_ratio) / (2 * kPi);
    p += 2 * UpperTail(0.5 / sigma_periods);
  }
  return std::min(p, 1.0);
}

double GrayContrastRatio(const std::vector<const cv::Mat*>& ps_frames, const std::vector<const cv::Mat*>& gray_frames,
                         const cv::Mat& sample, int stride) {
  if (gray_frames.empty() || ps_frames.empty()) return 1.0;
  auto at = [](const cv::Mat& m, int y, int x) -> double {
    switch (m.depth()) {
      case CV_8U:
        return m.at<uchar>(y, x);
      case CV_16U:
        return m.at<ushort>(y, x);
      default:
        return m.at<float>(y, x);
    }
  };
  const int n = static_cast<int>(ps_frames.size());
  stride = std::max(1, stride);
  std::vector<double> ratios, bits(gray_frames.size()), sn(n), cs(n);
  for (int k = 0; k < n; ++k) sn[k] = std::sin(2 * kPi * k / n), cs[k] = std::cos(2 * kPi * k / n);
  for (int y = 0; y < sample.rows; y += stride) {
    const uchar* mk = sample.ptr<uchar>(y);
    for (int x = 0; x < sample.cols; x += stride) {
      if (!mk[x]) continue;
      double sum = 0, s = 0, c = 0;
      for (int k = 0; k < n; ++k) {
        const double v = at(*ps_frames[k], y, x);
        sum += v;
        s += v * sn[k];
        c += v * cs[k];
      }
      const double a = sum / n, b = 2.0 / n * std::sqrt(s * s + c * c);
      if (!(b > 0)) continue;
      for (std::size_t j = 0; j < gray_frames.size(); ++j) bits[j] = std::abs(at(*gray_frames[j], y, x) - a);
      std::nth_element(bits.begin(), bits.begin() + bits.size() / 2, bits.end());
      ratios.push_back(bits[bits.size() / 2] / b);
    }
  }
  if (ratios.size() < 100) return 1.0;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return ratios[ratios.size() / 2];
}

ModulationThreshold SigmaModulationThreshold(const OrderDecision& d, int n, double sigma_i,
                                             const DecodeOptions& options) {
  const double sigma = std::max(sigma_i, 1.0 / std::sqrt(12.0));
  ModulationThreshold t;
  t.floor_dn = options.noise_floor_factor * std::sqrt(2.0 / n) * sigma;
  // OrderErrorProbability falls with B / sigma: bisection for the ratio where it meets the option.
  double lo = 0, hi = 64;
  if (OrderErrorProbability(d, n, hi) > options.max_order_error_probability) {
    lo = hi;  // not reachable: a threshold no pixel passes in practice
  } else {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (OrderErrorProbability(d, n, mid) > options.max_order_error_probability ? lo : hi) = mid;
    }
    lo = hi;
  }
  t.threshold_dn = std::max(t.floor_dn, lo * sigma);
  return t;
}

cv::Mat NoiseSampleMask(const cv::Mat& mask, const cv::Mat& modulation, float b_sample) {
  if (!(b_sample > 0)) return mask;
  cv::Mat strong;
  cv::compare(modulation, b_sample, strong, cv::CMP_GE);
  cv::Mat sample;
  cv::bitwise_and(mask, strong, sample);
  return sample;
}

long ApplyModulationThreshold(const ModulationThreshold& t, const cv::Mat& modulation, cv::Mat& mask,
                              cv::Mat& coordinate, long* dark, long* low) {
  struct Counts {
    long dark = 0, low = 0;
  };
  const float threshold = static_cast<float>(t.threshold_dn), floor = static_cast<float>(t.floor_dn);
  const Counts total = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, mask.rows, 16), Counts{},
      [&](const tbb::blocked_range<int>& r, Counts acc) {
        for (int y = r.begin(); y < r.end(); ++y) {
          uchar* mk = mask.ptr<uchar>(y);
          const float* b = modulation.ptr<float>(y);
          float* coord = coordinate.ptr<float>(y);
          for (int x = 0; x < mask.cols; ++x) {
            if (!mk[x] || b[x] >= threshold) continue;
            mk[x] = 0;
            coord[x] = std::numeric_limits<float>::quiet_NaN();
            ++(b[x] < floor ? acc.dark : acc.low);
          }
        }
        return acc;
      },
      [](Counts a, const Counts& b) {
        a.dark += b.dark;
        a.low += b.low;
        return a;
      });
  *dark += total.dark;
  *low += total.low;
  return total.dark + total.low;
}

}  // namespace ramtk::vision::detail
