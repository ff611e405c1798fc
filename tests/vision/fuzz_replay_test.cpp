// Replays every reproducer the fuzzers saved in fuzz/crashes/ (fuzz/run.sh) through the parser
// its target exercised: the only acceptable outcomes are a parsed value or an InputError. A
// reproducer stays in the repository after its fix, so the finding cannot come back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/measurements_io.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace fs = std::filesystem;

namespace {

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the parser named by the reproducer's prefix; returns false for an unknown prefix.
bool Replay(const std::string& name, const std::string& text) {
  try {
    if (name.rfind("fuzz_manifest-", 0) == 0) {
      const auto m = ramtk::vision::ParseFringeManifest(text, "/fuzz/manifest.json");
      (void)ramtk::vision::FringeManifestToJson(m);
    } else if (name.rfind("fuzz_csv-", 0) == 0) {
      (void)ramtk::ParseCsv(text, "fuzz.csv");
    } else if (name.rfind("fuzz_measurements-", 0) == 0) {
      (void)ramtk::kinematics::ParseRobotMeasurements(text, "fuzz.csv");
    } else if (name.rfind("fuzz_robot_yaml-", 0) == 0) {
      (void)ramtk::kinematics::ParseRobotModel(text, "fuzz.yaml");
    } else if (name.rfind("fuzz_laser_log-", 0) == 0) {
      (void)ramtk::tcf::ParseDeviceLog(text, "fuzz.csv");
    } else if (name.rfind("fuzz_tcf_json-", 0) == 0) {
      // First byte: odd = motion JSON, even = sensor JSON (fuzz/fuzz_tcf_json.cpp).
      if (text.empty()) return true;
      if (text[0] & 1)
        (void)ramtk::tcf::ProgrammedMotionFromJson(text.substr(1), "motion.json");
      else
        (void)ramtk::tcf::SensorFrameFromJson(text.substr(1), "sensor.json");
    } else if (name.rfind("fuzz_ply-", 0) == 0) {
      const fs::path path = fs::path(RAMTK_TEST_OUTPUT_DIR) / "fuzz_replay.ply";
      fs::create_directories(path.parent_path());
      std::ofstream(path, std::ios::binary) << text;
      ramtk::vision::ReadPly(path.string()).Check(path.string());
    } else if (name.rfind("fuzz_stereo_calibration-", 0) == 0) {
      (void)ramtk::camera::ParseStereoCalibration(text, "/fuzz/calibration.yml");
    } else if (name.rfind("fuzz_image-", 0) == 0) {
      const fs::path path = fs::path(RAMTK_TEST_OUTPUT_DIR) / "fuzz_replay_image.png";
      fs::create_directories(path.parent_path());
      std::ofstream(path, std::ios::binary) << text;
      int bits = 0;
      (void)ramtk::vision::LoadImageNative(path.string(), &bits);
    } else {
      return false;
    }
  } catch (const ramtk::InputError&) {
  }
  return true;
}

}  // namespace

TEST(FuzzReplay, EveryReproducerIsParsedOrRejectedAsBadInput) {
  const fs::path dir = fs::path(RAMTK_SOURCE_DIR) / "fuzz" / "crashes";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "no " << dir;
  int replayed = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    SCOPED_TRACE(name);
    // Any other exception escapes and fails the test with its message.
    EXPECT_TRUE(Replay(name, Slurp(e.path()))) << "unknown fuzz target prefix";
    ++replayed;
  }
  EXPECT_GT(replayed, 0);
}

// The first finding (fuzz_manifest, 2026-11-24): a number too large for a double made
// nlohmann::json throw out_of_range, which escaped the parse_error handler.
TEST(FuzzReplay, NumberOverflowInManifestIsAnInputError) {
  EXPECT_THROW(ramtk::vision::ParseFringeManifest("1e2222222", "m.json"), ramtk::InputError);
  EXPECT_THROW(ramtk::vision::ParseFringeManifest("{\"projector\": {\"width\": 1e999}}", "m.json"), ramtk::InputError);
}

// The stereo calibration finding (fuzz_stereo_calibration, 2026-11-24): a file whose top level is
// a list made OpenCV's key lookup throw cv::Exception instead of a bad-input error.
TEST(FuzzReplay, CalibrationWhoseTopLevelIsNotAMapIsAnInputError) {
  EXPECT_THROW(ramtk::camera::ParseStereoCalibration("%YAML:1.0\n- 1\n- 2\n", "c.yml"), ramtk::InputError);
  EXPECT_THROW(ramtk::camera::ParseStereoCalibration("[1, 2]", "c.json"), ramtk::InputError);
}

// The third (same target): a malformed file on which OpenCV's own parser throws
// std::length_error is bad input too (the reproducer is fuzz_stereo_calibration-crash-e780…,
// replayed above).

// The second (same target): an opencv-matrix whose "rows" was not a number made OpenCV allocate
// gigabytes before anything was checked.
TEST(FuzzReplay, CalibrationMatrixWithACorruptSizeIsAnInputError) {
  const std::string head = "%YAML:1.0\nK1: !!opencv-matrix\n   rows: ";
  const std::string tail = "\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n";
  for (const std::string rows : {"s", "100000000", "2", "-3"})
    EXPECT_THROW(ramtk::camera::ParseStereoCalibration(head + rows + tail, "c.yml"), ramtk::InputError) << rows;
}
