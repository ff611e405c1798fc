#include "ramtk/tcf/geometry.h"

#include <algorithm>

namespace ramtk::tcf {

double LineToRayDistance(const Vec3& p, const Vec3& d, const Vec3& c, const Vec3& e) {
  // Minimise |w + μ·e − λ·d| over λ (free) and μ ≥ 0, w = c − p.
  const Vec3 w = c - p;
  const double b = d.dot(e);
  const double den = 1.0 - b * b;
  const double mu = std::max(0.0, den > 1e-12 ? (b * d.dot(w) - e.dot(w)) / den : 0.0);
  const Vec3 v = w + mu * e;
  return (v - v.dot(d) * d).norm();
}

}  // namespace ramtk::tcf
