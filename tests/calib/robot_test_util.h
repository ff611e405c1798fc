// Shared by the robot calibration and pose planning tests: the shipped robots and the quick options.
#pragma once

#include <string>

#include "ramtk/calib/robot_calibration.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::calib::test {

inline kinematics::RobotChain Robot(const std::string& file) {
  return kinematics::ReadRobotChain(std::string(RAMTK_DATASETS_DIR) + "/robots/" + file);
}

// Links only, 2 folds: what the structural and Monte-Carlo tests need, fast.
inline RobotCalibrationOptions Quick() {
  RobotCalibrationOptions o;
  o.try_cyclic = false;
  o.try_compliance = false;
  o.folds = 2;
  return o;
}

}  // namespace ramtk::calib::test
