// Independent MDH forward kinematics; see mdh.h.
#include "mdh.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

namespace indep {
namespace {

constexpr double kDeg = M_PI / 180.0;

double Number(const YAML::Node& joint, const char* key, double fallback, bool required,
              const std::string& path, int index) {
  const YAML::Node value = joint[key];
  if (!value) {
    if (required) {
      throw std::runtime_error(path + ": joints[" + std::to_string(index) + "]." + key + " missing");
    }
    return fallback;
  }
  try {
    return value.as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(path + ": joints[" + std::to_string(index) + "]." + key +
                             ": expected a number");
  }
}

}  // namespace

Robot LoadRobot(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  Robot robot;
  robot.name = root["name"] ? root["name"].as<std::string>() : path;
  const YAML::Node joints = root["joints"];
  if (!joints || !joints.IsSequence() || joints.size() != 6) {
    throw std::runtime_error(path + ": 'joints' must list exactly 6 joints");
  }
  for (int i = 0; i < 6; ++i) {
    const YAML::Node j = joints[i];
    Joint& out = robot.joints[i];
    out.d_mm = Number(j, "d", 0, true, path, i);
    out.theta0_rad = Number(j, "theta0", 0, true, path, i) * kDeg;
    out.a_mm = Number(j, "a", 0, true, path, i);
    out.alpha_rad = Number(j, "alpha", 0, true, path, i) * kDeg;
    out.beta_rad = Number(j, "beta", 0, false, path, i) * kDeg;
    out.sign = Number(j, "sign", 1, false, path, i);
    out.offset_rad = Number(j, "offset", 0, false, path, i) * kDeg;
  }
  return robot;
}

Eigen::Isometry3d LinkTransform(const Joint& joint, double q_rad) {
  const double theta = joint.theta0_rad + joint.sign * q_rad + joint.offset_rad;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(0, 0, joint.d_mm));
  t.rotate(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()));
  t.translate(Eigen::Vector3d(joint.a_mm, 0, 0));
  t.rotate(Eigen::AngleAxisd(joint.alpha_rad, Eigen::Vector3d::UnitX()));
  t.rotate(Eigen::AngleAxisd(joint.beta_rad, Eigen::Vector3d::UnitY()));
  return t;
}

std::array<Eigen::Isometry3d, 7> LinkFrames(const Robot& robot, const Joints& q_rad) {
  std::array<Eigen::Isometry3d, 7> frames;
  frames[0] = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) frames[i + 1] = frames[i] * LinkTransform(robot.joints[i], q_rad(i));
  return frames;
}

namespace {

Eigen::Matrix<double, 6, 1> PoseError(const Eigen::Isometry3d& target, const Eigen::Isometry3d& at) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = target.translation() - at.translation();
  const Eigen::AngleAxisd rot(target.linear() * at.linear().transpose());
  e.tail<3>() = rot.angle() * rot.axis() * 1000.0;  // 1 rad weighs like 1 m
  return e;
}

}  // namespace

bool SolvePose(const Robot& robot, const Eigen::Isometry3d& target, Joints q, Joints* q_out) {
  for (int iter = 0; iter < 200; ++iter) {
    const Eigen::Isometry3d at = BaseFromFlange(robot, q);
    const Eigen::Matrix<double, 6, 1> e = PoseError(target, at);
    if (e.head<3>().norm() < 1e-6 && e.tail<3>().norm() < 1e-5) {
      *q_out = q;
      return true;
    }
    Eigen::Matrix<double, 6, 6> jac;
    const double h = 1e-7;
    for (int k = 0; k < 6; ++k) {
      Joints qh = q;
      qh(k) += h;
      jac.col(k) = (PoseError(target, at) - PoseError(target, BaseFromFlange(robot, qh))) / h;
    }
    const double lambda = 1e-3;
    const Eigen::Matrix<double, 6, 6> normal =
        jac.transpose() * jac + lambda * Eigen::Matrix<double, 6, 6>::Identity();
    Joints step = normal.ldlt().solve(jac.transpose() * e);
    const double max_step = 0.2;
    if (step.cwiseAbs().maxCoeff() > max_step) step *= max_step / step.cwiseAbs().maxCoeff();
    q += step;
  }
  return false;
}

}  // namespace indep
