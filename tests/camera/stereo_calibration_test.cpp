// Stereo calibration files: the real SLMaster caliInfo.yml (values typed from the file, and its
// own essential matrix E as an independent check of the R, T convention), write/read round trips
// in YAML and JSON, and malformed files that must name the file and key.
#include "ramtk/camera/stereo_calibration.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("ramtk_sim_calib_" + std::to_string(::getpid()) + "_" + name)).string();
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

TEST(SimStereoCalibration, ReadsSlmasterCaliInfo) {
  const std::string path = std::string(RAMTK_SHARED_DIR) + "/data/slmaster-binocular/caliInfo.yml";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  const StereoCalibration c = ReadStereoCalibration(path);
  // Values typed from the file.
  EXPECT_EQ(c.left.width, 1280);
  EXPECT_EQ(c.left.height, 1024);
  EXPECT_EQ(c.right.width, 1280);
  EXPECT_DOUBLE_EQ(c.left.fx, 1.7530279712582255e+03);
  EXPECT_DOUBLE_EQ(c.left.cy, 5.1146852562070677e+02);
  EXPECT_DOUBLE_EQ(c.right.fy, 1.7650942572782662e+03);
  EXPECT_DOUBLE_EQ(c.left.distortion.k3, 1.5137402885932413e-01);
  EXPECT_DOUBLE_EQ(c.right.distortion.p2, 6.1769783622975778e-05);
  EXPECT_DOUBLE_EQ(c.right_from_left.translation().x(), -1.9615657983156441e+02);
  EXPECT_DOUBLE_EQ(c.right_from_left.linear()(0, 2), 3.4283620429425404e-01);
  // Units: the baseline is ~200 mm, so T is in millimetres.
  EXPECT_NEAR(c.right_from_left.translation().norm(), 200.0, 1.0);
  // The file's own essential matrix E = [T]x R (typed from the file) confirms that Rlr, Tlr map
  // left-camera coordinates into the right camera (cv::stereoCalibrate's convention).
  const double e_file[9] = {-1.2172826761361839e-02, -3.9086789777494111e+01, 3.5679569151289503e-02,
                            -3.0531633681820416e+01, 6.9550924385852345e-03,  1.9766891595366951e+02,
                            -3.2606701889276439e-02, -1.9615658043776395e+02, -5.3447351790391739e-03};
  const Vec3 t = c.right_from_left.translation();
  Mat3 tx;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  const Mat3 e = tx * c.right_from_left.linear();
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(e(i / 3, i % 3), e_file[i], 1e-6) << i;
}

StereoCalibration ExampleCalibration() {
  StereoCalibration c;
  c.left = {7250.5, 7251.25, 1655.75, 1243.5, {-0.08, 0.12, 2e-4, -3e-4, 0.01}, 3312, 2488};
  c.right = {7249.0, 7248.5, 1650.0, 1240.25, {-0.07, 0.1, -1e-4, 2e-4, 0.0}, 3312, 2488};
  c.right_from_left.linear() =
      (Eigen::AngleAxisd(-0.28, Vec3::UnitY()) * Eigen::AngleAxisd(0.01, Vec3::UnitX())).toRotationMatrix();
  c.right_from_left.translation() = Vec3(-196.1, 0.04, 39.09);
  return c;
}

