#pragma once
// Rounding for per-pixel loops, exactly equal to the standard functions on their stated ranges.
// The build targets baseline x86-64 (SSE2), which has no rounding instruction (`roundsd` is
// SSE4.1): GCC expands std::floor into a multi-instruction sequence and calls libm for
// std::lround, per pixel. Checked against std::floor / std::lround in
// tests/vision/fast_round_test.cpp.
#include <cmath>
#include <limits>

namespace ramtk::vision::detail {

// std::floor(v), for every double (beyond 2^52, NaN and infinities: v itself, as std::floor).
inline double Floor(double v) {
  if (!(std::abs(v) < 4503599627370496.0)) return v;                // 2^52: already integral, or not finite
  const double t = static_cast<double>(static_cast<long long>(v));  // toward zero
  if (t == v) return v;                                             // integral (keeps -0.0)
  return t > v ? t - 1.0 : t;
}

// static_cast<int>(std::floor(v)) for |v| < 1e9. Beyond that, and for NaN, a large negative value
// that no image index passes (where the conversion of such a floor gave INT_MIN).
inline int FloorToInt(double v) {
  if (!(std::abs(v) < 1e9)) return std::numeric_limits<int>::min() / 2;
  const int i = static_cast<int>(v);
  return i - (v < i);
}

// floor(a / b) for b > 0.
inline int FloorDiv(int a, int b) { return a >= 0 ? a / b : -((b - 1 - a) / b); }

// std::lround(v) (halves away from zero) for |v| < 2^52.
inline long LRound(double v) {
  const long i = static_cast<long>(v);             // toward zero
  const double frac = v - static_cast<double>(i);  // exact
  return i + (frac >= 0.5) - (frac <= -0.5);  // without branches: a branch per rounding mispredicts
}

// t wrapped into [0, 1): t - floor(t).
inline double Wrap01(double t) { return t - Floor(t); }

// The fraction of a period in [0, 1) of the wrapped phase phi (PeriodFraction, unwrap.h).
inline double PeriodFractionOf(double phi, double phase_at_origin_rad) {
  return Wrap01((phi - phase_at_origin_rad) / 6.283185307179586476925);
}

}  // namespace ramtk::vision::detail
