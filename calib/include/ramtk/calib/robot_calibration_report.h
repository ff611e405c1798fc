#pragma once
// The page of `ramtk calib robot --report` (docs/robot_calibration.md): the summary, the table of
// unknowns with their identifiability, the residual per pose before / after / held-out, the
// residual against each joint, and the measured points in 3-D coloured by their residual.

#include "ramtk/calib/robot_calibration.h"
#include "ramtk/report/html_report.h"

namespace ramtk::calib {

report::HtmlReport RobotCalibrationReport(const RobotCalibration& calibration, const RobotCalibrationSummary& summary,
                                          const kinematics::TrackerMeasurements& data);

}  // namespace ramtk::calib
