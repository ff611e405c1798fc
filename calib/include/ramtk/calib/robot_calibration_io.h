#pragma once
// Files of `ramtk calib robot` (docs/formats.md, "Robot calibration outputs"), written into one
// folder: robot.yaml (the calibrated robot file every command reads), calibration.json (the
// unknowns with σ, the set-up, identifiability, residual statistics, covariance) and
// residuals.csv (per pose: before, after, held-out).

#include <string>

#include "ramtk/calib/robot_calibration.h"

namespace ramtk::calib {

std::string RobotCalibrationJson(const RobotCalibration& calibration, const RobotCalibrationSummary& summary);
std::string RobotCalibrationResidualsCsv(const kinematics::TrackerMeasurements& data,
                                         const RobotCalibrationSummary& summary);
// The table of unknowns as text (for the terminal): name, status, nominal, value, σ, combination.
std::string RobotCalibrationTable(const RobotCalibration& calibration);

}  // namespace ramtk::calib
