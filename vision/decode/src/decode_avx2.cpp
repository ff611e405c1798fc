// AVX2 row kernels of the fused decode (decode_avx2.h). Each function carries its own target
// attribute; the file is compiled for the baseline like every other, so nothing here runs on a
// CPU without AVX2 (Avx2Kernels decides), and no inline function of a shared header is
// instantiated with AVX2 code. No FMA target: the compiler cannot contract a product and a sum,
// so each lane rounds exactly as the 128-bit kernels do.
#include "ramtk/vision/decode/detail/decode_avx2.h"

#include <immintrin.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace ramtk::vision::detail {
namespace {

// Eight 0/1 bytes from the low eight bits of a movemask.
constexpr std::array<std::uint64_t, 256> MakeByteMasks() {
  std::array<std::uint64_t, 256> t{};
  for (int m = 0; m < 256; ++m)
    for (int j = 0; j < 8; ++j)
      if (m >> j & 1) t[m] |= std::uint64_t{1} << (8 * j);
  return t;
}
constexpr std::array<std::uint64_t, 256> kByteMasks = MakeByteMasks();

// flags[0..8) |= the lanes of `mask` as 0/1 bytes.
RAMTK_AVX2_INLINE void OrFlags(uchar* flags, __m256 mask) {
  std::uint64_t bytes;
  std::memcpy(&bytes, flags, sizeof bytes);
  bytes |= kByteMasks[static_cast<unsigned>(_mm256_movemask_ps(mask))];
  std::memcpy(flags, &bytes, sizeof bytes);
}

// The lane selects of the 128-bit kernels: mask ? a : b.
RAMTK_AVX2_INLINE __m256d Select(__m256d mask, __m256d a, __m256d b) { return _mm256_blendv_pd(b, a, mask); }
RAMTK_AVX2_INLINE __m256d K(double v) { return _mm256_set1_pd(v); }

// Atan2x2 (fast_atan2.h) on four lanes, operation for operation.
RAMTK_AVX2_INLINE __m256d Atan2x4(__m256d y, __m256d x) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kTanPiOver8 = 0.41421356237309504880;
  const __m256d zero = _mm256_setzero_pd();
  const __m256d sign = _mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull)));
  const __m256d ax = _mm256_andnot_pd(sign, x), ay = _mm256_andnot_pd(sign, y);
  const __m256d swap = _mm256_cmp_pd(ay, ax, _CMP_GT_OQ);
  const __m256d lo = Select(swap, ax, ay), hi = Select(swap, ay, ax);
  const __m256d t = Select(_mm256_cmp_pd(hi, zero, _CMP_GT_OQ), _mm256_div_pd(lo, hi), zero);
  const __m256d fold = _mm256_cmp_pd(t, K(kTanPiOver8), _CMP_GT_OQ);
  const __m256d u = Select(fold, _mm256_div_pd(_mm256_sub_pd(t, K(1.0)), _mm256_add_pd(t, K(1.0))), t);
  const __m256d u2 = _mm256_mul_pd(u, u);
  __m256d p = K(1.0 / 25);
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 23));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0 / 21));
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 19));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0 / 17));
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 15));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0 / 13));
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 11));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0 / 9));
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 7));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0 / 5));
  p = _mm256_sub_pd(_mm256_mul_pd(p, u2), K(1.0 / 3));
  p = _mm256_add_pd(_mm256_mul_pd(p, u2), K(1.0));
  __m256d r = _mm256_add_pd(Select(fold, K(kPi / 4), zero), _mm256_mul_pd(u, p));
  r = Select(swap, _mm256_sub_pd(K(kPi / 2), r), r);
  const __m256i sign_i = _mm256_castpd_si256(sign);
  const __m256d x_negative =
      _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(_mm256_castpd_si256(x), sign_i), sign_i));
  r = Select(x_negative, _mm256_sub_pd(K(kPi), r), r);
  return _mm256_xor_pd(r, _mm256_and_pd(y, sign));
}

