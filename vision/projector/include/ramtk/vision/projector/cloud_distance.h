#pragma once
// Cloud-to-cloud distance: for each point of one cloud, the distance to the nearest point of
// another (a voxel hash of the second cloud, no tree library), as peers' clouds are compared.

#include <Eigen/Core>
#include <vector>

namespace ramtk::vision {

// Distance (mm) from each point of `from` to its nearest point of `to`; +infinity where none lies
// within `max_distance_mm` (> 0; also the voxel size, so the search reads 27 voxels per point).
std::vector<double> NearestNeighbourDistances(const std::vector<Eigen::Vector3f>& from,
                                              const std::vector<Eigen::Vector3f>& to, double max_distance_mm);

}  // namespace ramtk::vision
