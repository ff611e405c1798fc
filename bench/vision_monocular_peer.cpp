// Side by side with SLMaster's monocular path (bench/slmaster_monocular_compare.sh runs both and
// then this): the two clouds' point counts, the distance from each ramtk point to the nearest
// SLMaster point and back (median, and the share within 1 mm), against the median sigma ramtk
// predicts for its points.
//
// usage: vision_monocular_peer RAMTK_CLOUD.ply PEER_CLOUD.ply
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "ramtk/vision/projector/cloud_distance.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Median of the finite distances, and how many are finite.
void Describe(const char* what, const std::vector<double>& d) {
  std::vector<double> finite;
  for (double x : d)
    if (std::isfinite(x)) finite.push_back(x);
  std::printf("%s: median %.4f mm over %zu of %zu points within 1 mm (%.1f %%)\n", what, Median(finite), finite.size(),
              d.size(), 100.0 * static_cast<double>(finite.size()) / std::max<std::size_t>(1, d.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s RAMTK_CLOUD.ply PEER_CLOUD.ply\n", argv[0]);
    return 2;
  }
  using namespace ramtk::vision;
  const PointCloud ours = ReadPly(argv[1]);
  const PointCloud peer = ReadPly(argv[2]);
  std::vector<double> sigma(ours.sigma_mm.begin(), ours.sigma_mm.end());
  std::printf("points: ramtk %zu, SLMaster %zu (ratio %.3f)\n", ours.size(), peer.size(),
              static_cast<double>(ours.size()) / std::max<std::size_t>(1, peer.size()));
  const double median_sigma = Median(sigma);
  std::printf("ramtk median predicted point sigma: %.4f mm\n", median_sigma);
  const std::vector<double> to_peer = NearestNeighbourDistances(ours.points_in_left, peer.points_in_left, 1.0);
  const std::vector<double> to_ours = NearestNeighbourDistances(peer.points_in_left, ours.points_in_left, 1.0);
  Describe("ramtk -> SLMaster nearest point", to_peer);
  Describe("SLMaster -> ramtk nearest point", to_ours);
  std::vector<double> finite;
  for (double x : to_peer)
    if (std::isfinite(x)) finite.push_back(x);
  std::printf("median cloud-to-cloud distance / median predicted sigma: %.3f\n", Median(finite) / median_sigma);
  return 0;
}