// The low and high four floats of v as doubles.
RAMTK_AVX2_INLINE __m256d Low(__m256 v) { return _mm256_cvtps_pd(_mm256_castps256_ps128(v)); }
RAMTK_AVX2_INLINE __m256d High(__m256 v) { return _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1)); }
// Two four-double vectors rounded to one eight-float vector (low lanes from `lo`).
RAMTK_AVX2_INLINE __m256 Floats(__m256d lo, __m256d hi) {
  return _mm256_set_m128(_mm256_cvtpd_ps(hi), _mm256_cvtpd_ps(lo));
}

}  // namespace

RAMTK_AVX2 int AccumulateRowU8Avx2(const uchar* const* rows, int n, int width, const float* sn, const float* cs,
                                   float* s, float* c, float* sum, float* sum2, float* top) {
  int x = 0;
  const __m256 minus_inf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  // Sixteen pixels per step, their five sums in registers over all frames.
  for (; x + 16 <= width; x += 16) {
    __m256 vs[2], vc[2], va[2], va2[2], vt[2];
    for (int h = 0; h < 2; ++h) {
      vs[h] = vc[h] = va[h] = va2[h] = _mm256_setzero_ps();
      vt[h] = minus_inf;
    }
    for (int k = 0; k < n; ++k) {
      const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rows[k] + x));
      const __m256 v[2] = {_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(bytes)),
                           _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_srli_si128(bytes, 8)))};
      const __m256 sk = _mm256_set1_ps(sn[k]), ck = _mm256_set1_ps(cs[k]);
      for (int h = 0; h < 2; ++h) {
        vs[h] = _mm256_add_ps(vs[h], _mm256_mul_ps(v[h], sk));
        vc[h] = _mm256_add_ps(vc[h], _mm256_mul_ps(v[h], ck));
        va[h] = _mm256_add_ps(va[h], v[h]);
        va2[h] = _mm256_add_ps(va2[h], _mm256_mul_ps(v[h], v[h]));
        vt[h] = _mm256_max_ps(vt[h], v[h]);
      }
    }
    for (int h = 0; h < 2; ++h) {
      _mm256_storeu_ps(s + x + 8 * h, vs[h]);
      _mm256_storeu_ps(c + x + 8 * h, vc[h]);
      _mm256_storeu_ps(sum + x + 8 * h, va[h]);
      _mm256_storeu_ps(sum2 + x + 8 * h, va2[h]);
      _mm256_storeu_ps(top + x + 8 * h, vt[h]);
    }
  }
  return x;
}

RAMTK_AVX2 int AccumulateRowU16Avx2(const std::uint16_t* const* rows, int n, int width, const float* sn,
                                    const float* cs, float* s, float* c, double* sum, double* sum2, float* top) {
  int x = 0;
  const __m256 minus_inf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  // Eight pixels per step: S, C and the maximum in float, the sums of I and I^2 in double.
  for (; x + 8 <= width; x += 8) {
    __m256 vs = _mm256_setzero_ps(), vc = _mm256_setzero_ps(), vt = minus_inf;
    __m256d va[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()}, va2[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()};
    for (int k = 0; k < n; ++k) {
      const __m256i i32 = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(rows[k] + x)));
      const __m256 v = _mm256_cvtepi32_ps(i32);
      vs = _mm256_add_ps(vs, _mm256_mul_ps(v, _mm256_set1_ps(sn[k])));
      vc = _mm256_add_ps(vc, _mm256_mul_ps(v, _mm256_set1_ps(cs[k])));
      vt = _mm256_max_ps(vt, v);
      const __m256d a[2] = {_mm256_cvtepi32_pd(_mm256_castsi256_si128(i32)),
                            _mm256_cvtepi32_pd(_mm256_extracti128_si256(i32, 1))};
      for (int h = 0; h < 2; ++h) {
        va[h] = _mm256_add_pd(va[h], a[h]);
        va2[h] = _mm256_add_pd(va2[h], _mm256_mul_pd(a[h], a[h]));
      }
    }
    _mm256_storeu_ps(s + x, vs);
    _mm256_storeu_ps(c + x, vc);
    _mm256_storeu_ps(top + x, vt);
    for (int h = 0; h < 2; ++h) {
      _mm256_storeu_pd(sum + x + 4 * h, va[h]);
      _mm256_storeu_pd(sum2 + x + 4 * h, va2[h]);
    }
  }
  return x;
}

