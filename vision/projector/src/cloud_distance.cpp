// Nearest-neighbour distances between clouds (cloud_distance.h).
#include "ramtk/vision/projector/cloud_distance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

std::int64_t Key(std::int64_t x, std::int64_t y, std::int64_t z) {
  return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (z & 0x1FFFFF);
}

}  // namespace

std::vector<double> NearestNeighbourDistances(const std::vector<Eigen::Vector3f>& from,
                                              const std::vector<Eigen::Vector3f>& to, double max_distance_mm) {
  if (!(max_distance_mm > 0)) throw InputError({"", 0, "max_distance_mm"}, "must be > 0");
  const double cell = max_distance_mm;
  auto index = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell)); };
  std::unordered_map<std::int64_t, std::vector<std::size_t>> voxels;
  for (std::size_t i = 0; i < to.size(); ++i)
    voxels[Key(index(to[i].x()), index(to[i].y()), index(to[i].z()))].push_back(i);
  std::vector<double> out(from.size(), std::numeric_limits<double>::infinity());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, from.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const Eigen::Vector3f& p = from[i];
      const std::int64_t x = index(p.x()), y = index(p.y()), z = index(p.z());
      double best = max_distance_mm * max_distance_mm;
      bool found = false;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = voxels.find(Key(x + dx, y + dy, z + dz));
            if (it == voxels.end()) continue;
            for (std::size_t j : it->second) {
              const double d2 = (to[j] - p).cast<double>().squaredNorm();
              if (d2 <= best) best = d2, found = true;
            }
          }
      if (found) out[i] = std::sqrt(best);
    }
  });
  return out;
}

}  // namespace ramtk::vision
