#include "ramtk/tcf/statistics.h"

#include <cmath>

namespace ramtk::tcf {

PointScatter ComputePointScatter(const std::vector<Vec3>& points) {
  PointScatter s;
  s.count = static_cast<int>(points.size());
  if (points.empty()) return s;
  for (const Vec3& p : points) s.mean += p / points.size();
  double ss = 0.0;
  for (const Vec3& p : points) {
    const double d = (p - s.mean).norm();
    ss += d * d;
    s.max_from_mean_mm = std::max(s.max_from_mean_mm, d);
  }
  s.rms_from_mean_mm = std::sqrt(ss / points.size());
  s.sample_std_mm = points.size() > 1 ? std::sqrt(ss / (points.size() - 1)) : 0.0;
  return s;
}

}  // namespace ramtk::tcf
