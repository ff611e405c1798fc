// Closed-form start + Ceres fit of the 9 unknowns (rotation on the SO(3) manifold), robust loss,
// covariance from the Jacobian.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/ceres_solve.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/kinematics/forward.h"
#include "sensor_robot_internal.h"

namespace ramtk::calib {
namespace {

// measured − R_s·(R_i·P_e + t_i) − t_s for one pose; quaternion in Eigen order (x, y, z, w).
// `weight` whitens the residual (identity when unweighted).
struct BallResidual {
  Mat3 flange_rotation;
  Vec3 flange_translation;
  Vec3 measured;
  Mat3 weight;
  template <typename T>
  bool operator()(const T* quaternion, const T* translation, const T* ball, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(quaternion);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> pe(ball);
    const Eigen::Matrix<T, 3, 1> in_base = flange_rotation.cast<T>() * pe + flange_translation.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = weight.cast<T>() * (measured.cast<T>() - (q * in_base + t));
    return true;
  }
};

// Per observation the whitening σ̄·L⁻¹ (C = L·Lᵀ, σ̄² the mean variance over all centres), or
// empty when not every observation has a covariance.
std::vector<Mat3> CentreWeights(const std::vector<BallObservation>& obs, double robot_noise_mm) {
  const Mat3 robot = robot_noise_mm * robot_noise_mm * Mat3::Identity();
  double mean_variance = 0.0;
  for (const BallObservation& o : obs) {
    if (!o.has_covariance) return {};
    mean_variance += (o.covariance_mm2 + robot).trace() / 3.0;
  }
  mean_variance /= static_cast<double>(obs.size());
  std::vector<Mat3> w;
  for (const BallObservation& o : obs) {
    const Eigen::LLT<Mat3> llt(o.covariance_mm2 + robot);
    if (llt.info() != Eigen::Success) {
      throw InputError({"", o.line, "cov_xx..cov_yz"},
                       "the centre covariance of pose " + std::to_string(o.pose) + " is not positive definite");
    }
    const Mat3 l_inv = llt.matrixL().solve(Mat3::Identity());
    w.push_back(std::sqrt(mean_variance) * l_inv);
  }
  return w;
}

}  // namespace

std::string SensorRobotOptions::Validate() const {
  if (loss != RobustLoss::kNone && !(loss_scale_mm > 0.0)) return "loss_scale_mm must be positive";
  if (!(outlier_factor > 1.0)) return "outlier_factor must exceed 1";
  if (!(robot_noise_mm >= 0.0)) return "robot_noise_mm must be >= 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(function_tolerance > 0.0) || !(parameter_tolerance > 0.0) || !(gradient_tolerance > 0.0)) {
    return "tolerances must be positive";
  }
  return checks.Validate();
}

SensorRobotCalibration CalibrateSensorRobot(const kinematics::RobotModel& model,
                                            const std::vector<BallObservation>& obs, const SensorRobotOptions& options,
                                            SensorRobotSummary* summary) {
  ThrowIfInvalid(options.Validate(), "SensorRobotOptions");
  SensorRobotSummary local;
  SensorRobotSummary& s = summary ? *summary : local;
  s = SensorRobotSummary();
  s.method = "manifold";
  s.diagnostics = internal::CheckPoseSetOrThrow(model, obs, options.checks);
  s.warnings = s.diagnostics.warnings;

  const SensorRobotCalibration start = SolveSensorRobotLinear(model, obs);
  Eigen::Quaterniond q(start.sensor_from_base.linear());
  q.normalize();
  Vec3 t = start.sensor_from_base.translation();
  Vec3 ball = start.ball_in_flange;

  std::vector<Mat3> weights;
  if (options.use_covariance) weights = CentreWeights(obs, options.robot_noise_mm);
  s.weighted = !weights.empty();
  ceres::Problem problem;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const BallObservation& o = obs[i];
    const Isometry3 f = kinematics::BaseFromFlange(model, o.q_controller);
    ceres::LossFunction* loss = nullptr;
    if (options.loss == RobustLoss::kHuber) loss = new ceres::HuberLoss(options.loss_scale_mm);
    if (options.loss == RobustLoss::kCauchy) loss = new ceres::CauchyLoss(options.loss_scale_mm);
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BallResidual, 3, 4, 3, 3>(new BallResidual{
            f.linear(), f.translation(), o.ball_in_sensor, s.weighted ? weights[i] : Mat3::Identity()}),
        loss, q.coeffs().data(), t.data(), ball.data());
  }
  problem.SetManifold(q.coeffs().data(), new ceres::EigenQuaternionManifold);
  ceres::Solver::Summary cs;
  ceres::Solve(DenseSolverOptions({options.max_iterations, options.function_tolerance, options.parameter_tolerance,
                                   options.gradient_tolerance}),
               &problem, &cs);
  s.iterations = CeresIterations(cs);
  s.initial_cost = cs.initial_cost;
  s.final_cost = cs.final_cost;
  s.termination = TerminationFromCeres(cs);

  SensorRobotCalibration c;
  c.sensor_from_base.linear() = q.normalized().toRotationMatrix();
  c.sensor_from_base.translation() = t;
  c.ball_in_flange = ball;
  c.orthonormality_error = OrthonormalityError(c.sensor_from_base.linear());
  internal::FillResiduals(model, obs, &c);
  internal::FillSummaryResiduals(c, options.outlier_factor, &s);

  if (options.compute_covariance) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance covariance(co);
    const std::vector<const double*> blocks = {q.coeffs().data(), t.data(), ball.data()};
    std::vector<std::pair<const double*, const double*>> pairs;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      for (std::size_t j = i; j < blocks.size(); ++j) pairs.emplace_back(blocks[i], blocks[j]);
    }
    Eigen::Matrix<double, 9, 9, Eigen::RowMajor> cov;
    if (covariance.Compute(pairs, &problem) && covariance.GetCovarianceMatrixInTangentSpace(blocks, cov.data())) {
      // Ceres's quaternion manifold turns by 2|δ| for a tangent step δ (q ← [cos|δ|, sin|δ|·δ/|δ|]·q),
      // so the rotation vector is φ = 2δ, applied on the left (sensor frame).
      Eigen::Matrix<double, 9, 9> scale = Eigen::Matrix<double, 9, 9>::Identity();
      scale.topLeftCorner<3, 3>() *= 2.0;
      const int dof = 3 * static_cast<int>(obs.size()) - 9;
      double sum2 = 0.0;
      for (std::size_t i = 0; i < c.residuals_mm.size(); ++i) {
        sum2 += (s.weighted ? Vec3(weights[i] * c.residuals_mm[i]) : c.residuals_mm[i]).squaredNorm();
      }
      const double variance = dof > 0 ? sum2 / dof : 0.0;
      c.covariance = variance * scale * cov * scale;
      c.has_covariance = true;
    } else {
      s.warnings.push_back("covariance could not be computed (rank-deficient Jacobian)");
      RAMTK_LOG(kWarning) << "sensor-robot calibration: covariance could not be computed";
    }
  }
  return c;
}

}  // namespace ramtk::calib
