// Bad input: malformed measurement files and pose sets that cannot determine the unknowns.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "ramtk/calib/sensor_robot_io.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/measurements_io.h"
#include "sensor_robot_test_util.h"

namespace ramtk::calib {
namespace {

using testing::Kr150;

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

const char* kHeader = "cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z\n";
const char* kGoodRow = "1,0.0,1,10,-80,95,20,35,-40,100.0,200.0,700.0\n";

std::string ErrorOf(const std::string& path) {
  try {
    ReadBallObservations(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SensorRobotInput, MalformedRowNamesTheLine) {
  const std::string path =
      WriteTemp("bad_row.csv", std::string(kHeader) + kGoodRow + "1,1.0,2,10,-80,95,20,abc,-40,1,2,3\n");
  const std::string e = ErrorOf(path);
  EXPECT_NE(e.find("bad_row.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("q5"), std::string::npos) << e;
}

TEST(SensorRobotInput, NanIsRefusedWithItsLine) {
  const std::string path =
      WriteTemp("nan.csv", std::string(kHeader) + kGoodRow + kGoodRow + "1,2.0,3,10,-80,95,20,35,-40,nan,2,3\n");
  const std::string e = ErrorOf(path);
  EXPECT_NE(e.find("nan.csv:4"), std::string::npos) << e;
}

TEST(SensorRobotInput, WrongJointCount) {
  // Five joint columns: q6 is missing from the header.
  const std::string path =
      WriteTemp("five_joints.csv", "cycle,time_s,pose,q1,q2,q3,q4,q5,x,y,z\n1,0,1,1,2,3,4,5,1,2,3\n");
  const std::string e = ErrorOf(path);
  EXPECT_NE(e.find("q6"), std::string::npos) << e;
  // A row with one joint value too few.
  const std::string path2 = WriteTemp("short_row.csv", std::string(kHeader) + kGoodRow + "1,1,2,1,2,3,4,5,1,2,3\n");
  const std::string e2 = ErrorOf(path2);
  EXPECT_NE(e2.find("short_row.csv:3"), std::string::npos) << e2;
}

TEST(SensorRobotInput, MonitoringFileIsNotABallFile) {
  const std::string path =
      WriteTemp("points.csv", "cycle,time_s,point,q1,q2,q3,q4,q5,q6,x,y,z\n" + std::string(kGoodRow));
  EXPECT_NE(ErrorOf(path).find("ball measurement"), std::string::npos);
}

TEST(SensorRobotInput, SimulatedFileRoundTrips) {
  const kinematics::RobotModel model = Kr150();
  const SensorRobotSimulation sim = SimulateSensorRobot(model, {});
  const std::string path = ::testing::TempDir() + "/sim_round_trip.csv";
  kinematics::WriteRobotMeasurements(MeasurementsFromObservations(sim.observations), path);
  const std::vector<BallObservation> back = ReadBallObservations(path);
  ASSERT_EQ(back.size(), sim.observations.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_LT((back[i].ball_in_sensor - sim.observations[i].ball_in_sensor).norm(), 1e-6);
    EXPECT_LT((back[i].q_controller - sim.observations[i].q_controller).norm(), 1e-10);
    EXPECT_EQ(back[i].line, static_cast<int>(i) + 2);
  }
}

std::string CalibrationError(const std::vector<BallObservation>& obs, bool thesis = false) {
  const kinematics::RobotModel model = Kr150();
  try {
    if (thesis) {
      CalibrateSensorRobotThesis(model, obs, {});
    } else {
      CalibrateSensorRobot(model, obs);
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SensorRobotPoseSet, FewerThanFivePosesIsAnError) {
  SensorRobotSimOptions o;
  o.num_poses = 4;
  const SensorRobotSimulation sim = SimulateSensorRobot(Kr150(), o);
  EXPECT_NE(CalibrationError(sim.observations).find("4 poses given; at least 5"), std::string::npos);
  EXPECT_NE(CalibrationError(sim.observations, true).find("at least 5"), std::string::npos);
}

TEST(SensorRobotPoseSet, PureTranslationsAreRefused) {
  SensorRobotSimOptions o;
  o.max_tilt_deg = 0.0;  // every pose has the same flange orientation
  const SensorRobotSimulation sim = SimulateSensorRobot(Kr150(), o);
  const std::string e = CalibrationError(sim.observations);
  EXPECT_NE(e.find("cannot be separated"), std::string::npos) << e;
  EXPECT_NE(e.find("condition number"), std::string::npos) << e;
}

TEST(SensorRobotPoseSet, RotationsAboutOneAxisOnlyAreNearSingular) {
  // Turning joint 6 alone rotates the flange about its Z axis: the ball offset along that axis is
  // indistinguishable from a sensor translation.
  const kinematics::RobotModel model = Kr150();
  SensorRobotSimOptions o;
  o.max_tilt_deg = 0.0;
  o.num_poses = 1;
  const SensorRobotSimulation one = SimulateSensorRobot(model, o);
  std::vector<BallObservation> obs;
  for (int i = 0; i < 8; ++i) {
    BallObservation b = one.observations[0];
    b.q_controller[5] += DegToRad(20.0 * i);
    b.ball_in_sensor = PredictBallInSensor(model, one.sensor_from_base, one.ball_in_flange, b.q_controller) +
                       Vec3(0.01 * ((i * 7) % 5 - 2), 0.01 * ((i * 3) % 5 - 2), 0.01 * ((i * 11) % 5 - 2));
    obs.push_back(b);
  }
  const std::string e = CalibrationError(obs);
  EXPECT_NE(e.find("near-singular pose set: condition number"), std::string::npos) << e;
  EXPECT_NE(CalibrationError(obs, true).find("condition number"), std::string::npos);
}

TEST(SensorRobotPoseSet, SmallTiltsWarnButSolve) {
  const kinematics::RobotModel model = Kr150();
  SensorRobotSimOptions o;
  o.max_tilt_deg = 5.0;
  const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
  SensorRobotSummary s;
  CalibrateSensorRobot(model, sim.observations, {}, &s);
  std::printf("%s\n", s.BriefReport().c_str());
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings[0].find("little rotation diversity"), std::string::npos) << s.warnings[0];
  EXPECT_GT(s.diagnostics.condition_number, SensorRobotOptions().checks.warn_condition_number);
}

}  // namespace
}  // namespace ramtk::calib