RAMTK_AVX2 int WrappedPhaseRowAvx2(const float* s, const float* c, int n, float* phi) {
  const __m256d sign = _mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull)));
  const __m256 pi = _mm256_set1_ps(static_cast<float>(3.14159265358979323846));
  const __m256 two_pi = _mm256_set1_ps(static_cast<float>(6.283185307179586476925));
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const __m256 sv = _mm256_loadu_ps(s + x), cv = _mm256_loadu_ps(c + x);
    const __m256d lo = Atan2x4(_mm256_xor_pd(Low(sv), sign), Low(cv));
    const __m256d hi = Atan2x4(_mm256_xor_pd(High(sv), sign), High(cv));
    const __m256 p = Floats(lo, hi);
    _mm256_storeu_ps(phi + x, _mm256_blendv_ps(p, _mm256_sub_ps(p, two_pi), _mm256_cmp_ps(p, pi, _CMP_GE_OQ)));
  }
  return x;
}

template <typename Acc>
RAMTK_AVX2_INLINE int FinestStats(int n, int width, const float* s, const float* c, const Acc* sum, const Acc* sum2,
                                  const float* top, float dark_dn, float saturation_dn, float b_min, uchar* dark,
                                  uchar* sat, uchar* low, float* a_row, float* b_row, float* res_ss, float* res_row,
                                  float* brightest) {
  const __m256d k2 = K(2.0 / n), nd = K(static_cast<double>(n)), zero = _mm256_setzero_pd();
  const __m256 dark_v = _mm256_set1_ps(dark_dn), sat_v = _mm256_set1_ps(saturation_dn), bmin_v = _mm256_set1_ps(b_min),
               dof = _mm256_set1_ps(static_cast<float>(n - 3));
  __m256 bright = _mm256_set1_ps(*brightest);
  int x = 0;
  for (; x + 8 <= width; x += 8) {
    const __m256 sf = _mm256_loadu_ps(s + x), cf = _mm256_loadu_ps(c + x);
    // The sums of I and I^2 as doubles: float sums converted (8-bit frames), or read as they are.
    __m256d mean_in[2], sq_in[2];
    if constexpr (std::is_same_v<Acc, float>) {
      const __m256 mf = _mm256_loadu_ps(sum + x), m2f = _mm256_loadu_ps(sum2 + x);
      mean_in[0] = Low(mf), mean_in[1] = High(mf), sq_in[0] = Low(m2f), sq_in[1] = High(m2f);
    } else {
      for (int h = 0; h < 2; ++h)
        mean_in[h] = _mm256_loadu_pd(sum + x + 4 * h), sq_in[h] = _mm256_loadu_pd(sum2 + x + 4 * h);
    }
    __m256d b2[2], a2[2], r2[2];
    for (int h = 0; h < 2; ++h) {
      const __m256d sd = h ? High(sf) : Low(sf);
      const __m256d cd = h ? High(cf) : Low(cf);
      const __m256d amp2 = _mm256_add_pd(_mm256_mul_pd(sd, sd), _mm256_mul_pd(cd, cd));
      b2[h] = _mm256_mul_pd(k2, _mm256_sqrt_pd(amp2));
      const __m256d mean = _mm256_div_pd(mean_in[h], nd);
      a2[h] = mean;
      const __m256d sq = sq_in[h];
      r2[h] = _mm256_max_pd(
          _mm256_sub_pd(_mm256_sub_pd(sq, _mm256_mul_pd(_mm256_mul_pd(nd, mean), mean)), _mm256_mul_pd(k2, amp2)),
          zero);
    }
    const __m256 b8 = Floats(b2[0], b2[1]), a8 = Floats(a2[0], a2[1]), ss8 = Floats(r2[0], r2[1]);
    _mm256_storeu_ps(a_row + x, a8);
    _mm256_storeu_ps(b_row + x, b8);
    _mm256_storeu_ps(res_ss + x, ss8);
    _mm256_storeu_ps(res_row + x, n > 3 ? _mm256_sqrt_ps(_mm256_div_ps(ss8, dof)) : _mm256_setzero_ps());
    const __m256 t = _mm256_loadu_ps(top + x);
    OrFlags(dark + x, _mm256_cmp_ps(t, dark_v, _CMP_LT_OQ));
    OrFlags(sat + x, _mm256_cmp_ps(t, sat_v, _CMP_GE_OQ));
    OrFlags(low + x, _mm256_cmp_ps(b8, bmin_v, _CMP_LT_OQ));
    bright = _mm256_max_ps(t, bright);  // top > bright ? top : bright, lane by lane
  }
  float lanes[8];
  _mm256_storeu_ps(lanes, bright);
  for (const float v : lanes) *brightest = v > *brightest ? v : *brightest;
  return x;
}

