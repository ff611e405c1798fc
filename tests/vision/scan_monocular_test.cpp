// The camera–projector scan (scan_monocular.h) on the fringe simulator's ball: the "small" rig's
// left camera and its projector (with a distorted projector lens, rendered by the simulator),
// the same radiance under 20 sensor-noise seeds. The fitted centre must lie within 2 sigma of the
// truth for every seed (|e| against |sigma|, and per axis for all but a Gaussian share of the
// 60 axis values), the seeds' mean within 2 sigma of the mean, and the predicted centre sigma
// must match the seed-to-seed scatter (0.8 .. 1.25).
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/vision/scan/scan_monocular.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

FringeSimulationConfig MonocularRig() {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.projector.intrinsics.distortion = {-0.06, 0.12, 4e-4, -3e-4, 0.0};
  // One ray per pixel: the camera samples the radiance at its pixel centres, the model the
  // triangulation assumes. With a box pixel (supersampling 3..6) the side-lit ball's shading
  // gradient times its phase gradient across each pixel moves the decoded phase, and the centre by
  // ~0.9 um in x (1.4 sigma of one scan; docs/scan.md, "Camera–projector sets").
  c.supersampling = 1;
  return c;
}

ProjectorCalibration CalibrationOf(const FringeSimulationConfig& c) {
  ProjectorCalibration p;
  p.camera = WrittenCalibration(c).left;
  p.projector = c.projector.intrinsics;
  p.projector_from_camera = c.projector.view_from_left;  // the left camera is the scan's camera
  return p;
}

TEST(ScanMonocular, BallCentreWithinSigmaAndSigmaMatchesScatterOver20Seeds) {
  const FringeSimulationConfig c = MonocularRig();
  const ProjectorCalibration calib = CalibrationOf(c);
  std::vector<PatternFrame> frames = ExpandSequence(c.sequence);
  RenderOptions ro;
  ro.supersampling = c.supersampling;
  ro.direction = c.direction;
  const RenderedView view = RenderView(c.scene, RenderedCameraView(c, 0), c.projector, frames, ro);
  const FringeManifest m = testing::ManifestForConfig(c);
  const Vec3 truth = c.scene.spheres.at(0).centre_in_left;
  const int seeds = 20;
  std::vector<Vec3> centres, sigmas;
  int beyond_2_sigma = 0;  // axis values; 4.6 % of 60 = 2.7 expected for honest sigma
  for (int seed = 1; seed <= seeds; ++seed) {
    std::vector<cv::Mat> images;
    for (std::size_t i = 0; i < frames.size(); ++i)
      images.push_back(ApplySensor(view.radiance[i], 1.0, c.sensor, static_cast<std::uint64_t>(seed), i));
    const ScanResult r = ScanMonocularFrames(m, calib, images, c.sensor.MaxValue(), ScanOptions());
    ASSERT_EQ(r.summary.spheres.spheres.size(), 1u) << r.summary.BriefReport();
    const SphereResult& s = r.summary.spheres.spheres[0];
    centres.push_back(s.centre_mm);
    sigmas.push_back(s.CentreSigma());
    const Vec3 e = s.centre_mm - truth;
    if (seed == 1) std::cout << r.summary.BriefReport() << "\n" << r.summary.projector.BriefReport() << "\n";
    EXPECT_LE(e.norm(), 2 * sigmas.back().norm()) << "seed " << seed << ": error " << e.transpose() * 1000 << " um";
    for (int k = 0; k < 3; ++k) beyond_2_sigma += std::abs(e[k]) > 2 * sigmas.back()[k] ? 1 : 0;
  }
  Vec3 mean = Vec3::Zero(), sigma_sq = Vec3::Zero();
  for (int i = 0; i < seeds; ++i) mean += centres[i] / seeds, sigma_sq += sigmas[i].cwiseAbs2() / seeds;
  Vec3 scatter_sq = Vec3::Zero();
  for (const Vec3& x : centres) scatter_sq += (x - mean).cwiseAbs2() / (seeds - 1);
  const double ratio = std::sqrt(sigma_sq.sum() / scatter_sq.sum());
  std::cout << "mean error (um) " << (mean - truth).transpose() * 1000 << "; predicted sigma (um) "
            << sigma_sq.cwiseSqrt().transpose() * 1000 << "; scatter (um) " << scatter_sq.cwiseSqrt().transpose() * 1000
            << "; predicted / scatter " << ratio << "\n";
  RecordProperty("sigma_over_scatter", std::to_string(ratio));
  for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(mean[k] - truth[k]), 2 * std::sqrt(sigma_sq[k] / seeds)) << k;
  EXPECT_LE(beyond_2_sigma, 7);  // P(Binomial(60, 0.046) > 7) < 1 %
  EXPECT_GE(ratio, 0.8);
  EXPECT_LE(ratio, 1.25);
}

