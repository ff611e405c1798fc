// Independent MDH forward kinematics (issue 15): written from docs/conventions.md only, no ramtk code.
// T_i^{i-1} = Trans(Z, d)·Rot(Z, θ)·Trans(X, a)·Rot(X, α)·Rot(Y, β), θ = θ0 + sign·q + offset.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <string>

namespace indep {

struct Joint {
  double d_mm = 0, theta0_rad = 0, a_mm = 0, alpha_rad = 0, beta_rad = 0;
  double sign = 1, offset_rad = 0;
};

struct Robot {
  std::string name;
  std::array<Joint, 6> joints;
};

using Joints = Eigen::Matrix<double, 6, 1>;  // controller joint angles, radians

// Reads the robot YAML of docs/formats.md (fields d, theta0, a, alpha, beta, sign, offset in mm / deg).
// Throws std::runtime_error naming the file on a malformed model.
Robot LoadRobot(const std::string& path);

// One link transform T_i^{i-1} for joint index i (0-based) at controller angle q (rad).
Eigen::Isometry3d LinkTransform(const Joint& joint, double q_rad);

// base_from_link[i] for i = 1..6 (index 0 is the identity = base frame); [6] is base_from_flange.
std::array<Eigen::Isometry3d, 7> LinkFrames(const Robot& robot, const Joints& q_rad);

inline Eigen::Isometry3d BaseFromFlange(const Robot& robot, const Joints& q_rad) {
  return LinkFrames(robot, q_rad)[6];
}

// Numeric inverse kinematics (damped least squares on the 6-D pose error, finite-difference Jacobian)
// from `start`; returns false if it does not converge to 1e-6 mm / 1e-8 rad.
bool SolvePose(const Robot& robot, const Eigen::Isometry3d& base_from_flange, Joints start, Joints* q_rad);

}  // namespace indep
