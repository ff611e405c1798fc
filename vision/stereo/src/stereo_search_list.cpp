// The match's searched pixels of a row (stereo_search_list.h).
#include "ramtk/vision/stereo/detail/stereo_search_list.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {
namespace {

int ListScalar(const uchar* mask, const float* coord, const float* sigma, const uchar* reach, int x, int width,
               double max_sigma, int* xs, int count, SearchCounts* counts) {
  for (; x < width; ++x) {
    if (!mask[x] || !std::isfinite(coord[x])) continue;
    ++counts->valid;
    if (!(sigma[x] <= max_sigma)) {
      ++counts->noisy;
    } else if (reach && !reach[x]) {
      ++counts->unreachable;
    } else {
      xs[count++] = x;
    }
  }
  return count;
}

// Per byte of set bits: the positions of its set bits, in order (the rest 0), and the bits as
// eight bytes 0 / 1.
struct CompressTable {
  alignas(32) int positions[256][8];
  uchar bytes[256][8];
  CompressTable() {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int i = 0; i < 8; ++i) positions[m][i] = 0, bytes[m][i] = static_cast<uchar>(m >> i & 1);
      for (int i = 0; i < 8; ++i)
        if (m >> i & 1) positions[m][k++] = i;
    }
  }
};
const CompressTable kCompress;

// The largest float t with t <= max_sigma (as doubles): for a float s, s <= t exactly when
// double(s) <= max_sigma. NaN sigmas fail both.
float FloatBound(double max_sigma) {
  if (!(max_sigma == max_sigma)) return std::numeric_limits<float>::quiet_NaN();
  if (max_sigma == std::numeric_limits<double>::infinity()) return std::numeric_limits<float>::infinity();
  if (max_sigma >= static_cast<double>(std::numeric_limits<float>::max())) return std::numeric_limits<float>::max();
  float t = static_cast<float>(max_sigma);
  if (static_cast<double>(t) > max_sigma) t = std::nextafter(t, -std::numeric_limits<float>::infinity());
  return t;
}

// Of eight mask (or reach) bytes, the nonzero ones as bits.
RAMTK_AVX2_INLINE int NonZero8(const uchar* b) {
  const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(b));
  return ~_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128())) & 0xFF;
}

RAMTK_AVX2 int ListAvx2(const uchar* mask, const float* coord, const float* sigma, const uchar* reach, int width,
                        double max_sigma, int* xs, SearchCounts* counts) {
  const __m256 bound = _mm256_set1_ps(FloatBound(max_sigma));
  const __m256i exponent = _mm256_set1_epi32(0x7f800000);
  int count = 0, x = 0;
  for (; x + 8 <= width; x += 8) {
    const int m = NonZero8(mask + x);
    if (!m) continue;
    const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coord + x));
    const int inf_or_nan =
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(c, exponent), exponent)));
    const int valid = m & ~inf_or_nan & 0xFF;
    if (!valid) continue;
    const int calm = _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(sigma + x), bound, _CMP_LE_OQ)) & valid;
    const int reached = reach ? calm & NonZero8(reach + x) : calm;
    counts->valid += __builtin_popcount(static_cast<unsigned>(valid));
    counts->noisy += __builtin_popcount(static_cast<unsigned>(valid & ~calm));
    counts->unreachable += __builtin_popcount(static_cast<unsigned>(calm & ~reached));
    // The columns of the set bits, eight at once (the entries past the count are scratch).
    const __m256i at = _mm256_add_epi32(
        _mm256_set1_epi32(x), _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompress.positions[reached])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(xs + count), at);
    count += __builtin_popcount(static_cast<unsigned>(reached));
  }
  return ListScalar(mask, coord, sigma, reach, x, width, max_sigma, xs, count, counts);
}

// One row of Pass::cell_ok from cell x on, branch-free (the compiler vectorises it): the span
// compared in double as EvalAt compared it.
void CellRowScalar(const float* __restrict r0, const float* __restrict r1, int x, int n, double max_span,
                   uchar* __restrict ok) {
  for (; x < n; ++x) {
    const float c00 = r0[x], c10 = r0[x + 1], c01 = r1[x], c11 = r1[x + 1];
    // x - x is 0 for a finite x and NaN otherwise; min and max are exact in float.
    const bool finite = ((c00 - c00) + (c10 - c10) + (c01 - c01) + (c11 - c11)) == 0.0f;
    const float hi = std::max(std::max(c00, c10), std::max(c01, c11));
    const float lo = std::min(std::min(c00, c10), std::min(c01, c11));
    ok[x] = finite & (static_cast<double>(hi) - static_cast<double>(lo) <= max_span);
  }
}

