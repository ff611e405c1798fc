// ramtk's sphere fit beside PCL's RANSAC sphere fit (SACSegmentation, SACMODEL_SPHERE, optimized
// coefficients) on the same synthetic clouds: both against the simulated truth. ramtk must be
// at least as accurate (centre and radius error RMS over the seeds).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "ramtk/vision/sphere/sphere_fit.h"
#include "sphere_pcl_peer.h"
#include "sphere_synth.h"

namespace ramtk::vision {
namespace {

TEST(SpherePclPeer, AtLeastAsAccurateAsPclRansac) {
  test::CapScene scene;
  constexpr int kSeeds = 10;
  double ramtk_centre2 = 0, pcl_centre2 = 0, ramtk_radius2 = 0, pcl_radius2 = 0;
  for (int k = 0; k < kSeeds; ++k) {
    const test::SynthCloud cloud = test::MakeCapCloud(scene, 500 + static_cast<uint64_t>(k));
    SphereFitOptions o;
    o.radius_mm = 19.05;
    o.noise_model = PointNoiseModel::kAlongLineOfSight;
    o.viewpoint_mm = cloud.viewpoint;
    const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
    ASSERT_EQ(s.spheres.size(), 1u) << s.BriefReport();
    // PCL with the same radius window and a 0.1 mm band (about 4 x the largest point sigma).
    const test::PclSphere p = test::PclFitSphere(test::ToPcl(cloud.points), 0.1, 17.05, 21.05);
    ASSERT_TRUE(p.found);
    ramtk_centre2 += (s.spheres[0].centre_mm - scene.centre).squaredNorm() / kSeeds;
    pcl_centre2 += (p.centre - scene.centre).squaredNorm() / kSeeds;
    ramtk_radius2 += std::pow(s.spheres[0].radius_mm - scene.radius, 2) / kSeeds;
    pcl_radius2 += std::pow(p.radius - scene.radius, 2) / kSeeds;
    // PCL agrees with the truth to its own (looser) level: the peer ran correctly.
    EXPECT_LT((p.centre - scene.centre).norm(), 0.05);
  }
  std::printf("centre error RMS: ramtk %.3f um, PCL %.3f um; radius error RMS: ramtk %.3f um, PCL %.3f um\n",
              1e3 * std::sqrt(ramtk_centre2), 1e3 * std::sqrt(pcl_centre2), 1e3 * std::sqrt(ramtk_radius2),
              1e3 * std::sqrt(pcl_radius2));
  EXPECT_LE(ramtk_centre2, pcl_centre2);
  EXPECT_LE(ramtk_radius2, pcl_radius2);
}

}  // namespace
}  // namespace ramtk::vision
