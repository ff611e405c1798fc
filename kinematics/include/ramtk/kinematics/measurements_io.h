#pragma once
// Robot measurement files (docs/formats.md): controller joints plus a point measured by a sensor.
//   ball measurements:       cycle,time_s,pose,q1,...,q6,x,y,z   (ball centre in the sensor frame)
//   monitoring measurements: cycle,time_s,point,q1,...,q6,x,y,z  (point in the tool-sensor frame)
// Joints in degrees and positions in mm in the file; radians and mm in memory. Extra columns
// (for example temp_j2) are carried through by name.

#include <array>
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
  // Extra cells that are not numbers (an operator's name, a note), carried through as text. The
  // columns ramtk reads (cov_*, temp_j*) must be numbers.
  std::map<std::string, std::string> extra_text;
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
// The same from the file's text (`path` names it in errors).
RobotMeasurementSet ParseRobotMeasurements(const std::string& text, const std::string& path);

// Plausibility limits of ReadRobotMeasurements: a value beyond them is an InputError naming the
// file, line, column and the limit (a corrupt file must not reach the solvers).
inline constexpr double kMaxAbsPositionMm = 1e5;  // 100 m: any robot cell
inline constexpr double kMaxAbsJointDeg = 1080.0;  // three turns
inline constexpr double kMaxAbsTimeS = 1e10;       // 317 years: unix seconds fit
// Writes atomically (no half-written file); positions with 6 decimals (nm), joints with 9, extra
// columns with 10 significant digits (a covariance of 1e-7 mm² keeps its digits). A set the reader
// would refuse (a value beyond the limits below, a covariance not positive definite) is an
// InputError naming the row and column, and nothing is written.
void WriteRobotMeasurements(const RobotMeasurementSet& set, const std::string& path);
std::string FormatRobotMeasurements(const RobotMeasurementSet& set);

// Optional extra columns of a ball file: the covariance of the measured centre (mm², the
// sensor frame), written by `ramtk measure` from the scan's sphere fit. When present, the
// sensor-to-robot calibration and the thermal identification weight each centre by it.
inline constexpr std::array<const char*, 6> kCentreCovarianceColumns = {"cov_xx", "cov_yy", "cov_zz",
                                                                       "cov_xy", "cov_xz", "cov_yz"};
// True when the set has all six columns; InputError naming the file and the missing column when
// it has only some of them.
bool HasCentreCovariance(const RobotMeasurementSet& set, const std::string& path);
// The row's 3×3 covariance (mm²) from those columns. InputError naming path:line and the column
// when it is not symmetric positive definite (a zero or negative variance, |correlation| ≥ 1).
Mat3 CentreCovariance(const RobotMeasurement& row, const std::string& path);
// Stores a covariance into the row's extra columns (adds the names to set.extra_columns once).
void SetCentreCovariance(const Mat3& covariance_mm2, RobotMeasurement* row);
void AddCentreCovarianceColumns(RobotMeasurementSet* set);

}  // namespace ramtk::kinematics
