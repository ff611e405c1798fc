#pragma once
// sin and cos of one double argument together, without branches or a library call, for the
// ripple basis of the nonlinearity estimate (nonlinearity_fast.cpp), where glibc's sincos was
// ~9 % of a decode. GCC does not vectorise a row loop over it (the quadrant's integer
// conversion and selects stay scalar), so SinCos2 below runs it on two lanes with OpenCV's
// universal intrinsics. Accuracy: within 2 ulp of std::sin / std::cos for |a| < 2^20 (checked in
// tests/vision/fast_sincos_test.cpp over that range against std::sin / std::cos).
#include <immintrin.h>

#include <cmath>
#include <opencv2/core/hal/intrin.hpp>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {

// a = q pi/2 + r, |r| <= pi/4: q rounded to nearest by the 1.5 * 2^52 shift, r by pi/2 in three
// parts whose products with q (< 2^20) are exact (Cody and Waite).
namespace sincos_constants {
constexpr double kTwoOverPi = 0.63661977236758134308;
constexpr double kShift = 6755399441055744.0;          // 1.5 * 2^52
constexpr double kPio2a = 1.57079632673412561417e+00;  // pi/2, first 33 bits
constexpr double kPio2b = 6.07710050630396597660e-11;  // next 33 bits
constexpr double kPio2c = 2.02226624871116645580e-21;  // the rest
// The lane versions' polynomial coefficients, innermost (highest order) first: the scalar
// version's nested Horner forms, in the same order.
constexpr double kSinCoef[] = {1.0 / 355687428096000, -1.0 / 1307674368000, 1.0 / 6227020800, -1.0 / 39916800,
                               1.0 / 362880,          -1.0 / 5040,          1.0 / 120,        -1.0 / 6};
constexpr double kCosCoef[] = {-1.0 / 6402373705728000,
                               1.0 / 20922789888000,
                               -1.0 / 87178291200,
                               1.0 / 479001600,
                               -1.0 / 3628800,
                               1.0 / 40320,
                               -1.0 / 720,
                               1.0 / 24,
                               -0.5};
}  // namespace sincos_constants

inline void SinCos(double a, double* s, double* c) {
  using namespace sincos_constants;
  const double qd = (a * kTwoOverPi + kShift) - kShift;
  const double r = ((a - qd * kPio2a) - qd * kPio2b) - qd * kPio2c;
  const double r2 = r * r;
  // Taylor series to r^17 / r^18: the next terms are below 1e-19 on |r| <= pi/4.
  const double sp =
      r + r * r2 *
              (-1.0 / 6 +
               r2 * (1.0 / 120 +
                     r2 * (-1.0 / 5040 +
                           r2 * (1.0 / 362880 + r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800 +
                                                                              r2 * (-1.0 / 1307674368000 +
                                                                                    r2 * (1.0 / 355687428096000))))))));
  const double cp =
      1.0 + r2 * (-0.5 + r2 * (1.0 / 24 +
                               r2 * (-1.0 / 720 +
                                     r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800 +
                                                               r2 * (1.0 / 479001600 +
                                                                     r2 * (-1.0 / 87178291200 +
                                                                           r2 * (1.0 / 20922789888000 +
                                                                                 r2 * (-1.0 / 6402373705728000)))))))));
  const int q = static_cast<int>(qd) & 3;
  const double s0 = (q & 1) ? cp : sp, c0 = (q & 1) ? sp : cp;
  *s = (q & 2) ? -s0 : s0;
  *c = ((q + 1) & 2) ? -c0 : c0;
}

