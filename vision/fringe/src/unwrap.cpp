// Gray-code and heterodyne temporal unwrapping with period-edge correction.
#include "ramtk/vision/fringe/unwrap.h"

#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>

#include "ramtk/vision/kernels/fast_round.h"

namespace ramtk::vision {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

using detail::Wrap01;

// Fraction of a beat with `cycles` <= 1 across the projector, wrapped into the interval centred
// on its valid range [0, cycles) so noise at the projector edges does not wrap around.
double WrapBeat(double t, double cycles) {
  const double lo = -(1.0 - cycles) / 2;
  return t - std::floor(t - lo);
}

}  // namespace

double PeriodFraction(double phi, double phase_at_origin_rad) {
  return detail::PeriodFractionOf(phi, phase_at_origin_rad);
}

cv::Mat DecodeGrayCode(const std::vector<cv::Mat>& frames, const cv::Mat& threshold) {
  cv::Mat cells(threshold.size(), CV_32S);
  const int bits = static_cast<int>(frames.size());
  cv::parallel_for_(cv::Range(0, cells.rows), [&](const cv::Range& range) {
    for (int y = range.start; y < range.end; ++y) {
      const float* th = threshold.ptr<float>(y);
      int* out = cells.ptr<int>(y);
      for (int x = 0; x < cells.cols; ++x) {
        int binary = 0, bit = 0;
        for (int j = 0; j < bits; ++j) {
          bit ^= frames[j].ptr<float>(y)[x] > th[x] ? 1 : 0;  // Gray -> binary: running XOR
          binary = (binary << 1) | bit;
        }
        out[x] = binary;
      }
    }
  });
  return cells;
}

UnwrapResult UnwrapGrayCode(const cv::Mat& wrapped, double phase_at_origin_rad, double cycles, int extent,
                            const cv::Mat& cells, int bits, bool complementary) {
  UnwrapResult r;
  r.coordinate.create(wrapped.size(), CV_32F);
  r.valid.create(wrapped.size(), CV_8U);
  const double period = extent / cycles;
  std::vector<long> corrected(wrapped.rows, 0), rejected(wrapped.rows, 0);
  cv::parallel_for_(cv::Range(0, wrapped.rows), [&](const cv::Range& range) {
    for (int y = range.start; y < range.end; ++y) {
      const float* phi = wrapped.ptr<float>(y);
      const int* cell = cells.ptr<int>(y);
      float* u = r.coordinate.ptr<float>(y);
      uchar* ok = r.valid.ptr<uchar>(y);
      for (int x = 0; x < wrapped.cols; ++x) {
        const double t = PeriodFraction(phi[x], phase_at_origin_rad);
        long n;
        if (complementary) {
          const double centre = (cell[x] + 0.5) / 2.0;  // half-period cell centre, in periods
          n = std::lround(centre - t);
          if (n != (cell[x] >> 1)) ++corrected[y];
        } else {
          n = cell[x];
        }
        const double coord = (n + t) * period;
        if (coord < -0.5 || coord >= extent - 0.5) {  // outside the projector's pixel centres
          u[x] = kNaN;
          ok[x] = 0;
          ++rejected[y];
        } else {
          u[x] = static_cast<float>(coord);
          ok[x] = 255;
        }
      }
    }
  });
  (void)bits;
  for (int y = 0; y < wrapped.rows; ++y) r.corrected += corrected[y], r.rejected += rejected[y];
  return r;
}

UnwrapResult UnwrapHeterodyne(const std::vector<cv::Mat>& wrapped, const std::vector<double>& cycles,
                              double phase_at_origin_rad, int extent, double max_order_residual) {
  CV_Assert(wrapped.size() == cycles.size() && (cycles.size() == 2 || cycles.size() == 3));
  UnwrapResult r;
  const cv::Size size = wrapped[0].size();
  r.coordinate.create(size, CV_32F);
  r.valid.create(size, CV_8U);
  const bool three = cycles.size() == 3;
  const double c1 = cycles[0], c2 = cycles[1], c3 = three ? cycles[2] : 0;
  const double c12 = c1 - c2, c23 = c2 - c3, c123 = c12 - c23;
  const double period = extent / c1;
  std::vector<long> corrected(size.height, 0), rejected(size.height, 0);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& range) {
    for (int y = range.start; y < range.end; ++y) {
      float* u = r.coordinate.ptr<float>(y);
      uchar* ok = r.valid.ptr<uchar>(y);
      for (int x = 0; x < size.width; ++x) {
        const double t1 = PeriodFraction(wrapped[0].ptr<float>(y)[x], phase_at_origin_rad);
        const double t2 = PeriodFraction(wrapped[1].ptr<float>(y)[x], phase_at_origin_rad);
        const double t12 = Wrap01(t1 - t2);  // beat of c12 cycles
        double big12 = t12, worst = 0;
        if (three) {
          const double t3 = PeriodFraction(wrapped[2].ptr<float>(y)[x], phase_at_origin_rad);
          const double t23 = Wrap01(t2 - t3);
          const double t123 = WrapBeat(t12 - t23, c123);  // c123 <= 1 cycle: absolute
          const double e12 = t123 * c12 / c123 - t12;
          big12 = t12 + std::round(e12);
          worst = std::abs(e12 - std::round(e12));
        } else {
          big12 = WrapBeat(t1 - t2, c12);  // c12 <= 1 cycle: absolute
        }
        const double e1 = big12 * c1 / c12 - t1;
        const double n = std::round(e1);
        worst = std::max(worst, std::abs(e1 - n));
        const double coord = (t1 + n) * period;
        if (worst > max_order_residual || coord < -0.5 || coord >= extent - 0.5) {
          u[x] = kNaN;
          ok[x] = 0;
          ++rejected[y];
        } else {
          u[x] = static_cast<float>(coord);
          ok[x] = 255;
        }
      }
    }
  });
  for (int y = 0; y < size.height; ++y) r.corrected += corrected[y], r.rejected += rejected[y];
  return r;
}

}  // namespace ramtk::vision
