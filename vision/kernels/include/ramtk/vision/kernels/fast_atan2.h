#pragma once
// atan2 of one double pair without a library call or branches, for the decode's wrapped phase
// (decode_fused.cpp), where glibc's atan2f was ~100 instructions per valid pixel. The ratio of the
// smaller to the larger magnitude is folded to |t| <= tan(pi/8) (atan t = pi/4 + atan((t-1)/(t+1))),
// where the Taylor series of atan to t^25 is exact to ~1e-11 rad; the octant then comes from the
// signs and the swap. IEEE atan2's signed zeros are kept: atan2(+-0, -0) = +-pi. Checked against
// std::atan2 in tests/vision/fast_atan2_test.cpp.
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>

namespace ramtk::vision::detail {

inline double Atan2(double y, double x) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kTanPiOver8 = 0.41421356237309504880;
  const double ax = std::abs(x), ay = std::abs(y);
  const bool swap = ay > ax;
  const double lo = swap ? ax : ay, hi = swap ? ay : ax;
  const double t = hi > 0 ? lo / hi : 0.0;  // in [0, 1]
  const bool fold = t > kTanPiOver8;
  const double u = fold ? (t - 1.0) / (t + 1.0) : t;  // |u| <= tan(pi/8)
  const double u2 = u * u;
  // atan u = u (1 - u^2/3 + u^4/5 - ... - u^24/25): the next term is below 2e-12 at |u| = tan(pi/8).
  double p = 1.0 / 25;
  p = p * u2 - 1.0 / 23;
  p = p * u2 + 1.0 / 21;
  p = p * u2 - 1.0 / 19;
  p = p * u2 + 1.0 / 17;
  p = p * u2 - 1.0 / 15;
  p = p * u2 + 1.0 / 13;
  p = p * u2 - 1.0 / 11;
  p = p * u2 + 1.0 / 9;
  p = p * u2 - 1.0 / 7;
  p = p * u2 + 1.0 / 5;
  p = p * u2 - 1.0 / 3;
  p = p * u2 + 1.0;
  double r = (fold ? kPi / 4 : 0.0) + u * p;  // atan(t), in [0, pi/4]
  r = swap ? kPi / 2 - r : r;
  r = std::signbit(x) ? kPi - r : r;
  return std::signbit(y) ? -r : r;
}

#if CV_SIMD128_64F
// Atan2 on two lanes: the same operations in the same order, each ternary a lane select, so each
// lane is bit-identical to Atan2 of its pair (tests/vision/fast_atan2_test.cpp). The sign tests
// read the sign bit, as std::signbit, and the final negation flips it.
inline cv::v_float64x2 Atan2x2(const cv::v_float64x2& y, const cv::v_float64x2& x) {
  using cv::v_float64x2;
  using cv::v_int64x2;
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kTanPiOver8 = 0.41421356237309504880;
  auto k = [](double v) { return cv::v_setall_f64(v); };
  const v_float64x2 zero = k(0.0);
  const v_float64x2 ax = cv::v_abs(x), ay = cv::v_abs(y);
  const v_float64x2 swap = ay > ax;
  const v_float64x2 lo = cv::v_select(swap, ax, ay), hi = cv::v_select(swap, ay, ax);
  const v_float64x2 t = cv::v_select(hi > zero, lo / hi, zero);
  const v_float64x2 fold = t > k(kTanPiOver8);
  const v_float64x2 u = cv::v_select(fold, (t - k(1.0)) / (t + k(1.0)), t);
  const v_float64x2 u2 = u * u;
  v_float64x2 p = k(1.0 / 25);
  p = p * u2 - k(1.0 / 23);
  p = p * u2 + k(1.0 / 21);
  p = p * u2 - k(1.0 / 19);
  p = p * u2 + k(1.0 / 17);
  p = p * u2 - k(1.0 / 15);
  p = p * u2 + k(1.0 / 13);
  p = p * u2 - k(1.0 / 11);
  p = p * u2 + k(1.0 / 9);
  p = p * u2 - k(1.0 / 7);
  p = p * u2 + k(1.0 / 5);
  p = p * u2 - k(1.0 / 3);
  p = p * u2 + k(1.0);
  v_float64x2 r = cv::v_select(fold, k(kPi / 4), zero) + u * p;
  r = cv::v_select(swap, k(kPi / 2) - r, r);
  const v_int64x2 sign = cv::v_setall_s64(static_cast<int64_t>(0x8000000000000000ull));
  const v_int64x2 x_bits = cv::v_reinterpret_as_s64(x), y_bits = cv::v_reinterpret_as_s64(y);
  r = cv::v_select(cv::v_reinterpret_as_f64((x_bits & sign) == sign), k(kPi) - r, r);
  return cv::v_reinterpret_as_f64(cv::v_reinterpret_as_s64(r) ^ (y_bits & sign));
}
#endif

}  // namespace ramtk::vision::detail