// std::min / std::max in float: (b < a) ? b : a and (a < b) ? b : a.
RAMTK_AVX2_INLINE __m256 MinF(__m256 a, __m256 b) { return _mm256_blendv_ps(a, b, _mm256_cmp_ps(b, a, _CMP_LT_OQ)); }
RAMTK_AVX2_INLINE __m256 MaxF(__m256 a, __m256 b) { return _mm256_blendv_ps(a, b, _mm256_cmp_ps(a, b, _CMP_LT_OQ)); }

RAMTK_AVX2 void CellRowAvx2(const float* r0, const float* r1, int n, double max_span, uchar* ok) {
  const __m256d span = _mm256_set1_pd(max_span);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const __m256 c00 = _mm256_loadu_ps(r0 + x), c10 = _mm256_loadu_ps(r0 + x + 1);
    const __m256 c01 = _mm256_loadu_ps(r1 + x), c11 = _mm256_loadu_ps(r1 + x + 1);
    const __m256 sum = _mm256_add_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_sub_ps(c00, c00), _mm256_sub_ps(c10, c10)), _mm256_sub_ps(c01, c01)),
        _mm256_sub_ps(c11, c11));
    const int finite = _mm256_movemask_ps(_mm256_cmp_ps(sum, _mm256_setzero_ps(), _CMP_EQ_OQ));
    const __m256 hi = MaxF(MaxF(c00, c10), MaxF(c01, c11)), lo = MinF(MinF(c00, c10), MinF(c01, c11));
    const __m256d d_lo =
        _mm256_sub_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(hi)), _mm256_cvtps_pd(_mm256_castps256_ps128(lo)));
    const __m256d d_hi =
        _mm256_sub_pd(_mm256_cvtps_pd(_mm256_extractf128_ps(hi, 1)), _mm256_cvtps_pd(_mm256_extractf128_ps(lo, 1)));
    const int within = _mm256_movemask_pd(_mm256_cmp_pd(d_lo, span, _CMP_LE_OQ)) |
                       _mm256_movemask_pd(_mm256_cmp_pd(d_hi, span, _CMP_LE_OQ)) << 4;
    const int bits = finite & within;
    std::memcpy(ok + x, &kCompress.bytes[bits], 8);  // the eight bits as eight bytes 0 / 1
  }
  CellRowScalar(r0, r1, x, n, max_span, ok);
}

RAMTK_AVX2 void FillNaNAvx2(float* row, int n) {
  const __m256 nan = _mm256_set1_ps(std::numeric_limits<float>::quiet_NaN());
  int i = 0;
  for (; i + 8 <= n; i += 8) _mm256_storeu_ps(row + i, nan);
  for (; i < n; ++i) row[i] = std::numeric_limits<float>::quiet_NaN();
}

RAMTK_AVX2 void FillNaNAvx2(double* row, int n) {
  const __m256d nan = _mm256_set1_pd(std::numeric_limits<double>::quiet_NaN());
  int i = 0;
  for (; i + 4 <= n; i += 4) _mm256_storeu_pd(row + i, nan);
  for (; i < n; ++i) row[i] = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

void CellRow(const float* r0, const float* r1, int n, double max_span, uchar* ok) {
  if (Avx2Kernels())
    CellRowAvx2(r0, r1, n, max_span, ok);
  else
    CellRowScalar(r0, r1, 0, n, max_span, ok);
}

void FillNaN(float* row, int n) {
  if (Avx2Kernels())
    FillNaNAvx2(row, n);
  else
    std::fill_n(row, n, std::numeric_limits<float>::quiet_NaN());
}

void FillNaN(double* row, int n) {
  if (Avx2Kernels())
    FillNaNAvx2(row, n);
  else
    std::fill_n(row, n, std::numeric_limits<double>::quiet_NaN());
}

int ListSearchedPixels(const uchar* mask, const float* coord, const float* sigma, const uchar* reach, int width,
                       double max_sigma, int* xs, SearchCounts* counts) {
  if (Avx2Kernels()) return ListAvx2(mask, coord, sigma, reach, width, max_sigma, xs, counts);
  return ListScalar(mask, coord, sigma, reach, 0, width, max_sigma, xs, 0, counts);
}

}  // namespace ramtk::vision::detail
