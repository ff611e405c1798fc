// The camera's sampling kernel in calibration files: round trips in YAML, JSON and XML for a
// stereo pair and a single camera, absent = not stated (and no key written), the shared
// `sampling_kernel` key, and malformed kernels named by their key.
#include <gtest/gtest.h>

#include <string>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

StereoCalibration Pair() {
  StereoCalibration c;
  for (CameraIntrinsics* cam : {&c.left, &c.right}) {
    cam->fx = cam->fy = 1000;
    cam->cx = 319.5;
    cam->cy = 255.5;
    cam->width = 640;
    cam->height = 512;
  }
  c.right_from_left.translation() = Vec3(-200, 0, 0);
  return c;
}

const std::string kBase =
    "%YAML:1.0\n---\nimage_size: [ 640, 512 ]\n"
    "K1: [ 1000., 0., 320., 0., 1000., 256., 0., 0., 1. ]\nD1: [ 0., 0., 0., 0., 0. ]\n"
    "K2: [ 1000., 0., 320., 0., 1000., 256., 0., 0., 1. ]\nD2: [ 0., 0., 0., 0., 0. ]\n"
    "R: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\nT: [ -200., 0., 0. ]\n";

TEST(SamplingKernelFile, RoundTripsInEveryDialect) {
  StereoCalibration c = Pair();
  c.left.sampling_kernel = SamplingKernel{0.7, 0.35};
  c.right.sampling_kernel = SamplingKernel{1.0, 0.0};
  for (const CalibrationFormat format : {CalibrationFormat::kYaml, CalibrationFormat::kJson, CalibrationFormat::kXml}) {
    const StereoCalibration back = ParseStereoCalibration(StereoCalibrationText(c, format), "mem");
    ASSERT_TRUE(back.left.sampling_kernel.has_value());
    ASSERT_TRUE(back.right.sampling_kernel.has_value());
    EXPECT_EQ(*back.left.sampling_kernel, *c.left.sampling_kernel);
    EXPECT_EQ(*back.right.sampling_kernel, *c.right.sampling_kernel);
  }
  // A single camera file keeps its kernel (ReadCameraCalibration reads camera 1).
  const std::string text = CameraCalibrationText(c.left, 0.1, {}, {});
  EXPECT_NE(text.find("sampling_kernel1"), std::string::npos);
}

TEST(SamplingKernelFile, AbsentIsNotStatedAndWritesNoKey) {
  const StereoCalibration c = Pair();
  for (const CalibrationFormat format : {CalibrationFormat::kYaml, CalibrationFormat::kJson, CalibrationFormat::kXml}) {
    const std::string text = StereoCalibrationText(c, format);
    EXPECT_EQ(text.find("sampling_kernel"), std::string::npos);
    const StereoCalibration back = ParseStereoCalibration(text, "mem");
    EXPECT_FALSE(back.left.sampling_kernel.has_value());
    EXPECT_FALSE(back.right.sampling_kernel.has_value());
  }
}

TEST(SamplingKernelFile, SharedKeyAppliesToBothCamerasAndSuffixWins) {
  const StereoCalibration both =
      ParseStereoCalibration(kBase + "sampling_kernel: { fill_factor: 0.5, psf_sigma_px: 0.25 }\n", "mem");
  ASSERT_TRUE(both.left.sampling_kernel && both.right.sampling_kernel);
  EXPECT_EQ(both.right.sampling_kernel->fill_factor, 0.5);
  EXPECT_EQ(both.left.sampling_kernel->psf_sigma_px, 0.25);
  const StereoCalibration one = ParseStereoCalibration(
      kBase + "sampling_kernel: { fill_factor: 0.5, psf_sigma_px: 0.25 }\n"
              "sampling_kernel2: { fill_factor: 0., psf_sigma_px: 0. }\n",
      "mem");
  EXPECT_EQ(one.left.sampling_kernel->fill_factor, 0.5);
  EXPECT_EQ(one.right.sampling_kernel->fill_factor, 0.0);
}

TEST(SamplingKernelFile, MalformedKernelsNameTheirKey) {
  for (const std::string bad : {"sampling_kernel1: 0.5\n", "sampling_kernel1: { fill_factor: 0.5 }\n",
                                "sampling_kernel1: { fill_factor: 1.5, psf_sigma_px: 0. }\n",
                                "sampling_kernel1: { fill_factor: 0.5, psf_sigma_px: -1. }\n"}) {
    try {
      ParseStereoCalibration(kBase + bad, "mem");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("sampling_kernel1"), std::string::npos) << e.what();
    }
  }
}

TEST(SamplingKernel, VarianceOfBoxAndGaussian) {
  EXPECT_DOUBLE_EQ((SamplingKernel{1.0, 0.0}.VariancePx2()), 1.0 / 12.0);
  EXPECT_DOUBLE_EQ((SamplingKernel{0.0, 0.5}.VariancePx2()), 0.25);
  EXPECT_EQ(SamplingKernel{}.Validate(), "");
  EXPECT_NE(SamplingKernel({0.5, 11.0}).Validate(), "");
}

}  // namespace
}  // namespace ramtk::camera
