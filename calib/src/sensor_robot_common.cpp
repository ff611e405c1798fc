// Shared pieces of the sensor-to-robot calibration: observations, predictions, the closed-form
// linear solution, pose-set diagnostics and the report helpers.
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::calib {
namespace {}  // namespace

std::vector<BallObservation> BallObservationsFromMeasurements(const kinematics::RobotMeasurementSet& set,
                                                              const std::string& path) {
  if (set.kind != kinematics::MeasurementKind::kBall) {
    throw InputError({path, 1, "pose"}, "expected a ball measurement file (column 'pose'), got monitoring points");
  }
  const bool with_covariance = kinematics::HasCentreCovariance(set, path);
  std::vector<BallObservation> obs;
  for (const kinematics::RobotMeasurement& m : set.rows) {
    if (!m.q_controller.allFinite() || !m.position_mm.allFinite()) {
      throw InputError({path, m.line, "q1..q6,x,y,z"}, "value is not finite");
    }
    BallObservation o;
    o.q_controller = m.q_controller;
    o.ball_in_sensor = m.position_mm;
    o.pose = m.index;
    o.line = m.line;
    if (with_covariance) {
      o.covariance_mm2 = kinematics::CentreCovariance(m, path);
      o.has_covariance = true;
    }
    obs.push_back(o);
  }
  return obs;
}

Vec3 SensorRobotCalibration::RotationStdArcsec() const {
  return covariance.diagonal().head<3>().cwiseMax(0.0).cwiseSqrt() * kArcsecPerRad;
}
Vec3 SensorRobotCalibration::TranslationStdMm() const {
  return covariance.diagonal().segment<3>(3).cwiseMax(0.0).cwiseSqrt();
}
Vec3 SensorRobotCalibration::BallStdMm() const { return covariance.diagonal().tail<3>().cwiseMax(0.0).cwiseSqrt(); }

std::string PoseSetCheckOptions::Validate() const {
  if (min_poses < 3) return "min_poses must be at least 3 (9 unknowns, 3 equations per pose)";
  if (!(min_rotation_spread_deg >= 0.0) || !(warn_rotation_spread_deg >= min_rotation_spread_deg)) {
    return "need 0 <= min_rotation_spread_deg <= warn_rotation_spread_deg";
  }
  if (!(warn_condition_number >= 1.0) || !(max_condition_number >= warn_condition_number)) {
    return "need 1 <= warn_condition_number <= max_condition_number";
  }
  return "";
}

const char* SensorRobotTerminationText(Termination t) {
  switch (t) {
    case Termination::kSuccess:
      return "converged";
    case Termination::kNoConvergence:
      return "no_convergence";
    default:
      return "failed";
  }
}

std::string SensorRobotSummary::BriefReport() const {
  char buf[400];
  std::snprintf(buf, sizeof(buf),
                "%s: %s after %d iterations, cost %.6g -> %.6g, RMS %.4f mm, worst %.4f mm (index %d), %zu outliers, "
                "%d poses, rotation spread %.1f deg, condition number %.3g",
                method.c_str(), SensorRobotTerminationText(termination), iterations, initial_cost, final_cost, rms_mm,
                max_residual_mm, worst_pose, outliers.size(), diagnostics.num_poses, diagnostics.rotation_spread_deg,
                diagnostics.condition_number);
  return std::string(buf) + (weighted ? ", each centre weighted by its covariance" : "");
}

Vec3 PredictBallInSensor(const kinematics::RobotModel& model, const Isometry3& sensor_from_base,
                         const Vec3& ball_in_flange, const kinematics::JointVector& q_controller) {
  return sensor_from_base * (kinematics::BaseFromFlange(model, q_controller) * ball_in_flange);
}

SensorRobotCalibration SolveSensorRobotLinear(const kinematics::RobotModel& model,
                                              const std::vector<BallObservation>& obs) {
  const int n = static_cast<int>(obs.size());
  std::vector<Isometry3> flange(n);
  Vec3 mean_p = Vec3::Zero(), mean_t = Vec3::Zero();
  Mat3 mean_r = Mat3::Zero();
  for (int i = 0; i < n; ++i) {
    flange[i] = kinematics::BaseFromFlange(model, obs[i].q_controller);
    mean_p += obs[i].ball_in_sensor / n;
    mean_t += flange[i].translation() / n;
    mean_r += flange[i].linear() / n;
  }
  // Centred equations: R_sᵀ(P_si − P̄) − (R_i − R̄)·P_e = t_i − t̄; unknowns [R_sᵀ row-major, P_e].
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * n, 12);
  Eigen::VectorXd b(3 * n);
  for (int i = 0; i < n; ++i) {
    const Vec3 dp = obs[i].ball_in_sensor - mean_p;
    const Mat3 dr = flange[i].linear() - mean_r;
    for (int k = 0; k < 3; ++k) {
      a.block<1, 3>(3 * i + k, 3 * k) = dp.transpose();
      a.block<1, 3>(3 * i + k, 9) = -dr.row(k);
    }
    b.segment<3>(3 * i) = flange[i].translation() - mean_t;
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  Mat3 rt;
  rt << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
  const Mat3 rs = NearestRotation(rt.transpose());
  // With R_s fixed: P_si − R_s·t_i = R_s·R_i·P_e + t_s, linear in [P_e, t_s].
  Eigen::MatrixXd a2(3 * n, 6);
  Eigen::VectorXd b2(3 * n);
  for (int i = 0; i < n; ++i) {
    a2.block<3, 3>(3 * i, 0) = rs * flange[i].linear();
    a2.block<3, 3>(3 * i, 3) = Mat3::Identity();
    b2.segment<3>(3 * i) = obs[i].ball_in_sensor - rs * flange[i].translation();
  }
  const Eigen::VectorXd y = a2.colPivHouseholderQr().solve(b2);
  SensorRobotCalibration c;
  c.sensor_from_base.linear() = rs;
  c.sensor_from_base.translation() = y.tail<3>();
  c.ball_in_flange = y.head<3>();
  double sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 r = obs[i].ball_in_sensor - c.sensor_from_base * (flange[i] * c.ball_in_flange);
    c.residuals_mm.push_back(r);
    sum2 += r.squaredNorm();
    c.max_residual_mm = std::max(c.max_residual_mm, r.norm());
  }
  c.rms_mm = n > 0 ? std::sqrt(sum2 / n) : 0.0;
  return c;
}

