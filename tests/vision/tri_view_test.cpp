// Tri-view on the simulated stereo rig (tri_view.h): the "small" preset's stereo scan, then the
// left pixels without a stereo point triangulated against the projector. At least the stereo
// points, more where the right camera does not see what the projector lights (the backdrop beside
// the ball), and the added points' depth errors against the simulator's truth consistent with their
// sigma.
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/vision/projector/tri_view.h"
#include "ramtk/vision/scan/scan.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

TEST(TriView, ProjectorAddsPointsTheStereoPairMissesWithHonestSigma) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.supersampling = 2;
  const testing::DecodedStereo s = testing::SimulateAndDecode(c);
  ScanOptions o;
  o.fit_spheres = false;
  ScanResult r = ScanDecoded(WrittenCalibration(c), s.left, s.right, s.period, o);
  ProjectorCalibration pc;
  pc.camera = WrittenCalibration(c).left;
  pc.projector = c.projector.intrinsics;
  pc.projector_from_camera = c.projector.view_from_left;
  const long stereo = static_cast<long>(r.cloud.size());
  const TriViewSummary sum = AddProjectorPoints(pc, c.direction, s.left, {}, &r.cloud, &r.depth);
  std::cout << "stereo " << sum.stereo_points << " points, projector adds " << sum.projector_points << " ("
            << sum.projector.BriefReport() << ")\n";
  EXPECT_EQ(sum.stereo_points, stereo);
  EXPECT_EQ(static_cast<long>(r.cloud.size()), stereo + sum.projector_points);
  EXPECT_GT(sum.projector_points, stereo / 100);
  // Every decoded left pixel is a point now (but those outside the projector's reach).
  EXPECT_GE(static_cast<double>(r.cloud.size()), 0.99 * s.left.summary.valid_pixels);
  // Added points against the truth depth, on clean pixels (all of the pixel's rays lit on one object).
  double sum_sq = 0;
  long n = 0, mixed = 0, mixed_off = 0;
  for (std::size_t i = static_cast<std::size_t>(stereo); i < r.cloud.size(); ++i) {
    const int x = static_cast<int>(r.cloud.left_pixels[i].x()), y = static_cast<int>(r.cloud.left_pixels[i].y());
    if (s.left_sim.truth.lit_fraction.at<float>(y, x) < 1.0f) {
      ++mixed;
      mixed_off += std::abs(r.cloud.points_in_left[i].z() - s.left_sim.truth.depth.at<float>(y, x)) > 1.0 ? 1 : 0;
      continue;
    }
    const Eigen::Vector3f& p = r.cloud.points_in_left[i];
    const double truth_z = s.left_sim.truth.depth.at<float>(y, x);
    const double sigma_z = r.cloud.sigma_mm[i] * p.z() / p.norm();
    sum_sq += std::pow((p.z() - truth_z) / sigma_z, 2);
    ++n;
  }
  ASSERT_GT(n, 1000);
  const double ratio = std::sqrt(sum_sq / static_cast<double>(n));
  std::cout << "added points: depth error RMS / sigma " << ratio << " over " << n << " clean pixels; " << mixed
            << " mixed pixels (edges, shadow borders), " << mixed_off << " of them more than 1 mm off\n";
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.4);
}

}  // namespace
}  // namespace ramtk::vision
