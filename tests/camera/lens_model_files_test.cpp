// Calibration files carrying the rational and fisheye lens models: round trips in YAML, JSON and
// XML, files OpenCV's FileStorage writes without a model key, ROS's model names, and the errors
// for a coefficient vector the named model does not take.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

#include "ramtk/camera/opencv_camera.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("ramtk_lens_files_" + std::to_string(::getpid()) + "_" + name)).string();
}

StereoCalibration WideRig() {
  StereoCalibration c;
  c.left = {1210.5, 1208.25, 963.7, 601.2, {}, 1928, 1208};
  EXPECT_EQ(DistortionFromVector(
                {-0.21, 0.04, 1e-4, -3e-4, 0.002, 0.11, -0.02, 0.004, 1e-3, -2e-4, 5e-4, 1e-4, 0.003, -0.001},
                LensModel::kRational, &c.left.distortion),
            "");
  c.right = {612.25, 611.75, 640.5, 480.25, {}, 1280, 960};
  EXPECT_EQ(DistortionFromVector({0.021, -0.0043, 0.0011, -2.5e-4}, LensModel::kFisheye, &c.right.distortion), "");
  c.right_from_left.linear() = Eigen::AngleAxisd(0.2, Vec3(0.1, 1.0, 0.05).normalized()).toRotationMatrix();
  c.right_from_left.translation() = Vec3(-150.25, 1.5, 12.0);
  return c;
}

void ExpectSameLens(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  EXPECT_EQ(a.distortion.model, b.distortion.model);
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.cy, b.cy);
  EXPECT_EQ(a.width, b.width);
  const std::vector<double> x = DistortionVector(a.distortion), y = DistortionVector(b.distortion);
  ASSERT_EQ(x.size(), y.size());
  // FileStorage writes 17 significant digits: the coefficient vector round-trips exactly, but for
  // the tilt, held in degrees, whose radians may differ in the last bit.
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], y[i], i < 12 ? 0.0 : 1e-15 * std::abs(x[i])) << i;
}

TEST(CameraLensModelFiles, RoundTripInYamlJsonAndXml) {
  const StereoCalibration c = WideRig();
  for (const std::string ext : {".yml", ".json", ".xml"}) {
    const std::string path = TempPath("wide" + ext);
    WriteStereoCalibration(path, c);
    const StereoCalibration back = ReadStereoCalibration(path);
    ExpectSameLens(c.left, back.left);
    ExpectSameLens(c.right, back.right);
    EXPECT_EQ(back.right.width, 1280);
    EXPECT_EQ((c.right_from_left.matrix() - back.right_from_left.matrix()).cwiseAbs().maxCoeff(), 0.0);
    std::remove(path.c_str());
  }
  // The left lens is written with all 14 coefficients, the right with the fisheye's 4.
  const std::string yaml = StereoCalibrationText(c, false);
  EXPECT_NE(yaml.find("distortion_model1: rational"), std::string::npos);
  EXPECT_NE(yaml.find("distortion_model2: fisheye"), std::string::npos);
  EXPECT_NE(yaml.find("cols: 14"), std::string::npos);
  EXPECT_NE(yaml.find("cols: 4"), std::string::npos);
}

TEST(CameraLensModelFiles, FiveCoefficientFilesNameNoModel) {
  StereoCalibration c = WideRig();
  c.left.distortion = Distortion{-0.08, 0.12, 2e-4, -3e-4, 0.01};
  c.right.distortion = Distortion{};
  const std::string yaml = StereoCalibrationText(c, false);
  EXPECT_EQ(yaml.find("distortion_model"), std::string::npos);
  EXPECT_NE(yaml.find("cols: 5"), std::string::npos);
}

// What cv::FileStorage writes by itself (8 coefficients, no model key) in XML and YAML: the
// rational model, by the vector's length and its non-zero extra terms.
TEST(CameraLensModelFiles, ReadsOpenCvFilesWithoutAModelKey) {
  const cv::Matx33d k(900, 0, 640, 0, 900, 480, 0, 0, 1);
  const std::vector<double> d8 = {-0.3, 0.1, 1e-4, 2e-4, -0.01, 0.05, 0.02, 0.001};
  for (const std::string ext : {".xml", ".yml"}) {
    const std::string path = TempPath("plain" + ext);
    {
      cv::FileStorage out(path, cv::FileStorage::WRITE);
      out << "image_size" << cv::Size(1280, 960) << "K1" << cv::Mat(k) << "D1" << cv::Mat(d8).reshape(1, 1) << "K2"
          << cv::Mat(k) << "D2" << cv::Mat(d8).reshape(1, 1) << "R" << cv::Mat(cv::Matx33d::eye()) << "T"
          << cv::Mat(cv::Vec3d(-100, 0, 0));
    }
    const StereoCalibration c = ReadStereoCalibration(path);
    EXPECT_EQ(c.left.distortion.model, LensModel::kRational) << ext;
    EXPECT_EQ(DistortionVector(c.right.distortion), d8) << ext;
    EXPECT_EQ(c.left.fx, 900.0);
    std::remove(path.c_str());
  }
}

// Runs the reader on YAML `text` and returns the InputError message and its key.
std::string ReadError(const std::string& text, std::string* key) {
  const std::string path = TempPath("bad.yml");
  {
    std::ofstream out(path);
    out << text;
  }
  std::string message;
  try {
    ReadStereoCalibration(path);
  } catch (const InputError& e) {
    message = e.what();
    *key = e.where().field;
  }
  std::remove(path.c_str());
  return message;
}

std::string PlainYaml(const std::string& d1, const std::string& model_line) {
  return "image_size: [640, 512]\nK1: [500, 0, 320, 0, 500, 256, 0, 0, 1]\nD1: [" + d1 +
         "]\nK2: [500, 0, 320, 0, 500, 256, 0, 0, 1]\nD2: [0, 0, 0, 0, 0]\nR: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-200, "
         "0, 0]\n" +
         model_line;
}

TEST(CameraLensModelFiles, ModelKeysAndTheirErrors) {
  std::string key;
  // ROS's name of the fisheye model, for camera 1 only.
  EXPECT_EQ(ReadError(PlainYaml("0.01, 0.002, 0, 0", "distortion_model1: equidistant\n"), &key), "");
  const std::string path = TempPath("ros.yml");
  {
    std::ofstream out(path);
    out << PlainYaml("0.01, 0.002, 0, 0", "distortion_model1: equidistant\n");
  }
  const StereoCalibration c = ReadStereoCalibration(path);
  std::remove(path.c_str());
  EXPECT_EQ(c.left.distortion.model, LensModel::kFisheye);
  EXPECT_EQ(c.left.distortion.k2, 0.002);
  EXPECT_EQ(c.right.distortion.model, LensModel::kPinhole5);
  // The shared key applies to both cameras: D2's 5 values are not a fisheye vector.
  EXPECT_NE(ReadError(PlainYaml("0.01, 0.002, 0, 0", "distortion_model: fisheye\n"), &key).find("fisheye"),
            std::string::npos);
  EXPECT_EQ(key, "D2");
  EXPECT_NE(ReadError(PlainYaml("0, 0, 0, 0, 0", "distortion_model: kannala\n"), &key).find("unknown lens model"),
            std::string::npos);
  EXPECT_EQ(key, "distortion_model");
  EXPECT_NE(ReadError(PlainYaml("0, 0, 0, 0, 0, 0.1", ""), &key).find("4, 5, 8, 12 or 14"), std::string::npos);
  EXPECT_EQ(key, "D1");
}

}  // namespace
}  // namespace ramtk::camera
