#include "ramtk/calib/robot_calibration_sim.h"

#include <Eigen/Geometry>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {

std::string RobotCalibrationSimOptions::Validate() const {
  if (num_poses < 1 || num_poses > 1000000) return "num_poses: expected 1..1e6";
  if (!(joint_range_deg > 0.0 && joint_range_deg <= 360.0)) return "joint_range_deg: expected (0, 360]";
  if (std::string bad = CheckNoise("length_error_mm", length_error_mm, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  if (std::string bad = CheckNoise("angle_error_deg", angle_error_deg, kMaxNoiseDeg, "deg"); !bad.empty()) return bad;
  if (targets_in_flange.empty()) return "targets_in_flange: expected at least one target";
  if (std::string bad = CheckNoise("position_noise_mm", position_noise_mm, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  if (std::string bad = CheckNoise("rotation_noise_deg", rotation_noise_deg, kMaxNoiseDeg, "deg"); !bad.empty())
    return bad;
  return "";
}

Isometry3 RobotCalibrationSimOptions::DefaultTrackerFromBase() {
  Isometry3 t = Isometry3::Identity();
  t.linear() = RotZ(2.4) * RotX(0.05);
  t.translation() = Vec3(2500.0, -800.0, 300.0);
  return t;
}

RobotCalibrationSimulation SimulateRobotCalibration(const kinematics::RobotChain& nominal,
                                                    const RobotCalibrationSimOptions& o) {
  ThrowIfInvalid(o.Validate(), "RobotCalibrationSimOptions");
  const int n = nominal.NumJoints();
  if (!o.perturb.empty() && static_cast<int>(o.perturb.size()) != nominal.NumParams()) {
    throw InputError({"", 0, "perturb"}, "expected one flag per link unknown");
  }
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  RobotCalibrationSimulation sim;
  sim.truth = nominal;
  Eigen::VectorXd p = nominal.Params();
  for (int i = 0; i < nominal.NumParams(); ++i) {
    const bool perturb = o.perturb.empty() ? !nominal.structural_zero[i] : o.perturb[i];
    if (!perturb) continue;
    p[i] += normal(rng) * (kinematics::IsChainAngleParam(i) ? DegToRad(o.angle_error_deg) : o.length_error_mm);
    sim.truth.structural_zero[i] = false;
  }
  sim.truth.SetParams(p);

  std::uniform_real_distribution<double> joint(-DegToRad(o.joint_range_deg), DegToRad(o.joint_range_deg));
  std::mt19937_64 noise_rng(o.noise_seed);
  kinematics::TrackerMeasurements& data = sim.data;
  data.num_joints = n;
  data.has_rotation = o.six_d;
  for (std::size_t k = 0; k < o.targets_in_flange.size(); ++k) data.target_names.push_back("t" + std::to_string(k + 1));
  for (int i = 0; i < o.num_poses; ++i) {
    kinematics::TrackerPose pose;
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) q[j] = joint(rng);
    pose.q_rad.assign(q.data(), q.data() + n);
    const Isometry3 tracker_from_flange = o.tracker_from_base * kinematics::ChainBaseFromFlange(sim.truth, q);
    for (std::size_t k = 0; k < o.targets_in_flange.size(); ++k) {
      kinematics::TargetMeasurement t;
      t.target = static_cast<int>(k);
      const Vec3 noise(normal(noise_rng), normal(noise_rng), normal(noise_rng));
      t.position_mm = tracker_from_flange * o.targets_in_flange[k] + o.position_noise_mm * noise;
      pose.targets.push_back(t);
    }
    if (o.six_d) {
      const Vec3 w(normal(noise_rng), normal(noise_rng), normal(noise_rng));
      const Vec3 angle = DegToRad(o.rotation_noise_deg) * w;
      const Mat3 noise = angle.norm() > 0 ? Mat3(Eigen::AngleAxisd(angle.norm(), angle.normalized())) : Mat3::Identity();
      pose.tracker_from_tool_rotation = noise * tracker_from_flange.linear() * o.flange_from_tool_rotation;
    }
    pose.line = i + 2;
    data.poses.push_back(pose);
  }
  return sim;
}

}  // namespace ramtk::calib
