// Simulated sensor-to-robot calibration measurements with known truth.
#include "ramtk/calib/sensor_robot_sim.h"

#include <Eigen/SVD>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "ramtk/core/error.h"
#include "ramtk/core/thesis_setup.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/inverse.h"

namespace ramtk::calib {

Isometry3 SensorRobotSimOptions::ThesisSensorFromBase() { return ramtk::ThesisSensorFromBase(); }

std::string SensorRobotSimOptions::Validate() const {
  if (num_poses < 1 || num_poses > 10000) return "num_poses must be in 1..10000";
  if (OrthonormalityError(sensor_from_base.linear()) > 1e-9) return "sensor_from_base is not a rigid transform";
  if (!(volume_half_size_mm >= 0.0)) return "volume_half_size_mm must be >= 0";
  if (!(max_tilt_deg >= 0.0 && max_tilt_deg <= 90.0)) return "max_tilt_deg must be in 0..90";
  if (std::string bad = CheckNoise("center_noise_mm", center_noise_mm, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  if (std::string bad = CheckNoise("repeatability_mm", repeatability_mm, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  return "";
}

SensorRobotSimulation SimulateSensorRobot(const kinematics::RobotModel& model, const SensorRobotSimOptions& options) {
  ThrowIfInvalid(options.Validate(), "SensorRobotSimOptions");
  SensorRobotSimulation sim;
  sim.sensor_from_base = options.sensor_from_base;
  sim.ball_in_flange = options.ball_in_flange;
  sim.center_noise_mm = options.center_noise_mm;
  sim.repeatability_mm = options.repeatability_mm;
  const Isometry3 base_from_sensor = options.sensor_from_base.inverse();
  const Vec3 center_in_base = base_from_sensor * options.volume_center_in_sensor;

  // Nominal flange orientation: flange Z horizontal, pointing from the robot axis at the
  // volume centre; flange X straight down.
  Vec3 out(center_in_base.x(), center_in_base.y(), 0.0);
  out = out.norm() > 1e-6 ? out.normalized() : Vec3::UnitX();
  Mat3 nominal;
  nominal.col(2) = out;
  nominal.col(0) = -Vec3::UnitZ();
  nominal.col(1) = nominal.col(2).cross(nominal.col(0));

  std::mt19937_64 geometry(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  kinematics::JointVector seed;
  seed << std::atan2(center_in_base.y(), center_in_base.x()) * model.mapping[0].sign, DegToRad(-60.0), DegToRad(100.0),
      0.0, DegToRad(30.0), 0.0;
  kinematics::InverseKinematicsOptions ik;
  ik.reach_position_tolerance_mm = 1e-6;
  std::vector<kinematics::JointVector> joints;
  int attempts = 0, unreachable = 0, off_branch = 0;
  while (static_cast<int>(joints.size()) < options.num_poses) {
    if (++attempts > 200 * options.num_poses) {
      throw std::runtime_error("simulator: could not reach enough poses around (" + std::to_string(center_in_base.x()) +
                               ", " + std::to_string(center_in_base.y()) + ", " + std::to_string(center_in_base.z()) +
                               ") mm in the base frame: " + std::to_string(unreachable) + " unreachable, " +
                               std::to_string(off_branch) + " off the seed's branch");
    }
    const Vec3 ball_in_base =
        center_in_base + options.volume_half_size_mm * Vec3(unit(geometry), unit(geometry), unit(geometry));
    Vec3 axis(unit(geometry), unit(geometry), unit(geometry));
    if (axis.norm() < 1e-3) continue;
    const double angle = DegToRad(options.max_tilt_deg) * std::sqrt(0.5 * (unit(geometry) + 1.0));
    const Mat3 rotation = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix() * nominal;
    Isometry3 target = Isometry3::Identity();
    target.linear() = rotation;
    target.translation() = ball_in_base - rotation * options.ball_in_flange;
    const kinematics::InverseKinematicsSummary s = kinematics::SolveInverseKinematics(model, target, seed, ik);
    if (!s.Converged()) {
      ++unreachable;
      continue;
    }
    // Stay on the seed's branch (elbow up, wrist not flipped) as a real teach would.
    kinematics::JointVector q = s.q_controller;
    for (int k = 0; k < kinematics::kNumJoints; ++k) q[k] = std::remainder(q[k], 2.0 * kPi);
    // Keep away from the wrist singularity (q5 = 0) and stay on the seed's arm branch (shoulder
    // and elbow within 90 deg of the seed), as a real teach would.
    if (std::abs(q[4]) < DegToRad(5.0) || (q.head<3>() - seed.head<3>()).cwiseAbs().maxCoeff() > DegToRad(90.0)) {
      ++off_branch;
      continue;
    }
    joints.push_back(q);
  }

  std::mt19937_64 noise(options.noise_seed * 0x9E3779B97F4A7C15ULL + 7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sigma_robot = options.repeatability_mm / 3.6;
  for (int i = 0; i < options.num_poses; ++i) {
    const Vec3 truth = PredictBallInSensor(model, sim.sensor_from_base, sim.ball_in_flange, joints[i]);
    const Vec3 robot_error(gauss(noise), gauss(noise), gauss(noise));
    const Vec3 center_error(gauss(noise), gauss(noise), gauss(noise));
    BallObservation o;
    o.q_controller = joints[i];
    o.ball_in_sensor =
        truth + sim.sensor_from_base.linear() * (sigma_robot * robot_error) + options.center_noise_mm * center_error;
    o.pose = i + 1;
    sim.true_ball_in_sensor.push_back(truth);
    sim.observations.push_back(o);
  }
  return sim;
}

std::string SensorRobotTruthJson(const SensorRobotSimulation& sim, const SensorRobotSimOptions& options) {
  nlohmann::json j;
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) {
    m.push_back({sim.sensor_from_base.matrix()(r, 0), sim.sensor_from_base.matrix()(r, 1),
                 sim.sensor_from_base.matrix()(r, 2), sim.sensor_from_base.matrix()(r, 3)});
  }
  j["sensor_from_base"] = m;
  j["ball_in_flange_mm"] = {sim.ball_in_flange.x(), sim.ball_in_flange.y(), sim.ball_in_flange.z()};
  j["center_noise_mm"] = sim.center_noise_mm;
  j["repeatability_mm"] = sim.repeatability_mm;
  j["num_poses"] = options.num_poses;
  j["seed"] = options.seed;
  j["noise_seed"] = options.noise_seed;
  j["max_tilt_deg"] = options.max_tilt_deg;
  j["volume_half_size_mm"] = options.volume_half_size_mm;
  j["volume_center_in_sensor_mm"] = {options.volume_center_in_sensor.x(), options.volume_center_in_sensor.y(),
                                     options.volume_center_in_sensor.z()};
  nlohmann::json truth = nlohmann::json::array();
  for (const Vec3& p : sim.true_ball_in_sensor) truth.push_back({p.x(), p.y(), p.z()});
  j["true_ball_in_sensor_mm"] = truth;
  return j.dump(2) + "\n";
}

kinematics::RobotMeasurementSet MeasurementsFromObservations(const std::vector<BallObservation>& obs) {
  kinematics::RobotMeasurementSet set;
  set.kind = kinematics::MeasurementKind::kBall;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    kinematics::RobotMeasurement m;
    m.cycle = 1;
    m.time_s = static_cast<double>(i);
    m.index = obs[i].pose;
    m.q_controller = obs[i].q_controller;
    m.position_mm = obs[i].ball_in_sensor;
    set.rows.push_back(m);
  }
  return set;
}

}  // namespace ramtk::calib