PoseSetDiagnostics DiagnosePoseSet(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                                   const Vec3& ball_in_flange, const PoseSetCheckOptions& options) {
  PoseSetDiagnostics d;
  d.num_poses = static_cast<int>(obs.size());
  char buf[300];
  if (d.num_poses < options.min_poses) {
    std::snprintf(buf, sizeof(buf), "%d poses given; at least %d are needed (thesis §3.3: 3n >= 12)", d.num_poses,
                  options.min_poses);
    d.error = buf;
    d.condition_number = std::numeric_limits<double>::infinity();
    return d;
  }
  const int n = d.num_poses;
  std::vector<Isometry3> flange(n);
  for (int i = 0; i < n; ++i) flange[i] = kinematics::BaseFromFlange(model, obs[i].q_controller);
  Mat3 mean_r = Mat3::Zero();
  for (int i = 0; i < n; ++i) {
    mean_r += flange[i].linear() / n;
    for (int j = i + 1; j < n; ++j) {
      d.rotation_spread_deg =
          std::max(d.rotation_spread_deg, RadToDeg(RotationAngleBetween(flange[i].linear(), flange[j].linear())));
    }
  }
  Eigen::MatrixXd stacked(3 * n, 3);
  for (int i = 0; i < n; ++i) stacked.block<3, 3>(3 * i, 0) = flange[i].linear() - mean_r;
  const double smin = Eigen::JacobiSVD<Eigen::MatrixXd>(stacked).singularValues()(2);
  d.min_axis_spread_deg = RadToDeg(std::asin(std::min(1.0, smin / std::sqrt(static_cast<double>(n)))));

  // Jacobian in the base frame, rotation about the centroid, scaled by the RMS radius.
  std::vector<Vec3> p(n);
  Vec3 mean_p = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    p[i] = flange[i] * ball_in_flange;
    mean_p += p[i] / n;
  }
  double rho2 = 0.0;
  for (int i = 0; i < n; ++i) rho2 += (p[i] - mean_p).squaredNorm() / n;
  const double rho = std::max(std::sqrt(rho2), 1e-9);
  Eigen::MatrixXd j(3 * n, 9);
  for (int i = 0; i < n; ++i) {
    j.block<3, 3>(3 * i, 0) = -Skew(p[i] - mean_p) / rho;
    j.block<3, 3>(3 * i, 3) = Mat3::Identity();
    j.block<3, 3>(3 * i, 6) = flange[i].linear();
  }
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(j).singularValues();
  d.condition_number = sv(8) > sv(0) * 1e-15 ? sv(0) / sv(8) : std::numeric_limits<double>::infinity();

  if (d.rotation_spread_deg < options.min_rotation_spread_deg) {
    std::snprintf(buf, sizeof(buf),
                  "flange orientations differ by at most %.3g deg (need >= %.3g): the ball offset cannot be separated "
                  "from the sensor translation (condition number %.3g)",
                  d.rotation_spread_deg, options.min_rotation_spread_deg, d.condition_number);
    d.error = buf;
  } else if (!(d.condition_number <= options.max_condition_number)) {
    std::snprintf(buf, sizeof(buf),
                  "near-singular pose set: condition number %.3g exceeds %.3g (rotation spread %.3g deg, smallest "
                  "spread about any axis %.3g deg); add poses that turn the flange about other axes",
                  d.condition_number, options.max_condition_number, d.rotation_spread_deg, d.min_axis_spread_deg);
    d.error = buf;
  }
  if (!d.error.empty()) return d;
  if (d.rotation_spread_deg < options.warn_rotation_spread_deg) {
    std::snprintf(buf, sizeof(buf), "little rotation diversity: flange orientations differ by at most %.3g deg",
                  d.rotation_spread_deg);
    d.warnings.push_back(buf);
  }
  if (d.condition_number > options.warn_condition_number) {
    std::snprintf(buf, sizeof(buf), "poorly conditioned pose set: condition number %.3g (warning above %.3g)",
                  d.condition_number, options.warn_condition_number);
    d.warnings.push_back(buf);
  }
  return d;
}

}  // namespace ramtk::calib
