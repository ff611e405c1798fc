// SLMaster's own monocular capture (shared/data/slmaster-monocular, datasets/vision/
// slmaster_monocular.json) through the camera–projector scan, against SLMaster's monocular path
// (bench/peers/slmaster_monocular): at least its valid points, and (when its cloud is given in
// RAMTK_SLMASTER_MONOCULAR_PLY, as bench/slmaster_monocular_compare.sh writes it) a median
// cloud-to-cloud distance within 2x ramtk's median predicted point sigma. Skipped when the data
// are absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "ramtk/vision/projector/cloud_distance.h"
#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {
namespace {

// SLMaster's monocular path on this set: its cloud points (`/tmp/peer-slm-mono/driver --data
// ../shared/data/slmaster-monocular`, bench/peers/slmaster_monocular).
constexpr long kSlmasterPoints = 208995;

// The dataset's manifest with its files pointed at RAMTK_SHARED_DIR, written to a temporary file.
bool MonocularManifest(std::string* path) {
  const std::string shared = RAMTK_SHARED_DIR;
  if (!std::filesystem::exists(shared + "/data/slmaster-monocular/L/0.bmp")) return false;
  FringeManifest m = ReadFringeManifest(std::string(RAMTK_DATASETS_DIR) + "/vision/slmaster_monocular.json");
  const std::string rel = "../../../shared";
  for (auto& [name, files] : m.cameras)
    for (std::string& f : files)
      if (f.rfind(rel, 0) == 0) f = shared + f.substr(rel.size());
  m.projector_calibration = shared + "/data/slmaster-monocular/caliInfo.yml";
  *path = ::testing::TempDir() + "/slmaster_monocular.json";
  WriteFringeManifest(*path, m);
  return true;
}

ScanResult ScanSet(const std::string& manifest) {
  ScanOptions o;
  o.fit_spheres = false;  // the scene holds no ball
  return ScanFringeSet(manifest, o);
}

double MedianOf(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(ScanMonocularReal, AtLeastSlmastersPoints) {
  std::string manifest;
  if (!MonocularManifest(&manifest)) GTEST_SKIP() << "shared/data/slmaster-monocular not present";
  const ScanResult r = ScanSet(manifest);
  std::cout << r.summary.left.BriefReport() << "\n" << r.summary.projector.BriefReport() << "\n";
  RecordProperty("points", std::to_string(r.summary.projector.points));
  EXPECT_EQ(r.summary.mode, "monocular");
  EXPECT_GE(r.summary.projector.points, kSlmasterPoints);
  // Nearly every decoded pixel is a point: the projector sees what it lights.
  EXPECT_GE(r.summary.projector.points, 0.99 * r.summary.projector.coded_pixels);
}

TEST(ScanMonocularReal, CloudWithinTwoSigmaOfSlmasters) {
  std::string manifest;
  if (!MonocularManifest(&manifest)) GTEST_SKIP() << "shared/data/slmaster-monocular not present";
  const char* peer_path = std::getenv("RAMTK_SLMASTER_MONOCULAR_PLY");
  if (!peer_path || !std::filesystem::exists(peer_path))
    GTEST_SKIP() << "RAMTK_SLMASTER_MONOCULAR_PLY (SLMaster's cloud, bench/slmaster_monocular_compare.sh) not given";
  const ScanResult r = ScanSet(manifest);
  const PointCloud peer = ReadPly(peer_path);
  ASSERT_GE(static_cast<long>(peer.size()), kSlmasterPoints * 99 / 100);
  std::vector<double> d = NearestNeighbourDistances(r.cloud.points_in_left, peer.points_in_left, 1.0);
  d.erase(std::remove_if(d.begin(), d.end(), [](double x) { return !std::isfinite(x); }), d.end());
  ASSERT_GT(d.size(), r.cloud.size() / 2);
  const double median_distance = MedianOf(d);
  const double median_sigma = MedianOf(std::vector<double>(r.cloud.sigma_mm.begin(), r.cloud.sigma_mm.end()));
  std::cout << "median cloud-to-cloud distance " << median_distance << " mm, median predicted sigma " << median_sigma
            << " mm\n";
  EXPECT_LE(median_distance, 2 * median_sigma);
}

}  // namespace
}  // namespace ramtk::vision
