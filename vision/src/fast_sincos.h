#pragma once
// sin and cos of one double argument together, without branches or a library call, for the
// ripple basis of the nonlinearity estimate (nonlinearity_fast.cpp), where glibc's sincos was
// ~9 % of a decode. (GCC does not vectorise the row loop over it: the quadrant's integer
// conversion and selects stay scalar.) Accuracy: within 2 ulp of std::sin / std::cos for |a| < 2^20 (checked in
// tests/vision/fast_sincos_test.cpp over that range against std::sin / std::cos).
#include <cmath>

namespace ramtk::vision::detail {

inline void SinCos(double a, double* s, double* c) {
  // a = q pi/2 + r, |r| <= pi/4: q rounded to nearest by the 1.5 * 2^52 shift, r by pi/2 in three
  // parts whose products with q (< 2^20) are exact (Cody and Waite).
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kShift = 6755399441055744.0;          // 1.5 * 2^52
  constexpr double kPio2a = 1.57079632673412561417e+00;  // pi/2, first 33 bits
  constexpr double kPio2b = 6.07710050630396597660e-11;  // next 33 bits
  constexpr double kPio2c = 2.02226624871116645580e-21;  // the rest
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

}  // namespace ramtk::vision::detail
