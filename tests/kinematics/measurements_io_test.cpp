#include "ramtk/kinematics/measurements_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

TEST(MeasurementsIo, RoundTripWithExtraColumns) {
  RobotMeasurementSet set;
  set.extra_columns = {"temp_j2"};
  for (int k = 0; k < 3; ++k) {
    RobotMeasurement m;
    m.cycle = k / 2;
    m.time_s = 12.5 * k;
    m.index = k;
    m.q_controller << 0.1 * k, -1.2, 1.5, 0.3, 0.9, -0.4;
    m.position_mm = Vec3(1234.567891, -0.000123, 845.5);
    m.extra["temp_j2"] = 24.25 + k;
    set.rows.push_back(m);
  }
  const std::string path = ::testing::TempDir() + "/meas.csv";
  WriteRobotMeasurements(set, path);
  const RobotMeasurementSet back = ReadRobotMeasurements(path);
  std::remove(path.c_str());
  ASSERT_EQ(back.rows.size(), 3u);
  EXPECT_EQ(back.kind, MeasurementKind::kBall);
  EXPECT_EQ(back.extra_columns, set.extra_columns);
  for (int k = 0; k < 3; ++k) {
    // 9 decimals of a degree and 6 of a millimetre are what the file keeps.
    EXPECT_LT((back.rows[k].q_controller - set.rows[k].q_controller).cwiseAbs().maxCoeff(), DegToRad(1e-9));
    EXPECT_LT((back.rows[k].position_mm - set.rows[k].position_mm).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_EQ(back.rows[k].extra.at("temp_j2"), 24.25 + k);
    EXPECT_EQ(back.rows[k].line, k + 2);
  }
}

TEST(MeasurementsIo, MalformedNamesLineAndColumn) {
  const std::string path = ::testing::TempDir() + "/bad_meas.csv";
  WriteFileAtomically(path, "cycle,time_s,point,q1,q2,q3,q4,q5,q6,x,y,z\n0,0,1,0,0,0,0,0,0,1,2,3\n0,1,2,0,0,zz,0,0,0,1,2,3\n");
  try {
    ReadRobotMeasurements(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":3: field 'q3': expected a number, got 'zz'");
  }
  WriteFileAtomically(path, "cycle,time_s,q1,q2,q3,q4,q5,q6,x,y,z\n");
  EXPECT_THROW(ReadRobotMeasurements(path), InputError);  // neither pose nor point
  std::remove(path.c_str());
}

TEST(MeasurementsIo, TextColumnsAreCarriedThroughAndLimitsNamed) {
  // docs/formats.md: extra columns are carried through; a note or an operator name is text.
  const std::string text =
      "cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z,operator,note\n"
      "0,0,1,0,0,0,0,0,0,1,2,3,alice,\"warm-up, 2nd try\"\n"
      "0,1,2,0,0,0,0,0,0,1,2,3,bob,\n";
  const RobotMeasurementSet set = ParseRobotMeasurements(text, "notes.csv");
  ASSERT_EQ(set.rows.size(), 2u);
  EXPECT_EQ(set.rows[0].extra_text.at("operator"), "alice");
  EXPECT_EQ(set.rows[0].extra_text.at("note"), "warm-up, 2nd try");
  const RobotMeasurementSet again = ParseRobotMeasurements(FormatRobotMeasurements(set), "again.csv");
  EXPECT_EQ(again.rows[0].extra_text.at("note"), "warm-up, 2nd try");
  EXPECT_EQ(again.rows[1].extra_text.at("operator"), "bob");
  // The columns ramtk reads stay numeric, and values beyond the plausible range are named.
  EXPECT_THROW(ParseRobotMeasurements("cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z,temp_j1\n0,0,1,0,0,0,0,0,0,1,2,3,hot\n",
                                      "t.csv"),
               InputError);
  try {
    ParseRobotMeasurements("cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z\n0,0,1,0,0,0,0,0,0,1,2,1e6\n", "far.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().field, "z");
    EXPECT_NE(std::string(e.what()).find("kMaxAbsPositionMm"), std::string::npos);
  }
}

}  // namespace
}  // namespace ramtk::kinematics

namespace ramtk::kinematics {
namespace {

// The writer refuses what the reader would refuse, and writes nothing.
TEST(MeasurementsIo, WriterRefusesWhatTheReaderWouldRefuse) {
  const std::string dir = ::testing::TempDir();
  RobotMeasurementSet set;
  set.kind = MeasurementKind::kBall;
  RobotMeasurement m;
  m.q_controller << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6;
  m.position_mm = Vec3(1, 2, 3);
  set.rows.push_back(m);
  const std::string good = dir + "/writer_good.csv";
  WriteRobotMeasurements(set, good);
  EXPECT_EQ(ReadRobotMeasurements(good).rows.size(), 1u);

  RobotMeasurementSet bad = set;
  bad.rows[0].q_controller[2] = 5000.0 * 3.141592653589793 / 180.0;  // 5000°
  const std::string path = dir + "/writer_bad_joint.csv";
  std::remove(path.c_str());
  try {
    WriteRobotMeasurements(bad, path);
    FAIL() << "a joint of 5000 deg was written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not written"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("q3"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));

  RobotMeasurementSet cov = set;
  AddCentreCovarianceColumns(&cov);
  Mat3 c = Mat3::Identity() * 1e-4;
  c(0, 0) = -1e-4;  // a negative variance
  SetCentreCovariance(c, &cov.rows[0]);
  const std::string cov_path = dir + "/writer_bad_cov.csv";
  std::remove(cov_path.c_str());
  EXPECT_THROW(WriteRobotMeasurements(cov, cov_path), InputError);
  EXPECT_FALSE(std::filesystem::exists(cov_path));
}

}  // namespace
}  // namespace ramtk::kinematics
