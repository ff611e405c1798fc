// The match's searched pixels of a row (stereo_search_list.h).
#include "stereo_search_list.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "avx2.h"

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

// Per byte of set bits: the positions of its set bits, in order (the rest 0).
struct CompressTable {
  alignas(32) int positions[256][8];
  CompressTable() {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int i = 0; i < 8; ++i) positions[m][i] = 0;
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
