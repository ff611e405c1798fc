// ramtk measure: joining scan-batch centres with the controller log (campaign/measure.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ramtk/campaign/controller_log.h"
#include "ramtk/campaign/measure.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::campaign {
namespace {
namespace fs = std::filesystem;

void Write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A folder with three captured sets (c0p1, c0p2, c1p1), a scan batch results.csv whose second
// set found no sphere, and each set's spheres.json with a full covariance.
class MeasureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ramtk_measure_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    const char* names[] = {"c0p1", "c0p2", "c1p1"};
    const double times[] = {10.0, 20.0, 610.0};
    for (int i = 0; i < 3; ++i) {
      Write(dir_ / "captures" / names[i] / "manifest.json",
            "{\"format\": \"ramtk-fringe-set\", \"capture_time_s\": " + std::to_string(times[i] + 0.2) + "}");
    }
    Write(dir_ / "scan" / "000_c0p1" / "spheres.json",
          R"({"spheres": [{"centre_mm": [1, 2, 3], "centre_covariance_mm2": [[4e-6, 1e-6, 0], [1e-6, 9e-6, 2e-6], [0, 2e-6, 2.5e-5]]}]})");
    Write(dir_ / "scan" / "002_c1p1" / "spheres.json",
          R"({"spheres": [{"centre_mm": [1, 2, 3], "centre_covariance_mm2": [[1e-6, 0, 0], [0, 1e-6, 0], [0, 0, 4e-6]]}]})");
    const std::string header =
        "set,status,points,x_mm,y_mm,z_mm,radius_mm,sigma_x_mm,sigma_y_mm,sigma_z_mm,rms_mm,num_points,num_outliers,"
        "seconds,out_dir,message\n";
    const std::string cap = (dir_ / "captures").string();
    const std::string scan = (dir_ / "scan").string();
    Write(dir_ / "scan" / "results.csv",
          header + cap + "/c0p1/manifest.json,ok,100,100.5,-20.25,800.125,19.05,0.002,0.003,0.005,0.01,90,1,0.5," + scan +
              "/000_c0p1,\n" + cap + "/c0p2/manifest.json,no sphere found,3,,,,,,,,,,,0.4," + scan +
              "/001_c0p2,\"too few points, 3\"\n" + cap + "/c1p1/manifest.json,ok,100,101.5,-21.25,801.125,19.05,0.001,0.001,0.002,0.01,90,1,0.5," +
              scan + "/002_c1p1,\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Log(bool with_set, const std::string& extra_row = "") {
    std::string text = with_set ? "set,time_s,cycle,pose,q1,q2,q3,q4,q5,q6,temp_j2\n" : "time_s,cycle,pose,q1,q2,q3,q4,q5,q6,temp_j2\n";
    const char* rows[] = {"c0p1,10.0,0,1,10,-80,90,0,30,45,20.5", "c0p2,20.0,0,2,15,-85,95,5,35,50,20.6",
                          "c1p1,610.0,1,1,10,-80,90,0,30,45,24.0"};
    for (const char* r : rows) {
      std::string s = r;
      text += (with_set ? s : s.substr(s.find(',') + 1)) + "\n";
    }
    text += extra_row;
    const fs::path p = dir_ / (with_set ? "log_set.csv" : "log_time.csv");
    Write(p, text);
    return p.string();
  }

  fs::path dir_;
};

TEST_F(MeasureTest, JoinsByIdWithFullCovarianceAndLeavesOutTheSetWithoutASphere) {
  const auto captures = ReadScanResults((dir_ / "scan" / "results.csv").string());
  ASSERT_EQ(captures.size(), 3u);
  EXPECT_FALSE(captures[1].has_sphere);
  EXPECT_EQ(captures[1].message, "too few points, 3");  // the quoted comma survives
  MeasureSummary s;
  const auto set = JoinCentresWithLog(captures, ReadControllerLog(Log(true)), {}, &s);
  EXPECT_EQ(s.match, "id");
  ASSERT_EQ(set.rows.size(), 2u);
  ASSERT_EQ(s.left_out.size(), 1u);
  EXPECT_EQ(s.left_out[0].cycle, 0);
  EXPECT_EQ(s.left_out[0].pose, 2);
  const auto& r0 = set.rows[0];
  EXPECT_EQ(r0.cycle, 0);
  EXPECT_EQ(r0.index, 1);
  EXPECT_DOUBLE_EQ(r0.time_s, 10.0);  // the controller's clock
  EXPECT_NEAR(RadToDeg(r0.q_controller[1]), -80.0, 1e-12);
  EXPECT_DOUBLE_EQ(r0.position_mm.x(), 100.5);
  EXPECT_DOUBLE_EQ(r0.extra.at("temp_j2"), 20.5);
  // Full covariance from spheres.json, not the diagonal of the CSV's sigmas.
  const Mat3 c = kinematics::CentreCovariance(r0, "x");
  EXPECT_DOUBLE_EQ(c(0, 1), 1e-6);
  EXPECT_DOUBLE_EQ(c(2, 2), 2.5e-5);
  EXPECT_EQ(set.rows[1].cycle, 1);

  // Round trip through the file keeps the covariance digits.
  const std::string out = (dir_ / "ball.csv").string();
  kinematics::WriteRobotMeasurements(set, out);
  const auto back = kinematics::ReadRobotMeasurements(out);
  ASSERT_TRUE(kinematics::HasCentreCovariance(back, out));
  EXPECT_NEAR(kinematics::CentreCovariance(back.rows[0], out)(1, 2), 2e-6, 1e-15);
}

