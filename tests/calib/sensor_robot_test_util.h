#pragma once
// Helpers for the sensor-to-robot tests: the KR150 model and errors against truth.
#include <string>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/calib/sensor_robot_sim.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::calib::testing {

inline kinematics::RobotModel Kr150() {
  return kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
}

struct Errors {
  double rotation_arcsec = 0.0;  // angle between the estimated (projected) and true rotation
  double translation_um = 0.0;
  double ball_um = 0.0;
};

inline Errors ErrorsAgainstTruth(const SensorRobotCalibration& c, const SensorRobotSimulation& sim) {
  Errors e;
  // The thesis method's rotation may be slightly non-orthonormal: compare its polar projection.
  Eigen::JacobiSVD<Mat3> svd(c.sensor_from_base.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3 r = svd.matrixU() * svd.matrixV().transpose();
  e.rotation_arcsec = RotationAngleBetween(r, sim.sensor_from_base.linear()) * kArcsecPerRad;
  e.translation_um = (c.sensor_from_base.translation() - sim.sensor_from_base.translation()).norm() * 1000.0;
  e.ball_um = (c.ball_in_flange - sim.ball_in_flange).norm() * 1000.0;
  return e;
}

}  // namespace ramtk::calib::testing