RAMTK_AVX2 int FinestStatsU8Avx2(int n, int width, const float* s, const float* c, const float* sum, const float* sum2,
                                 const float* top, float dark_dn, float saturation_dn, float b_min, uchar* dark,
                                 uchar* sat, uchar* low, float* a_row, float* b_row, float* res_ss, float* res_row,
                                 float* brightest) {
  return FinestStats(n, width, s, c, sum, sum2, top, dark_dn, saturation_dn, b_min, dark, sat, low, a_row, b_row,
                     res_ss, res_row, brightest);
}

RAMTK_AVX2 int FinestStatsDoubleAvx2(int n, int width, const float* s, const float* c, const double* sum,
                                     const double* sum2, const float* top, float dark_dn, float saturation_dn,
                                     float b_min, uchar* dark, uchar* sat, uchar* low, float* a_row, float* b_row,
                                     float* res_ss, float* res_row, float* brightest) {
  return FinestStats(n, width, s, c, sum, sum2, top, dark_dn, saturation_dn, b_min, dark, sat, low, a_row, b_row,
                     res_ss, res_row, brightest);
}

RAMTK_AVX2 int SigmaRowAvx2(const uchar* mk, const float* b, int width, double k_sigma, double ripple, double to_px,
                            float* c, float* sp, float* sc) {
  const __m256d k2 = K(k_sigma * k_sigma), r2 = K(ripple * ripple), px = K(to_px);
  const __m256 nan = _mm256_set1_ps(std::numeric_limits<float>::quiet_NaN());
  const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  int x = 0;
  for (; x + 8 <= width; x += 8) {
    std::uint64_t m8;
    std::memcpy(&m8, mk + x, sizeof m8);
    if (!m8) {  // eight masked pixels: NaN, no arithmetic
      _mm256_storeu_ps(c + x, nan);
      if (sp) _mm256_storeu_ps(sp + x, nan);
      _mm256_storeu_ps(sc + x, nan);
      continue;
    }
    const __m256 valid = _mm256_castsi256_ps(_mm256_xor_si256(
        _mm256_cmpeq_epi32(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(mk + x))),
                           _mm256_setzero_si256()),
        _mm256_set1_epi32(-1)));
    const __m256 bf = _mm256_loadu_ps(b + x);
    const __m256d b0 = Low(bf), b1 = High(bf);
    const __m256 root = Floats(_mm256_sqrt_pd(_mm256_add_pd(_mm256_div_pd(k2, _mm256_mul_pd(b0, b0)), r2)),
                               _mm256_sqrt_pd(_mm256_add_pd(_mm256_div_pd(k2, _mm256_mul_pd(b1, b1)), r2)));
    const __m256 sigma = _mm256_blendv_ps(inf, root, _mm256_cmp_ps(bf, _mm256_setzero_ps(), _CMP_GT_OQ));
    const __m256 coord_sigma = Floats(_mm256_mul_pd(Low(sigma), px), _mm256_mul_pd(High(sigma), px));
    _mm256_storeu_ps(c + x, _mm256_blendv_ps(nan, _mm256_loadu_ps(c + x), valid));
    if (sp) _mm256_storeu_ps(sp + x, _mm256_blendv_ps(nan, sigma, valid));
    _mm256_storeu_ps(sc + x, _mm256_blendv_ps(nan, coord_sigma, valid));
  }
  return x;
}

