#pragma once
// Robot measurement files (docs/formats.md): controller joints plus a point measured by a sensor.
//   ball measurements:       cycle,time_s,pose,q1,...,q6,x,y,z   (ball centre in the sensor frame)
//   monitoring measurements: cycle,time_s,point,q1,...,q6,x,y,z  (point in the tool-sensor frame)
// Joints in degrees and positions in mm in the file; radians and mm in memory. Extra columns
// (for example temp_j2) are carried through by name.

#include <map>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {

struct RobotMeasurement {
  int cycle = 0;
  double time_s = 0.0;
  int index = 0;                          // the `pose` (ball files) or `point` (monitoring) column
  JointVector q_controller = JointVector::Zero();  // rad
  Vec3 position_mm = Vec3::Zero();        // ball_in_sensor, or the monitored point in the tool sensor
  std::map<std::string, double> extra;    // extra numeric columns by name
  int line = 0;                           // 1-based line in the file it came from (0 if none)
};

enum class MeasurementKind { kBall, kMonitoring };  // `pose` or `point` index column

struct RobotMeasurementSet {
  MeasurementKind kind = MeasurementKind::kBall;
  std::vector<std::string> extra_columns;  // in file order
  std::vector<RobotMeasurement> rows;
};

// Reads either kind (decided by the presence of a `pose` or `point` column). InputError names
// the file, line and column of anything malformed.
RobotMeasurementSet ReadRobotMeasurements(const std::string& path);
// Writes atomically (no half-written file); positions with 6 decimals (nm), joints with 9.
void WriteRobotMeasurements(const RobotMeasurementSet& set, const std::string& path);
std::string FormatRobotMeasurements(const RobotMeasurementSet& set);

}  // namespace ramtk::kinematics