TEST_F(MeasureTest, JoinsByNearestTimeWithinTheTolerance) {
  MeasureSummary s;
  const auto set = JoinCentresWithLog(ReadScanResults((dir_ / "scan" / "results.csv").string()),
                                      ReadControllerLog(Log(false)), {}, &s);
  EXPECT_EQ(s.match, "time");
  ASSERT_EQ(set.rows.size(), 2u);
  EXPECT_EQ(set.rows[1].cycle, 1);
  EXPECT_NEAR(s.worst_time_offset_s, 0.2, 1e-9);
  MeasureOptions tight;
  tight.time_tolerance_s = 0.1;
  try {
    JoinCentresWithLog(ReadScanResults((dir_ / "scan" / "results.csv").string()), ReadControllerLog(Log(false)), tight);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("log_time.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no log row within 0.1 s"), std::string::npos) << e.what();
  }
}

TEST_F(MeasureTest, ErrorsNameFileLineAndField) {
  try {
    ReadControllerLog(Log(true, "c9,700,0,1,1,2,3,4,5,6,20\n"));  // cycle 0 pose 1 twice
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 5);
    EXPECT_EQ(e.where().field, "cycle,pose");
  }
  try {
    ReadControllerLog(Log(true, "c9,abc,2,1,1,2,3,4,5,6,20\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 5);
    EXPECT_EQ(e.where().field, "time_s");
  }
  // The clock stepping back (30 s after 610 s on line 4) would match captures to the wrong rows.
  try {
    ReadControllerLog(Log(true, "c9,30,2,1,1,2,3,4,5,6,20\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 5);
    EXPECT_EQ(e.where().field, "time_s");
    EXPECT_NE(std::string(e.what()).find("the time goes backwards: 30.000 s after 610.000 s on line 4"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(ReadControllerLog(Log(true, "c9,610,2,1,1,2,3,4,5,6,20\n")));  // equal times: fine
  // Beyond the plausible ranges of the measurement files (kMaxAbsTimeS, kMaxAbsJointDeg).
  for (const char* row : {"c9,1e308,2,1,1,2,3,4,5,6,20\n", "c9,700,2,1,1e308,2,3,4,5,6,20\n"}) {
    try {
      ReadControllerLog(Log(true, row));
      FAIL() << row;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().line, 5);
      EXPECT_NE(std::string(e.what()).find("beyond the plausible range"), std::string::npos) << e.what();
    }
  }
  // A capture with a centre that the log does not name is an error, never dropped silently.
  Write(dir_ / "short.csv", "set,time_s,cycle,pose,q1,q2,q3,q4,q5,q6\nc0p1,10,0,1,0,0,0,0,0,0\n");
  try {
    JoinCentresWithLog(ReadScanResults((dir_ / "scan" / "results.csv").string()),
                       ReadControllerLog((dir_ / "short.csv").string()), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c1p1"), std::string::npos) << e.what();
  }
  // A half-given covariance is named.
  kinematics::RobotMeasurementSet bad;
  bad.extra_columns = {"cov_xx", "cov_yy"};
  try {
    kinematics::HasCentreCovariance(bad, "b.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "cov_zz");
  }
}

}  // namespace
}  // namespace ramtk::campaign

namespace ramtk::campaign {
namespace {

kinematics::RobotMeasurementSet Rows(const std::vector<std::pair<int, int>>& cycle_pose) {
  kinematics::RobotMeasurementSet s;
  for (const auto& [cycle, pose] : cycle_pose) {
    kinematics::RobotMeasurement r;
    r.cycle = cycle;
    r.index = pose;
    s.rows.push_back(r);
  }
  return s;
}

// The twin drops a pose that lost its centre in any cycle from both chains (the drift is
// measured pose by pose against the cold cycle): hand-made sets with the answer known.
TEST(DropPoses, APoseMissingInAnyCycleOrNeverMeasuredIsDropped) {
  // Planned: poses 1..4 in cycles 0..2. Pose 2 lost its centre in cycle 1; pose 4 never had one.
  std::vector<std::pair<int, int>> planned, measured;
  for (int c = 0; c < 3; ++c)
    for (int p = 1; p <= 4; ++p) {
      planned.push_back({c, p});
      if (p != 4 && !(p == 2 && c == 1)) measured.push_back({c, p});
    }
  const auto expected = Rows(planned), got = Rows(measured);
  const std::vector<int> missing = PosesMissingInSomeCycle(got, expected);
  EXPECT_EQ(missing, (std::vector<int>{2, 4}));
  const auto kept = DropPoses(got, missing);
  EXPECT_EQ(kept.rows.size(), 6u);  // poses 1 and 3 in three cycles
  for (const auto& r : kept.rows) EXPECT_TRUE(r.index == 1 || r.index == 3);
  // Nothing missing: nothing dropped, the set unchanged.
  EXPECT_TRUE(PosesMissingInSomeCycle(expected, expected).empty());
  EXPECT_EQ(DropPoses(expected, {}).rows.size(), expected.rows.size());
}

}  // namespace
}  // namespace ramtk::campaign