#if CV_SIMD128_64F
// SinCos on two lanes: the same operations in the same order (no fused multiply-add on either
// path in a baseline x86-64 build), so each lane is bit-identical to SinCos of its element
// (tests/vision/fast_sincos_test.cpp). The quadrant q mod 4 is read from the low bits of
// a 2/pi + 1.5 * 2^52, whose mantissa holds 2^51 + q.
inline void SinCos2(const cv::v_float64x2& a, cv::v_float64x2* s, cv::v_float64x2* c) {
  using namespace sincos_constants;
  using cv::v_float64x2;
  using cv::v_int64x2;
  auto k = [](double v) { return cv::v_setall_f64(v); };
  const v_float64x2 t = a * k(kTwoOverPi) + k(kShift);
  const v_float64x2 qd = t - k(kShift);
  const v_float64x2 r = ((a - qd * k(kPio2a)) - qd * k(kPio2b)) - qd * k(kPio2c);
  const v_float64x2 r2 = r * r;
  // The scalar version's nested polynomials (Horner: the same products and sums in the same order).
  v_float64x2 ps = k(kSinCoef[0]);
  for (int i = 1; i < 8; ++i) ps = k(kSinCoef[i]) + r2 * ps;
  const v_float64x2 sp = r + r * r2 * ps;
  v_float64x2 pc = k(kCosCoef[0]);
  for (int i = 1; i < 9; ++i) pc = k(kCosCoef[i]) + r2 * pc;
  const v_float64x2 cp = k(1.0) + r2 * pc;
  const v_int64x2 q = cv::v_reinterpret_as_s64(t);
  const v_int64x2 one = cv::v_setall_s64(1), two = cv::v_setall_s64(2);
  const v_float64x2 odd = cv::v_reinterpret_as_f64((q & one) == one);
  const v_int64x2 s0 = cv::v_reinterpret_as_s64(cv::v_select(odd, cp, sp));
  const v_int64x2 c0 = cv::v_reinterpret_as_s64(cv::v_select(odd, sp, cp));
  *s = cv::v_reinterpret_as_f64(s0 ^ ((q & two) << 62));          // negated in quadrants 2, 3
  *c = cv::v_reinterpret_as_f64(c0 ^ (((q + one) & two) << 62));  // negated in quadrants 1, 2
}
#endif

// SinCos2 on four lanes (AVX2; call only where detail::Avx2Kernels() holds), operation for
// operation.
RAMTK_AVX2_INLINE void SinCos4(__m256d a, __m256d* s, __m256d* c) {
  using namespace sincos_constants;
  const __m256d t = _mm256_add_pd(_mm256_mul_pd(a, _mm256_set1_pd(kTwoOverPi)), _mm256_set1_pd(kShift));
  const __m256d qd = _mm256_sub_pd(t, _mm256_set1_pd(kShift));
  const __m256d r = _mm256_sub_pd(_mm256_sub_pd(_mm256_sub_pd(a, _mm256_mul_pd(qd, _mm256_set1_pd(kPio2a))),
                                                _mm256_mul_pd(qd, _mm256_set1_pd(kPio2b))),
                                  _mm256_mul_pd(qd, _mm256_set1_pd(kPio2c)));
  const __m256d r2 = _mm256_mul_pd(r, r);
  __m256d ps = _mm256_set1_pd(kSinCoef[0]);
  for (int i = 1; i < 8; ++i) ps = _mm256_add_pd(_mm256_set1_pd(kSinCoef[i]), _mm256_mul_pd(r2, ps));
  const __m256d sp = _mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, r2), ps));
  __m256d pc = _mm256_set1_pd(kCosCoef[0]);
  for (int i = 1; i < 9; ++i) pc = _mm256_add_pd(_mm256_set1_pd(kCosCoef[i]), _mm256_mul_pd(r2, pc));
  const __m256d cp = _mm256_add_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(r2, pc));
  const __m256i q = _mm256_castpd_si256(t);
  const __m256i one = _mm256_set1_epi64x(1), two = _mm256_set1_epi64x(2);
  const __m256d odd = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(q, one), one));
  const __m256i s0 = _mm256_castpd_si256(_mm256_blendv_pd(sp, cp, odd));
  const __m256i c0 = _mm256_castpd_si256(_mm256_blendv_pd(cp, sp, odd));
  *s = _mm256_castsi256_pd(_mm256_xor_si256(s0, _mm256_slli_epi64(_mm256_and_si256(q, two), 62)));
  *c =
      _mm256_castsi256_pd(_mm256_xor_si256(c0, _mm256_slli_epi64(_mm256_and_si256(_mm256_add_epi64(q, one), two), 62)));
}

}  // namespace ramtk::vision::detail
