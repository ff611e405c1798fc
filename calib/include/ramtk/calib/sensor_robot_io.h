#pragma once
// Files of the sensor-to-robot calibration: the ball measurement CSV in (docs/formats.md,
// `cycle,time_s,pose,q1..q6,x,y,z`), the result JSON out (mm and degrees; format in docs/calib.md).

#include <string>
#include <vector>

#include "ramtk/calib/sensor_robot.h"

namespace ramtk::calib {

// Reads a ball measurement CSV. InputError names file:line and the column of a malformed row,
// a missing joint column, or a non-finite value; also a monitoring (`point`) file.
std::vector<BallObservation> ReadBallObservations(const std::string& path);

// The result as JSON text: sensor_from_base (4×4, translation mm, KUKA A,B,C deg), ball_in_flange
// (mm), standard deviations (arcsec, mm), the 9×9 covariance (rotation in deg, lengths in mm),
// per-pose residuals (mm), RMS and the summary.
std::string SensorRobotResultJson(const SensorRobotCalibration& calibration, const SensorRobotSummary& summary,
                                  const std::vector<BallObservation>& obs);
// Writes it atomically (temporary file + rename).
void WriteSensorRobotResult(const std::string& path, const SensorRobotCalibration& calibration,
                            const SensorRobotSummary& summary, const std::vector<BallObservation>& obs);

}  // namespace ramtk::calib