RAMTK_AVX2 int GrayCoordinatesAvx2(const int* code, const float* phi, int width, double phase_at_origin_rad,
                                   double period, int extent, bool complementary, uchar* mk, float* coord,
                                   long* corrected, long* rejected) {
  const __m256d origin = K(phase_at_origin_rad), two_pi = K(6.283185307179586476925), half = K(0.5), two = K(2.0);
  const __m256d lo = K(-0.5), hi = K(extent - 0.5), per = K(period), one = K(1.0);
  const __m128 nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN());
  int x = 0;
  for (; x + 4 <= width; x += 4) {
    std::uint32_t m4;
    std::memcpy(&m4, mk + x, sizeof m4);
    if (!m4) continue;
    const __m128i bytes = _mm_cvtsi32_si128(static_cast<int>(m4));
    const __m128i valid32 =
        _mm_xor_si128(_mm_cmpeq_epi32(_mm_cvtepu8_epi32(bytes), _mm_setzero_si128()), _mm_set1_epi32(-1));
    const __m256d valid = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(valid32));
    // PeriodFractionOf: t - floor(t), t = (phi - origin) / 2 pi.
    const __m256d tr = _mm256_div_pd(_mm256_sub_pd(_mm256_cvtps_pd(_mm_loadu_ps(phi + x)), origin), two_pi);
    const __m256d t = _mm256_sub_pd(tr, _mm256_floor_pd(tr));
    const __m128i binary = _mm_loadu_si128(reinterpret_cast<const __m128i*>(code + x));
    __m256d order = _mm256_cvtepi32_pd(binary);
    if (complementary) {
      // LRound((binary + 0.5) / 2 - t): the truncation, then one up or down by the fraction.
      const __m256d v = _mm256_sub_pd(_mm256_div_pd(_mm256_add_pd(order, half), two), t);
      const __m256d i = _mm256_round_pd(v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
      const __m256d frac = _mm256_sub_pd(v, i);
      const __m256d up = _mm256_and_pd(_mm256_cmp_pd(frac, half, _CMP_GE_OQ), one);
      const __m256d down =
          _mm256_and_pd(_mm256_cmp_pd(frac, _mm256_sub_pd(_mm256_setzero_pd(), half), _CMP_LE_OQ), one);
      order = _mm256_sub_pd(_mm256_add_pd(i, up), down);
      const __m256d plain = _mm256_cvtepi32_pd(_mm_srai_epi32(binary, 1));
      const __m256d changed = _mm256_and_pd(valid, _mm256_cmp_pd(order, plain, _CMP_NEQ_OQ));
      *corrected += __builtin_popcount(static_cast<unsigned>(_mm256_movemask_pd(changed)));
    }
    const __m256d u = _mm256_mul_pd(_mm256_add_pd(order, t), per);
    const __m256d out = _mm256_or_pd(_mm256_cmp_pd(u, lo, _CMP_LT_OQ), _mm256_cmp_pd(u, hi, _CMP_GE_OQ));
    const int out_bits = _mm256_movemask_pd(_mm256_and_pd(valid, out));
    *rejected += __builtin_popcount(static_cast<unsigned>(out_bits));
    const __m128i out32 =
        _mm_setr_epi32(-(out_bits & 1), -(out_bits >> 1 & 1), -(out_bits >> 2 & 1), -(out_bits >> 3 & 1));
    __m128 result = _mm_blendv_ps(_mm_loadu_ps(coord + x), _mm256_cvtpd_ps(u), _mm_castsi128_ps(valid32));
    result = _mm_blendv_ps(result, nan, _mm_castsi128_ps(out32));
    _mm_storeu_ps(coord + x, result);
    if (out_bits)
      for (int j = 0; j < 4; ++j)
        if (out_bits >> j & 1) mk[x + j] = 0;
  }
  return x;
}

}  // namespace ramtk::vision::detail
