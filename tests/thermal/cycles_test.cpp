// Cycle grouping and setup files: the bad inputs of the issue are InputErrors naming file/line/field.
#include "ramtk/thermal/cycles.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::thermal {
namespace {

kinematics::RobotMeasurementSet Parse(const std::string& text) {
  // One file per test: ctest runs the tests of this file as parallel processes.
  const std::string path = ::testing::TempDir() + "/cycles_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv";
  WriteFileAtomically(path, text);
  kinematics::RobotMeasurementSet set = kinematics::ReadRobotMeasurements(path);
  std::remove(path.c_str());
  return set;
}

const char* kHeader = "cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z,temp_j2\n";

std::string Row(int cycle, int pose, double q1, double x) {
  char buf[200];
  std::snprintf(buf, sizeof(buf), "%d,%d,%d,%g,-90,90,0,30,0,%g,0,700,%d\n", cycle, 10 * cycle + pose, pose, q1, x,
                22 + cycle);
  return buf;
}

std::string ErrorOf(const std::string& text, CycleOptions o = {}) {
  try {
    GroupCycles(Parse(text), "ball.csv", o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ThermalCycles, GroupsAndDifferences) {
  const std::string text =
      std::string(kHeader) + Row(0, 0, 10, 1.0) + Row(0, 1, 20, 2.0) + Row(1, 1, 20, 2.5) + Row(1, 0, 10, 0.5);
  const CycleSeries s = GroupCycles(Parse(text), "ball.csv");
  ASSERT_EQ(s.NumCycles(), 2);
  ASSERT_EQ(s.NumPoses(), 2);
  const Eigen::MatrixXd y = s.DifferencesFromReference();
  EXPECT_DOUBLE_EQ(y(0, 1), -0.5);  // pose 0 x
  EXPECT_DOUBLE_EQ(y(3, 1), 0.5);   // pose 1 x
  EXPECT_DOUBLE_EQ(y(0, 0), 0.0);
  EXPECT_DOUBLE_EQ(s.cycles[1].extra.at("temp_j2"), 23.0);
  EXPECT_DOUBLE_EQ(s.cycles[1].time_s, 10.5);
}

TEST(ThermalCycles, MissingColdReferenceCycle) {
  const std::string text = std::string(kHeader) + Row(1, 0, 10, 1.0) + Row(2, 0, 10, 1.0);
  EXPECT_NE(ErrorOf(text).find("ball.csv: field 'cycle': the cold reference cycle 0 is missing"), std::string::npos)
      << ErrorOf(text);
  CycleOptions o;
  o.reference_cycle = 1;
  EXPECT_EQ(ErrorOf(text, o), "");
}

TEST(ThermalCycles, InconsistentPoseSets) {
  const std::string base = std::string(kHeader) + Row(0, 0, 10, 1.0) + Row(0, 1, 20, 2.0);
  // A pose missing from cycle 1.
  std::string e = ErrorOf(base + Row(1, 0, 10, 1.0));
  EXPECT_NE(e.find("cycle 1 lacks pose 1"), std::string::npos) << e;
  // A pose that the reference does not have (line 6).
  e = ErrorOf(base + Row(1, 0, 10, 1.0) + Row(1, 1, 20, 1.0) + Row(1, 2, 20, 1.0));
  EXPECT_NE(e.find("ball.csv:6: field 'pose': pose 2 of cycle 1 is not in the reference cycle 0"), std::string::npos)
      << e;
  // The same pose id at different joints (line 5).
  e = ErrorOf(base + Row(1, 0, 10.5, 1.0) + Row(1, 1, 20, 1.0));
  EXPECT_NE(e.find("ball.csv:4: field 'q1..q6': pose 0 of cycle 1 has joints 0.5"), std::string::npos) << e;
  // A pose twice in one cycle.
  e = ErrorOf(base + Row(1, 0, 10, 1.0) + Row(1, 0, 10, 1.0) + Row(1, 1, 20, 1.0));
  EXPECT_NE(e.find("appears twice in cycle 1"), std::string::npos) << e;
}

TEST(ThermalSetupFile, RoundTripAndThesisValues) {
  ThermalSetup s;
  s.sensor_from_base = ThesisSensorFromBase();
  s.ball_in_flange = ThesisBallInFlange();
  s.flange_from_tool_sensor.translation() = Vec3(1, 2, 3);
  s.has_tool_sensor = true;
  // Eq. (5-1) printed to 4 decimals: the re-orthonormalised rotation stays within 1e-3 of it.
  Mat3 printed;
  printed << 0.9003, -0.1695, -0.4009, -0.1695, 0.7117, -0.6817, 0.4009, 0.6817, 0.6120;
  EXPECT_LT((s.sensor_from_base.linear() - printed).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(OrthonormalityError(s.sensor_from_base.linear()), 1e-12);
  const std::string path = ::testing::TempDir() + "/setup.json";
  WriteThermalSetup(s, path);
  const ThermalSetup back = ReadThermalSetup(path);
  EXPECT_TRUE(back.sensor_from_base.isApprox(s.sensor_from_base, 1e-12));
  EXPECT_TRUE(back.ball_in_flange.isApprox(Vec3(43.0823, -5.6419, 306.7015), 1e-12));
  EXPECT_TRUE(back.has_tool_sensor);
  EXPECT_TRUE(back.flange_from_tool_sensor.translation().isApprox(Vec3(1, 2, 3)));
  WriteFileAtomically(path, R"({"sensor_from_base": [[1,0,0,0],[0,2,0,0],[0,0,1,0]], "ball_in_flange_mm": [0,0,1]})");
  try {
    ReadThermalSetup(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'sensor_from_base': rotation part is not orthonormal"),
              std::string::npos)
        << e.what();
  }
  WriteFileAtomically(path, R"({"sensor_from_base": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]})");
  EXPECT_THROW(ReadThermalSetup(path), InputError);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ramtk::thermal
