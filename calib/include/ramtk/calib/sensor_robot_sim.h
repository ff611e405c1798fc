#pragma once
// Simulator of the sensor-to-robot calibration measurement (thesis §3.3, §5.1.1): a fixed sensor
// measures the centre of a ball carried by the robot at N poses with diverse flange orientations.
// Truth defaults to the thesis's measured values, eq. (5-1) (projected onto SO(3)) and eq. (5-2).

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/rotation.h"
#include "ramtk/core/thesis_setup.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::calib {

struct SensorRobotSimOptions {
  int num_poses = 9;  // thesis §5.1.1 uses 9
  // Truth; defaults to eq. (5-1) with the rotation projected onto SO(3).
  Isometry3 sensor_from_base = ThesisSensorFromBase();
  Vec3 ball_in_flange = ThesisBallInFlange();  // eq. (5-2), mm (core/thesis_setup.h)
  // Centre of the measurement volume in the sensor frame (mm) and the half-size of the box the
  // ball centres are drawn from (the thesis sensor sees ≈570×430 mm at 700 mm).
  Vec3 volume_center_in_sensor = Vec3(0.0, 0.0, 700.0);
  double volume_half_size_mm = 150.0;
  // Flange orientations: a nominal orientation facing the volume, turned about a random axis by
  // a random angle up to this (deg); the poses then differ by up to twice this.
  double max_tilt_deg = 35.0;
  // Sphere-centre noise per axis, sensor frame (mm, 1σ). A fringe scanner gives 5–20 µm.
  double center_noise_mm = 0.010;
  // Robot position repeatability, ISO 9283 RP (mm). Simulated as an isotropic Gaussian offset of
  // the ball in the base frame with σ per axis = RP / 3.6 (RP = mean + 3σ of the distance for a
  // 3-D Gaussian).
  double repeatability_mm = 0.05;
  std::uint64_t seed = 1;        // geometry (poses)
  std::uint64_t noise_seed = 1;  // noise; vary this alone for Monte-Carlo over a fixed pose set

  static Isometry3 ThesisSensorFromBase();  // eq. (5-1), rotation projected onto SO(3)
  std::string Validate() const;
};

struct SensorRobotSimulation {
  std::vector<BallObservation> observations;           // noisy
  std::vector<Vec3> true_ball_in_sensor;               // noise-free
  Isometry3 sensor_from_base = Isometry3::Identity();  // truth
  Vec3 ball_in_flange = Vec3::Zero();                  // truth
  double center_noise_mm = 0.0;
  double repeatability_mm = 0.0;
};

// InputError if the options are invalid; std::runtime_error if no reachable poses are found.
SensorRobotSimulation SimulateSensorRobot(const kinematics::RobotModel& model, const SensorRobotSimOptions& options);

// Truth as JSON text (mm, deg) and the observations as a ball measurement set.
std::string SensorRobotTruthJson(const SensorRobotSimulation& sim, const SensorRobotSimOptions& options);
kinematics::RobotMeasurementSet MeasurementsFromObservations(const std::vector<BallObservation>& obs);

}  // namespace ramtk::calib