void ExpectSame(const StereoCalibration& a, const StereoCalibration& b) {
  for (const auto& [x, y] : {std::pair{a.left, b.left}, std::pair{a.right, b.right}}) {
    EXPECT_EQ(x.fx, y.fx);
    EXPECT_EQ(x.fy, y.fy);
    EXPECT_EQ(x.cx, y.cx);
    EXPECT_EQ(x.cy, y.cy);
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(x.distortion.k1, y.distortion.k1);
    EXPECT_EQ(x.distortion.k2, y.distortion.k2);
    EXPECT_EQ(x.distortion.p1, y.distortion.p1);
    EXPECT_EQ(x.distortion.p2, y.distortion.p2);
    EXPECT_EQ(x.distortion.k3, y.distortion.k3);
  }
  // FileStorage writes 17 significant digits: exact round trip.
  EXPECT_EQ((a.right_from_left.matrix() - b.right_from_left.matrix()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SimStereoCalibration, WriteReadRoundTripYamlAndJson) {
  StereoCalibration c = ExampleCalibration();
  c.rms_px = 0.0421;
  c.per_view_errors_px = {0.03, 0.05};
  for (const std::string ext : {".yml", ".json"}) {
    const std::string path = TempPath("round_trip" + ext);
    WriteStereoCalibration(path, c);
    const StereoCalibration back = ReadStereoCalibration(path);
    ExpectSame(c, back);
    EXPECT_EQ(back.rms_px, 0.0421);
    EXPECT_EQ(back.per_view_errors_px, c.per_view_errors_px);
    std::remove(path.c_str());
  }
}

// Runs the reader on `text` and returns the InputError message ("" if it did not throw).
std::string ReadError(const std::string& text, InputLocation* where = nullptr) {
  const std::string path = TempPath("bad.yml");
  WriteText(path, text);
  std::string message;
  try {
    ReadStereoCalibration(path);
  } catch (const InputError& e) {
    message = e.what();
    if (where) *where = e.where();
  }
  std::remove(path.c_str());
  return message;
}

std::string GoodYamlWith(const std::string& r_data, const std::string& k2_rows = "3") {
  return "%YAML:1.0\n---\n"
         "image_size: [ 640, 512 ]\n"
         "K1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1000., 0., 320., 0., 1000., 256., 0., 0., "
         "1. ]\n"
         "D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n"
         "K2: !!opencv-matrix\n   rows: " +
         k2_rows +
         "\n   cols: 3\n   dt: d\n   data: [ 1000., 0., 320., 0., 1000., 256., 0., 0., 1. ]\n"
         "D2: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n"
         "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ " +
         r_data +
         " ]\n"
         "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -200., 0., 0. ]\n";
}

TEST(SimStereoCalibration, MinimalStandardFileReads) {
  EXPECT_EQ(ReadError(GoodYamlWith("1., 0., 0., 0., 1., 0., 0., 0., 1.")), "");
}

TEST(SimStereoCalibration, NonRotationIsRejectedWithItsError) {
  InputLocation where;
  const std::string msg = ReadError(GoodYamlWith("1., 0.01, 0., 0., 1., 0., 0., 0., 1."), &where);
  EXPECT_EQ(where.field, "R");
  EXPECT_NE(msg.find("bad.yml"), std::string::npos) << msg;
  // RᵀR − I has an off-diagonal 0.01 entry: the reported error is 1.000e-02.
  EXPECT_NE(msg.find("not a rotation: orthonormality error 1.000e-02"), std::string::npos) << msg;
}

TEST(SimStereoCalibration, WrongSizeAndMissingKeysNameTheKey) {
  InputLocation where;
  std::string msg = ReadError(GoodYamlWith("1., 0., 0., 0., 1., 0., 0., 0., 1.", "1"), &where);
  EXPECT_EQ(where.field, "K2") << msg;
  std::string text = GoodYamlWith("1., 0., 0., 0., 1., 0., 0., 0., 1.");
  text = text.substr(0, text.find("T: !!"));
  msg = ReadError(text, &where);
  EXPECT_EQ(where.field, "T") << msg;
  EXPECT_NE(msg.find("missing key"), std::string::npos) << msg;
  text = GoodYamlWith("1., 0., 0., 0., 1., 0., 0., 0., 1.");
  text.replace(text.find("image_size"), 10, "image_sise");
  msg = ReadError(text, &where);
  EXPECT_EQ(where.field, "image_size") << msg;
  msg = ReadError("this: [is, not: a calibration", &where);
  EXPECT_NE(msg, "");
  try {
    ReadStereoCalibration("/nonexistent/calib.yml");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "/nonexistent/calib.yml");
  }
}

// The reader is our own (yaml-cpp / nlohmann-json, vision/src/calibration_tree.cpp), not
// cv::FileStorage, whose YAML parser hangs on a fuzz-found file (fuzz/crashes/...-timeout-*).
// It must still read what OpenCV writes, in both dialects, and say where a problem is.
TEST(SimStereoCalibration, ReadsWhatOpenCvWritesInBothDialects) {
  const StereoCalibration c = ExampleCalibration();
  for (const std::string ext : {".yml", ".json"}) {
    const std::string path = TempPath("opencv" + ext);
    WriteStereoCalibration(path, c);  // written by cv::FileStorage
    ExpectSame(c, ReadStereoCalibration(path));
    std::remove(path.c_str());
  }
  // Plain YAML without OpenCV's first line and tags, and plain JSON lists, read the same.
  const std::string plain =
      "image_size: [640, 512]\nK1: [1000, 0, 320, 0, 1000, 256, 0, 0, 1]\nD1: [0, 0, 0, 0, 0]\n"
      "K2: [1000, 0, 320, 0, 1000, 256, 0, 0, 1]\nD2: [0, 0, 0, 0, 0]\nR: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-200, 0, "
      "0]\n";
  EXPECT_EQ(ReadError(plain), "");
  // Nested lists are matrices by rows; a ragged one is an error on its row.
  std::string nested = plain;
  nested.replace(nested.find("R: [1, 0, 0, 0, 1, 0, 0, 0, 1]"), 30, "R: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]");
  EXPECT_EQ(ReadError(nested), "");
  nested.replace(nested.find("[0, 0, 1]]"), 10, "[0, 1]]   ");
  InputLocation where;
  EXPECT_NE(ReadError(nested, &where).find("rows of equal length"), std::string::npos);
  EXPECT_EQ(where.field, "R");
  EXPECT_EQ(where.line, 6);
}

TEST(SimStereoCalibration, ErrorsGiveTheLineOfTheKey) {
  InputLocation where;
  // The line of "R: !!opencv-matrix", counted in the text (line 1 is %YAML:1.0).
  const std::string text = GoodYamlWith("1., 0.01, 0., 0., 1., 0., 0., 0., 1.");
  int r_line = 1;
  for (std::size_t i = 0; i < text.find("R: !!"); ++i) r_line += text[i] == '\n';
  ReadError(text, &where);
  EXPECT_EQ(where.field, "R");
  EXPECT_EQ(where.line, r_line);
  // A syntax error names its line.
  ReadError("%YAML:1.0\n---\nK1: [1, 2\nD1: x: y\n", &where);
  EXPECT_GE(where.line, 3);
}

TEST(SimStereoCalibration, MalformedStructuresAreInputErrors) {
  InputLocation where;
  const std::string good = GoodYamlWith("1., 0., 0., 0., 1., 0., 0., 0., 1.");
  EXPECT_NE(ReadError(good + "K1: [1]\n", &where).find("duplicate key"), std::string::npos);
  EXPECT_EQ(where.field, "K1");
  std::string deep = "K1: ";
  for (int i = 0; i < 40; ++i) deep += "[";
  deep += "1";
  for (int i = 0; i < 40; ++i) deep += "]";
  EXPECT_NE(ReadError(deep).find("nested deeper"), std::string::npos);
  // XML is read by cv::FileStorage: its parse errors say XML; an empty storage misses the first key.
  EXPECT_NE(ReadError("<?xml version=\"1.0\"?>\n<opencv_storage/>\n").find("XML"), std::string::npos);
  const std::string empty_xml = ReadError("<?xml version=\"1.0\"?>\n<opencv_storage>\n</opencv_storage>\n");
  EXPECT_NE(empty_xml.find("missing key"), std::string::npos) << empty_xml;
  EXPECT_NE(ReadError("<?xml version=\"1.0\"?>\n<opencv_storage><K1>1 2</opencv_storage>\n"), "");
  std::string quoted = good;
  quoted.replace(quoted.find("-200."), 5, "\"-200\"");
  EXPECT_NE(ReadError(quoted, &where).find("expected a list of numbers"), std::string::npos);
  EXPECT_EQ(where.field, "T");
  std::string inf = good;
  inf.replace(inf.find("-200."), 5, ".Inf");
  EXPECT_NE(ReadError(inf).find("non-finite"), std::string::npos);
  EXPECT_NE(ReadError("{\"K1\": [1, 2,]}").find("not valid JSON"), std::string::npos);
  EXPECT_NE(ReadError("- K1\n- D1\n").find("top level is not a map"), std::string::npos);
  EXPECT_NE(ReadError(std::string(5u << 20, ' ')).find("at most"), std::string::npos);
}

}  // namespace
}  // namespace ramtk::camera
