// The harmonic ratios of the fast decode path (decode_internal.h MeasureHarmonicRatiosFast): the
// DFT of every sampled pixel's phase-shift samples, rows in parallel and summed in row order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {
namespace {

// rh[j] += v[j] c and ih[j] += v[j] s for j < n: the harmonic ratios' DFT along a row (the
// compiler vectorises it; in the AVX2 copy on four lanes, the same products and sums).
__attribute__((always_inline)) inline void AddScaledPairBody(const double* __restrict v, double c, double s, int n,
                                                             double* __restrict rh, double* __restrict ih) {
  for (int j = 0; j < n; ++j) rh[j] += v[j] * c, ih[j] += v[j] * s;
}
void AddScaledPair(const double* v, double c, double s, int n, double* rh, double* ih) {
  AddScaledPairBody(v, c, s, n, rh, ih);
}
RAMTK_AVX2 void AddScaledPairAvx2(const double* v, double c, double s, int n, double* rh, double* ih) {
  AddScaledPairBody(v, c, s, n, rh, ih);
}

template <typename T>
std::vector<double> HarmonicRatiosSubsampled(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                                             int stride) {
  const int n = static_cast<int>(frames.size());
  std::vector<double> ratios;
  const int max_h = (n + 1) / 2 - 1;
  if (n < 5 || max_h < 2) return ratios;
  // Twiddle table e^{-i 2 pi h k / n}.
  std::vector<double> tc((max_h + 1) * n), ts((max_h + 1) * n);
  for (int h = 1; h <= max_h; ++h)
    for (int k = 0; k < n; ++k) {
      tc[h * n + k] = std::cos(2 * CV_PI * h * k / n);
      ts[h * n + k] = -std::sin(2 * CV_PI * h * k / n);
    }
  // Per sampled row: its sums and count (rows in parallel, added in row order: deterministic).
  const int rows = (mask.rows + stride - 1) / stride;
  const bool avx2 = Avx2Kernels();
  std::vector<double> row_sum(static_cast<std::size_t>(rows) * (max_h + 1), 0.0);
  std::vector<long> row_count(rows, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 4), [&](const tbb::blocked_range<int>& r) {
    // The row's valid samples gathered per frame, then each harmonic's DFT over the frames as
    // loops along the row (vectorised).
    // Per thread (each harmonic's row is cleared before its sums): not allocated and zeroed per task.
    thread_local std::vector<double> v, re, im;
    thread_local std::vector<int> xs;
    re.resize(static_cast<std::size_t>(max_h + 1) * mask.cols);
    im.resize(re.size());
    for (int i = r.begin(); i < r.end(); ++i) {
      const int y = i * stride;
      const uchar* m = mask.ptr<uchar>(y);
      xs.clear();
      for (int x = 0; x < mask.cols; x += stride)
        if (m[x]) xs.push_back(x);
      const int cnt = static_cast<int>(xs.size());
      if (cnt == 0) continue;
      v.resize(static_cast<std::size_t>(n) * cnt);
      for (int k = 0; k < n; ++k) {
        const T* f = frames[k]->ptr<T>(y);
        double* vk = v.data() + static_cast<std::size_t>(k) * cnt;
        for (int j = 0; j < cnt; ++j) vk[j] = f[xs[j]];
      }
      for (int h = 1; h <= max_h; ++h) {
        double* rh = re.data() + h * cnt;
        double* ih = im.data() + h * cnt;
        std::fill(rh, rh + cnt, 0.0);
        std::fill(ih, ih + cnt, 0.0);
        for (int k = 0; k < n; ++k) {
          const double c = tc[h * n + k], sn = ts[h * n + k];
          const double* vk = v.data() + static_cast<std::size_t>(k) * cnt;
          (avx2 ? AddScaledPairAvx2 : AddScaledPair)(vk, c, sn, cnt, rh, ih);
        }
      }
      double* sum = row_sum.data() + static_cast<std::size_t>(i) * (max_h + 1);
      long count = 0;
      for (int j = 0; j < cnt; ++j) {
        const double r1 = re[cnt + j], i1 = im[cnt + j];
        const double a1 = std::sqrt(r1 * r1 + i1 * i1);
        if (!(a1 > 0)) continue;
        // unit = conj(c1) / |c1| = e^{-i phi}; sum_h += Re(c_h * unit^h) / |c1|.
        const double ur = r1 / a1, ui = -i1 / a1;
        double rr = ur, ri = ui;
        for (int h = 2; h <= max_h; ++h) {
          const double nr = rr * ur - ri * ui, ni = rr * ui + ri * ur;
          rr = nr;
          ri = ni;
          sum[h] += (re[h * cnt + j] * rr - im[h * cnt + j] * ri) / a1;
        }
        ++count;
      }
      row_count[i] = count;
    }
  });
  std::vector<double> sum(max_h + 1, 0.0);
  long count = 0;
  for (int i = 0; i < rows; ++i) {
    for (int h = 2; h <= max_h; ++h) sum[h] += row_sum[static_cast<std::size_t>(i) * (max_h + 1) + h];
    count += row_count[i];
  }
  for (int h = 2; h <= max_h; ++h) ratios.push_back(count ? sum[h] / count : 0.0);
  return ratios;
}

}  // namespace

std::vector<double> MeasureHarmonicRatiosFast(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                                              int stride) {
  switch (frames[0]->depth()) {
    case CV_8U:
      return HarmonicRatiosSubsampled<uchar>(frames, mask, stride);
    case CV_16U:
      return HarmonicRatiosSubsampled<ushort>(frames, mask, stride);
    default:
      return HarmonicRatiosSubsampled<float>(frames, mask, stride);
  }
}

}  // namespace ramtk::vision::detail
