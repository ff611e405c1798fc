// A simulated ball bar: two 38.1 mm balls 52 mm apart scanned together; both centres and their
// distance against the simulator's truth.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "ramtk/vision/scan/scan.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

TEST(ScanBallBar, CentreDistanceAgainstTheSimulatorTruth) {
  FringeSimulationConfig c = MakeFringePreset("small");  // windows around (0, 0, 700)
  c.seed = 5;
  // Widen both camera windows to 960 x 512 (143 x 76 mm at 700 mm) so that both balls are seen.
  for (CameraIntrinsics* cam : {&c.cameras.left, &c.cameras.right}) {
    cam->cx += 160;
    cam->width = 960;
  }
  const double length = 52.0;  // 14 mm between the surfaces
  c.scene.spheres = {{"ball_a", Vec3(-length / 2, 0, 700), 19.05, 0.8},
                     {"ball_b", Vec3(length / 2, 0, 700), 19.05, 0.8}};
  const auto s = testing::SimulateAndDecode(c);
  ScanOptions o;
  o.sphere.max_spheres = 2;
  const ScanResult r = ScanDecoded(WrittenCalibration(c), s.left, s.right, s.period, o);
  ASSERT_EQ(r.summary.termination, Termination::kSuccess) << r.summary.BriefReport();
  ASSERT_EQ(r.summary.spheres.spheres.size(), 2u);
  const std::vector<Sphere> truth = c.scene.spheres;
  const std::vector<int> match = MatchTruthSpheres(r.summary.spheres, truth);
  ASSERT_NE(match[0], -1);
  ASSERT_NE(match[1], -1);
  ASSERT_NE(match[0], match[1]);
  const SphereResult& a = r.summary.spheres.spheres[0];
  const SphereResult& b = r.summary.spheres.spheres[1];
  const CentreDistance d = ComputeCentreDistance(a, b);
  const double error = d.distance_mm - length;
  std::cout << r.summary.BriefReport() << "\ncentre distance " << d.distance_mm << " mm +- " << 1000 * d.sigma_mm
            << " um, error " << 1000 * error << " um\n";
  RecordProperty("distance_error_um", std::to_string(1000 * error));
  RecordProperty("distance_sigma_um", std::to_string(1000 * d.sigma_mm));
  // Along the bar (x) each centre's noise is ~0.5 um (predicted, correlation included) and the
  // sweep's largest x bias per pose is < 1 um (docs/scan.md), so the distance is good to ~2 um;
  // 3 um fails on a matching or fitting error while leaving room for this seed's noise.
  EXPECT_LT(std::abs(error), 0.003);
  EXPECT_GT(d.sigma_mm, 0.0002);  // the correlation-inflated sigma of two centres
  EXPECT_LT(d.sigma_mm, 0.002);
  for (int k = 0; k < 2; ++k) {
    const SphereResult& f = r.summary.spheres.spheres[k];
    const Sphere& t = truth[match[k]];
    EXPECT_LT((f.centre_mm - t.centre_in_left).norm(), 0.005) << t.name;  // issue 4's target
    EXPECT_LT(std::abs(f.radius_mm - t.radius), 0.005) << t.name;
  }
}

}  // namespace
}  // namespace ramtk::vision