// Both fringe directions rendered (the manifest's vertical set and its horizontal cross set):
// ray–ray (the default) gives the centre within 3 sigma of the truth over 5 seeds, with a centre
// sigma no larger than ray–plane's from the vertical set alone, and the summary names the method.
TEST(ScanMonocular, BothDirectionsTriangulateRayRay) {
  const FringeSimulationConfig c = MonocularRig();
  const ProjectorCalibration calib = CalibrationOf(c);
  std::vector<PatternFrame> frames = ExpandSequence(c.sequence);
  RenderOptions ro;
  ro.supersampling = c.supersampling;
  ro.direction = FringeDirection::kVertical;
  const RenderedView vertical = RenderView(c.scene, RenderedCameraView(c, 0), c.projector, frames, ro);
  ro.direction = FringeDirection::kHorizontal;
  const RenderedView horizontal = RenderView(c.scene, RenderedCameraView(c, 0), c.projector, frames, ro);
  FringeManifest m = testing::ManifestForConfig(c);
  m.direction = FringeDirection::kVertical;
  const Vec3 truth = c.scene.spheres.at(0).centre_in_left;
  for (int seed = 1; seed <= 5; ++seed) {
    std::vector<cv::Mat> u, v;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      u.push_back(ApplySensor(vertical.radiance[i], 1.0, c.sensor, static_cast<std::uint64_t>(seed), i));
      v.push_back(ApplySensor(horizontal.radiance[i], 1.0, c.sensor, static_cast<std::uint64_t>(seed + 100), i));
    }
    ScanOptions plane;
    plane.projector_ray_plane = true;
    const ScanResult rr = ScanMonocularFramesBothDirections(m, calib, u, v, c.sensor.MaxValue(), ScanOptions());
    const ScanResult rp = ScanMonocularFramesBothDirections(m, calib, u, v, c.sensor.MaxValue(), plane);
    EXPECT_EQ(rr.summary.projector_triangulation, "ray-ray");
    EXPECT_EQ(rp.summary.projector_triangulation, "ray-plane");
    ASSERT_EQ(rr.summary.spheres.spheres.size(), 1u) << rr.summary.BriefReport();
    ASSERT_EQ(rp.summary.spheres.spheres.size(), 1u) << rp.summary.BriefReport();
    const SphereResult& s = rr.summary.spheres.spheres[0];
    const Vec3 e = s.centre_mm - truth;
    if (seed == 1)
      std::cout << "ray-ray: " << rr.summary.projector.BriefReport() << "\nray-plane: " << rp.summary.projector.BriefReport()
                << "\n";
    std::cout << "seed " << seed << ": ray-ray error (um) " << e.transpose() * 1000 << ", sigma (um) "
              << s.CentreSigma().transpose() * 1000 << "; ray-plane sigma (um) "
              << rp.summary.spheres.spheres[0].CentreSigma().transpose() * 1000 << "\n";
    for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(e[k]), 3 * s.CentreSigma()[k]) << "seed " << seed << " axis " << k;
    EXPECT_LE(s.CentreSigma().norm(), rp.summary.spheres.spheres[0].CentreSigma().norm());
  }
}

}  // namespace
}  // namespace ramtk::vision
