// Eight cells of the back-match reach on AVX2 lanes (back_reach_lanes.h). Float operations as
// the scalar loop takes them; std::min / std::max as blends (their order on ties); the quick
// bilinear bound in double, as Sq.
#include "ramtk/vision/stereo/detail/back_reach_lanes.h"

#include <immintrin.h>

#include <initializer_list>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {
namespace {

// std::min(a, b) = (b < a) ? b : a; std::max(a, b) = (a < b) ? b : a.
RAMTK_AVX2_INLINE __m256 Min(__m256 a, __m256 b) { return _mm256_blendv_ps(a, b, _mm256_cmp_ps(b, a, _CMP_LT_OQ)); }
RAMTK_AVX2_INLINE __m256 Max(__m256 a, __m256 b) { return _mm256_blendv_ps(a, b, _mm256_cmp_ps(a, b, _CMP_LT_OQ)); }
RAMTK_AVX2_INLINE __m256 Finite(__m256 a) {
  return _mm256_cmp_ps(_mm256_sub_ps(a, a), _mm256_setzero_ps(), _CMP_EQ_OQ);
}
RAMTK_AVX2_INLINE __m256 Load(const float* p) { return _mm256_loadu_ps(p); }

// Sq(a) + Sq(b) < 15.9 in double, of eight float differences.
RAMTK_AVX2_INLINE int QuickBilinear(__m256 a, __m256 b) {
  const __m256d lo_a = _mm256_cvtps_pd(_mm256_castps256_ps128(a)), hi_a = _mm256_cvtps_pd(_mm256_extractf128_ps(a, 1));
  const __m256d lo_b = _mm256_cvtps_pd(_mm256_castps256_ps128(b)), hi_b = _mm256_cvtps_pd(_mm256_extractf128_ps(b, 1));
  const __m256d bound = _mm256_set1_pd(15.9);
  const int lo = _mm256_movemask_pd(
      _mm256_cmp_pd(_mm256_add_pd(_mm256_mul_pd(lo_a, lo_a), _mm256_mul_pd(lo_b, lo_b)), bound, _CMP_LT_OQ));
  const int hi = _mm256_movemask_pd(
      _mm256_cmp_pd(_mm256_add_pd(_mm256_mul_pd(hi_a, hi_a), _mm256_mul_pd(hi_b, hi_b)), bound, _CMP_LT_OQ));
  return lo | hi << 4;
}

RAMTK_AVX2 void ReachBoxesAvx2(const float* bu0, const float* bu1, const float* bv0, const float* bv1, const float* s0,
                               const float* s1, int u, float lr_tolerance, float factor, float slack, int src_cols,
                               int src_rows, ReachBoxes* out) {
  const __m256 a0 = Load(bu0 + u), a1 = Load(bu0 + u + 1), a2 = Load(bu1 + u), a3 = Load(bu1 + u + 1);
  const __m256 b0 = Load(bv0 + u), b1 = Load(bv0 + u + 1), b2 = Load(bv1 + u), b3 = Load(bv1 + u + 1);
  const __m256 finite =
      _mm256_and_ps(_mm256_and_ps(_mm256_and_ps(Finite(a0), Finite(a1)), _mm256_and_ps(Finite(a2), Finite(a3))),
                    _mm256_and_ps(_mm256_and_ps(Finite(b0), Finite(b1)), _mm256_and_ps(Finite(b2), Finite(b3))));
  const int all = _mm256_movemask_ps(finite);
  if (!all) {
    out->fast = out->has = 0;
    return;
  }
  const __m256 umin = Min(Min(a0, a1), Min(a2, a3)), umax = Max(Max(a0, a1), Max(a2, a3));
  const __m256 vmin = Min(Min(b0, b1), Min(b2, b3)), vmax = Max(Max(b0, b1), Max(b2, b3));
  const int fast = all & QuickBilinear(_mm256_sub_ps(umax, umin), _mm256_sub_ps(vmax, vmin));
  __m256 tolerance = _mm256_set1_ps(lr_tolerance);
  if (s0) {
    const __m256 f = _mm256_set1_ps(factor);
    for (const __m256 s : {Load(s0 + u), Load(s0 + u + 1), Load(s1 + u), Load(s1 + u + 1)})
      tolerance = _mm256_blendv_ps(tolerance, Max(tolerance, _mm256_mul_ps(f, s)), Finite(s));
  }
  const __m256 t = _mm256_add_ps(tolerance, _mm256_set1_ps(slack));
  const __m256 lo_u = _mm256_sub_ps(umin, t), hi_u = _mm256_add_ps(umax, t);
  const __m256 lo_v = _mm256_sub_ps(vmin, t), hi_v = _mm256_add_ps(vmax, t);
  // pixels(): some pixel inside the image, then the box clamped to it.
  const __m256 zero = _mm256_setzero_ps();
  const __m256 last_x = _mm256_set1_ps(static_cast<float>(src_cols - 1)),
               last_y = _mm256_set1_ps(static_cast<float>(src_rows - 1));
  const __m256 inside =
      _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(hi_u, zero, _CMP_GE_OQ), _mm256_cmp_ps(hi_v, zero, _CMP_GE_OQ)),
                    _mm256_and_ps(_mm256_cmp_ps(lo_u, last_x, _CMP_LE_OQ), _mm256_cmp_ps(lo_v, last_y, _CMP_LE_OQ)));
  const __m256i x0 = _mm256_cvttps_epi32(_mm256_ceil_ps(Max(lo_u, zero)));
  const __m256i x1 = _mm256_cvttps_epi32(_mm256_floor_ps(Min(hi_u, last_x)));
  const __m256i y0 = _mm256_cvttps_epi32(_mm256_ceil_ps(Max(lo_v, zero)));
  const __m256i y1 = _mm256_cvttps_epi32(_mm256_floor_ps(Min(hi_v, last_y)));
  const __m256i nonempty = _mm256_andnot_si256(_mm256_or_si256(_mm256_cmpgt_epi32(x0, x1), _mm256_cmpgt_epi32(y0, y1)),
                                               _mm256_set1_epi32(-1));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out->x0), x0);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out->x1), x1);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out->y0), y0);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out->y1), y1);
  out->fast = fast;
  out->has = fast & _mm256_movemask_ps(inside) & _mm256_movemask_ps(_mm256_castsi256_ps(nonempty));
}

}  // namespace

void ReachBoxesOfEight(const float* bu0, const float* bu1, const float* bv0, const float* bv1, const float* s0,
                       const float* s1, int u, float lr_tolerance, float factor, float slack, int src_cols,
                       int src_rows, ReachBoxes* out) {
  ReachBoxesAvx2(bu0, bu1, bv0, bv1, s0, s1, u, lr_tolerance, factor, slack, src_cols, src_rows, out);
}

}  // namespace ramtk::vision::detail
