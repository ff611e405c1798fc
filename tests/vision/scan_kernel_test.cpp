// The stereo matcher's kernel and interpolation terms against the simulator's truth: on
// SLMaster's rig (1280x1024, f = 1753 px, the ball ~120 px across: large pixels), a point-sampled
// noise-free render scans with a centre and radius bias of several µm when the calibration states
// no sampling kernel (the bilinear interpolant's curvature, docs/scan.md "Sampling kernel"); with
// the render's kernel stated the bias is gone to the noise-free residual; with a wrong kernel
// stated (a box pixel and a lens PSF) the kernel terms bias it several times more.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

struct Errors {
  Vec3 centre_um = Vec3::Zero();
  double radius_um = 0;
};

TEST(ScanKernel, StatedKernelRemovesTheCurvatureBiasOfLargePixels) {
  const std::string path = std::string(RAMTK_SHARED_DIR) + "/data/slmaster-binocular/caliInfo.yml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  FringeSimulationConfig c = MakeFringeConfigForCalibration(ReadStereoCalibration(path));
  c.supersampling = 1;  // one ray per pixel: the kernel is a point, fill factor 0
  c.sensor.noise = false;
  const SimulatedCamera l = SimulateCamera(c, 0), r = SimulateCamera(c, 1);
  const Sphere& ball = c.scene.spheres.at(0);
  auto scan = [&](std::optional<camera::SamplingKernel> kernel) {
    StereoCalibration calib = WrittenCalibration(c);
    calib.left.sampling_kernel = calib.right.sampling_kernel = kernel;
    ScanOptions o;
    o.roi.mode = ScanRoiOptions::Mode::kAuto;
    // Not stated means no kernel terms here (the estimate from the data: kernel_estimate_test.cpp).
    o.match.kernel_estimate = StereoMatchOptions::KernelEstimate::kOff;
    const ScanResult res = ScanFrames(testing::ManifestForConfig(c), calib, l.images, r.images, 255.0, o);
    EXPECT_FALSE(res.summary.spheres.spheres.empty());
    Errors e;
    if (res.summary.spheres.spheres.empty()) return e;
    const SphereResult& s = res.summary.spheres.spheres[0];
    e.centre_um = 1e3 * (s.centre_mm - ball.centre_in_left);
    e.radius_um = 1e3 * (s.radius_mm - ball.radius);
    std::printf("kernel %s: centre error (%+.2f, %+.2f, %+.2f) um, radius %+.2f um\n",
                kernel ? (std::to_string(kernel->fill_factor) + "," + std::to_string(kernel->psf_sigma_px)).c_str()
                       : "unstated",
                e.centre_um.x(), e.centre_um.y(), e.centre_um.z(), e.radius_um);
    return e;
  };
  // Not stated: the interpolant's bias (noise-free, full frame: (+2.0, 0.0, −5.3) µm, radius −5.1 µm).
  const Errors unstated = scan(std::nullopt);
  EXPECT_LT(unstated.centre_um.z(), -3.0);
  EXPECT_LT(unstated.radius_um, -3.0);
  // The render's kernel stated: within 1 µm ((+0.1, 0.0, −0.5) µm, radius −0.5 µm; the centre's
  // σ with noise is 0.7–2.8 µm per axis on this rig).
  const Errors stated = scan(camera::SamplingKernel{0.0, 0.0});
  EXPECT_LT(stated.centre_um.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT(std::abs(stated.radius_um), 1.0);
  // A wrong kernel (a box pixel and a 0.7 px PSF on a point-sampled render): −21 µm along z,
  // radius −17 µm.
  const Errors wrong = scan(camera::SamplingKernel{1.0, 0.7});
  EXPECT_LT(wrong.centre_um.z(), -10.0);
  EXPECT_LT(wrong.radius_um, -10.0);
}

}  // namespace
}  // namespace ramtk::vision
