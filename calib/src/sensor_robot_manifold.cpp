// Closed-form start + Ceres fit of the 9 unknowns (rotation on the SO(3) manifold), robust loss,
// covariance from the Jacobian.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/ceres_solve.h"
#include "ramtk/core/error.h"
#include "ramtk/core/rotation.h"
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

// The delete-a-block jackknife and block hold-out of SensorRobotOptions::jackknife_blocks.
void BlockJackknife(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                    const SensorRobotOptions& options, SensorRobotCalibration* c, SensorRobotSummary* s) {
  const int k = options.jackknife_blocks;
  const int n = static_cast<int>(obs.size());
  if (k < 2 || n < 3 * k) return;
  SensorRobotOptions inner = options;
  inner.jackknife_blocks = 0;
  inner.compute_covariance = false;
  std::vector<Eigen::Matrix<double, 9, 1>> thetas;
  double held_sum = 0.0;
  int held_count = 0;
  for (int b = 0; b < k; ++b) {
    const int lo = b * n / k, hi = (b + 1) * n / k;
    std::vector<BallObservation> train(obs.begin(), obs.begin() + lo);
    train.insert(train.end(), obs.begin() + hi, obs.end());
    SensorRobotCalibration fit;
    try {
      fit = CalibrateSensorRobot(model, train, inner, nullptr);
    } catch (const InputError&) {
      continue;  // the rest cannot determine the set-up: this block adds no replicate
    }
    Eigen::Matrix<double, 9, 1> theta;
    theta.head<3>() = LogSO3(fit.sensor_from_base.linear() * c->sensor_from_base.linear().transpose());
    theta.segment<3>(3) = fit.sensor_from_base.translation();
    theta.tail<3>() = fit.ball_in_flange;
    thetas.push_back(theta);
    for (int i = lo; i < hi; ++i) {
      const Vec3 r = obs[i].ball_in_sensor -
                     PredictBallInSensor(model, fit.sensor_from_base, fit.ball_in_flange, obs[i].q_controller);
      held_sum += r.squaredNorm();
      ++held_count;
    }
  }
  if (held_count > 0) s->held_out_rms_mm = std::sqrt(held_sum / held_count);
  if (s->held_out_rms_mm > 2.0 * s->rms_mm && s->rms_mm > 0) {
    s->warnings.push_back("poses left out in blocks are predicted at " + std::to_string(s->held_out_rms_mm) +
                          " mm RMS against " + std::to_string(s->rms_mm) +
                          " mm in the fit: the pose set does not support prediction beyond its own poses (spread "
                          "them over the workspace, or calibrate the robot first: calib robot)");
  }
  const int m = static_cast<int>(thetas.size());
  if (m < 2 || !c->has_covariance) return;
  Eigen::Matrix<double, 9, 1> mean = Eigen::Matrix<double, 9, 1>::Zero();
  for (const auto& t : thetas) mean += t;
  mean /= m;
  Eigen::Matrix<double, 9, 9> jk = Eigen::Matrix<double, 9, 9>::Zero();
  for (const auto& t : thetas) jk += (t - mean) * (t - mean).transpose();
  jk *= static_cast<double>(m - 1) / m;
  // Traces per block of unknowns compare like with like (rad² and mm²).
  const double scaled = c->covariance.block<3, 3>(3, 3).trace() + c->covariance.block<3, 3>(6, 6).trace();
  const double jack = jk.block<3, 3>(3, 3).trace() + jk.block<3, 3>(6, 6).trace();
  s->jackknife_ratio = scaled > 0 ? std::sqrt(jack / scaled) : 0.0;
  // Replaced only when clearly wider (σ ratio above √2): with noise alone ten replicates scatter
  // the trace by about ±30 %, and the residual-scaled covariance is then the better estimate.
  if (jack > 2.0 * scaled) {
    c->covariance = jk;
    s->covariance_source = "block jackknife";
    s->warnings.push_back("σ from the spread of the fits without each block of poses: " +
                          std::to_string(s->jackknife_ratio) +
                          "× the residual's; the robot model's error, not the sensor's noise, limits the set-up");
  }
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
  if (jackknife_blocks < 0 || jackknife_blocks > 1000) return "jackknife_blocks must be in 0..1000";
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
  if (c.has_covariance) s.covariance_source = "residual-scaled";
  BlockJackknife(model, obs, options, &c, &s);
  return c;
}

}  // namespace ramtk::calib
