#pragma once
// atan2 of one double pair without a library call or branches, for the decode's wrapped phase
// (decode_fast.cpp), where glibc's atan2f was ~100 instructions per valid pixel. The ratio of the
// smaller to the larger magnitude is folded to |t| <= tan(pi/8) (atan t = pi/4 + atan((t-1)/(t+1))),
// where the Taylor series of atan to t^25 is exact to ~1e-11 rad; the octant then comes from the
// signs and the swap. IEEE atan2's signed zeros are kept: atan2(+-0, -0) = +-pi. Checked against
// std::atan2 in tests/vision/fast_atan2_test.cpp.
#include <cmath>

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

}  // namespace ramtk::vision::detail
