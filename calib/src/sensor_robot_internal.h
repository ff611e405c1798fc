#pragma once
// Helpers shared by the two sensor-to-robot estimators (not installed).

#include <vector>

#include "ramtk/calib/sensor_robot.h"

namespace ramtk::calib::internal {

// Residuals measured − predicted, RMS and worst residual of `c` over `obs`.
void FillResiduals(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                   SensorRobotCalibration* c);
// RMS, worst pose and outliers (|r| > outlier_factor·median |r|) of `c` into the summary.
void FillSummaryResiduals(const SensorRobotCalibration& c, double outlier_factor, SensorRobotSummary* s);
// Diagnoses the pose set (ball offset from the closed-form solution); InputError (field "poses")
// if it must be refused; warnings are logged and returned in the diagnostics.
PoseSetDiagnostics CheckPoseSetOrThrow(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                                       const PoseSetCheckOptions& checks);

}  // namespace ramtk::calib::internal
