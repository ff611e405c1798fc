// A robot cause added at run time beside the table's (ramtk/diagnose/engine/robot_causes.def): an
// effect on the measured ball that is linear in a few constant coefficients, given as its columns
// ∂ball/∂coefficient per measurement. Once registered, `DiagnoseRobotData` fits it like the table's
// causes (held-out score, look-alikes, plausibility) and names it when it wins, and
// `DrawHiddenRobotEffect` plants it when HiddenRobotOptions::effect names it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::diagnose {

// One measured ball centre as a cause's columns see it.
struct RobotCauseRow {
  kinematics::JointVector q = kinematics::JointVector::Zero();  // controller joints, rad
  double time_h = 0;                                            // hours since the first row
  int cycle = 0;                                                // cycle number of the file
  Eigen::Matrix<double, 3, kinematics::kNumParams> j_param;     // ∂ball/∂X, sensor frame (mm per mm or rad)
  Eigen::Matrix<double, 3, 9> j_setup;                          // ∂ball/∂[φ sensor, t sensor, ball in flange]
};

// One simulated measurement as the hidden-effect generator plants the cause in it.
struct RobotPlantRow {
  kinematics::JointVector q = kinematics::JointVector::Zero();  // controller joints, rad
  double time_h = 0;                                            // hours since the first row
  int cycle = 0;                                                // cycle number
  const kinematics::RobotModel* model = nullptr;                // the nominal robot
  Eigen::Isometry3d sensor_from_base = Eigen::Isometry3d::Identity();
  Eigen::Vector3d ball_in_flange = Eigen::Vector3d::Zero();     // mm
};

struct RobotColumnCause {
  EffectInfo info{"", DataKind::kRobot, "", "", ""};  // its catalogue row (kind kRobot)
  std::vector<std::string> keys;                       // report key of each coefficient, unit in the key
  std::vector<double> factors;                         // report unit per coefficient unit, one per key
  // ∂ball/∂coefficient (sensor frame, mm per coefficient unit): 3 × keys.size().
  std::function<Eigen::Matrix<double, 3, Eigen::Dynamic>(const RobotCauseRow&)> columns;
  bool drift = false;                       // changes with time (a static cause that predicts as well wins)
  std::map<std::string, double> truth;      // what the generator plants (report keys), for the draw's truth
  // The planted displacement of the ball (robot base frame, mm); empty: never planted.
  std::function<Eigen::Vector3d(const RobotPlantRow&)> displacement;
  std::string Validate() const;  // "" when usable, else the first problem as `field: what is wrong`
};

// Adds the cause to the catalogue and to the robot diagnosis, after the table's causes. InputError
// when it is invalid or its name is already registered.
void RegisterRobotCause(const RobotColumnCause& cause);

}  // namespace ramtk::diagnose
