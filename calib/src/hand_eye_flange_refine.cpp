#include "ramtk/calib/hand_eye_flange_refine.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "hand_eye_json.h"
#include "ramtk/core/ceres_solve.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

// Whitened residual of one pose: 3 rotation (rad / σ_rot), 3 translation (mm / σ_t).
// Parameters: q_x (Eigen order x y z w), t_x, q_z, t_z.
struct PoseResidual {
  Eigen::Quaterniond q_flange;  // base_from_flange
  Vec3 t_flange;
  Eigen::Quaterniond q_meas;  // camera_from_board, measured
  Vec3 t_meas;
  // Whitening of the raw residual [rotation (rad); translation (mm)]: L⁻¹ of its covariance L·Lᵀ
  // (diagonal 1/σ_rot, 1/σ_t for one noise level for all poses).
  Eigen::Matrix<double, 6, 6> whiten;
  // false: camera on the flange, parameters (X = flange_from_camera, Z = base_from_board) and
  // camera_from_board = X⁻¹ F⁻¹ Z. true: camera on a stand, parameters (C = camera_from_base,
  // B = flange_from_board) and camera_from_board = C F B.
  bool stand = false;

  template <typename T>
  bool operator()(const T* qx_, const T* tx_, const T* qz_, const T* tz_, T* r) const {
    using Q = Eigen::Quaternion<T>;
    using V = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Q> qx(qx_), qz(qz_);
    const Eigen::Map<const V> tx(tx_), tz(tz_);
    const Q qf = q_flange.cast<T>();
    const V tf = t_flange.cast<T>();
    Q q_pred;
    V t_pred;
    if (!stand) {  // camera_from_board = X⁻¹ F⁻¹ Z
      q_pred = qx.conjugate() * qf.conjugate() * qz;
      t_pred = qx.conjugate() * (qf.conjugate() * (tz - tf) - tx);
    } else {  // camera_from_board = C F B (x = C, z = B)
      q_pred = qx * qf * qz;
      t_pred = qx * (qf * tz + tf) + tx;
    }
    const Q q_err = q_meas.cast<T>() * q_pred.conjugate();  // R_meas R_predᵀ, camera frame
    T wxyz[4] = {q_err.w(), q_err.x(), q_err.y(), q_err.z()};
    if (wxyz[0] < T(0))
      for (T& v : wxyz) v = -v;
    T aa[3];
    ceres::QuaternionToAngleAxis(wxyz, aa);
    const V dt = t_meas.cast<T>() - t_pred;
    const T raw[6] = {aa[0], aa[1], aa[2], dt[0], dt[1], dt[2]};
    for (int i = 0; i < 6; ++i) {
      r[i] = T(0);
      for (int k = 0; k < 6; ++k) r[i] += T(whiten(i, k)) * raw[k];
    }
    return true;
  }
};

struct Solved {
  Eigen::Quaterniond qx, qz;
  Vec3 tx, tz;
  ceres::Solver::Summary summary;
  double rot_ss = 0, trans_ss = 0;  // unwhitened residual sums of squares (rad², mm²)
  double chi2 = 0;                  // whitened sum of squares
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  bool cov_ok = false;
};

using Mat6 = Eigen::Matrix<double, 6, 6>;

Mat6 IsotropicWhitening(double sigma_rot_rad, double sigma_mm) {
  Mat6 w = Mat6::Zero();
  for (int k = 0; k < 3; ++k) w(k, k) = 1.0 / sigma_rot_rad, w(3 + k, 3 + k) = 1.0 / sigma_mm;
  return w;
}

// True when every pose has a positive definite covariance.
bool AllPosesHaveCovariance(const std::vector<FlangeCameraObservation>& obs) {
  for (const FlangeCameraObservation& o : obs)
    if (o.camera_from_board_covariance.isZero(0) ||
        Eigen::LLT<Mat6>(o.camera_from_board_covariance).info() != Eigen::Success)
      return false;
  return !obs.empty();
}

// L⁻¹ of each pose's covariance plus an isotropic extra noise (rad², mm² per axis), L·Lᵀ.
std::vector<Mat6> PoseWhitening(const std::vector<FlangeCameraObservation>& obs, double extra_rot2,
                                double extra_t2) {
  std::vector<Mat6> w;
  for (const FlangeCameraObservation& o : obs) {
    Mat6 c = o.camera_from_board_covariance;
    for (int k = 0; k < 3; ++k) c(k, k) += extra_rot2, c(3 + k, 3 + k) += extra_t2;
    w.push_back(Mat6(Eigen::LLT<Mat6>(c).matrixL()).inverse());
  }
  return w;
}

Solved Solve(const std::vector<FlangeCameraObservation>& obs, const Isometry3& x0, const Isometry3& z0,
             const std::vector<Mat6>& whiten, int max_iterations, bool covariance, bool stand) {
  Solved s;
  s.qx = Eigen::Quaterniond(x0.linear()).normalized();
  s.qz = Eigen::Quaterniond(z0.linear()).normalized();
  s.tx = x0.translation();
  s.tz = z0.translation();
  ceres::Problem problem;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const FlangeCameraObservation& o = obs[i];
    auto* cost = new ceres::AutoDiffCostFunction<PoseResidual, 6, 4, 3, 4, 3>(
        new PoseResidual{Eigen::Quaterniond(o.base_from_flange.linear()).normalized(), o.base_from_flange.translation(),
                         Eigen::Quaterniond(o.camera_from_board.linear()).normalized(),
                         o.camera_from_board.translation(), whiten[i], stand});
    problem.AddResidualBlock(cost, nullptr, s.qx.coeffs().data(), s.tx.data(), s.qz.coeffs().data(), s.tz.data());
  }
  problem.SetManifold(s.qx.coeffs().data(), new ceres::EigenQuaternionManifold);
  problem.SetManifold(s.qz.coeffs().data(), new ceres::EigenQuaternionManifold);
  ceres::Solve(DenseSolverOptions({max_iterations, 1e-14, 1e-14, 1e-16}), &problem, &s.summary);
  s.qx.normalize();
  s.qz.normalize();
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const FlangeCameraObservation& o = obs[i];
    double r[6];
    PoseResidual pr{Eigen::Quaterniond(o.base_from_flange.linear()).normalized(),
                    o.base_from_flange.translation(),
                    Eigen::Quaterniond(o.camera_from_board.linear()).normalized(),
                    o.camera_from_board.translation(),
                    Mat6::Identity(),
                    stand};
    pr(s.qx.coeffs().data(), s.tx.data(), s.qz.coeffs().data(), s.tz.data(), r);
    for (int k = 0; k < 3; ++k) s.rot_ss += r[k] * r[k], s.trans_ss += r[3 + k] * r[3 + k];
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> raw(r);
    s.chi2 += (whiten[i] * raw).squaredNorm();
  }
  if (covariance && s.summary.IsSolutionUsable()) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    ceres::Covariance cov(co);
    const std::vector<const double*> blocks = {s.qx.coeffs().data(), s.tx.data()};
    if (cov.Compute(blocks, &problem)) {
      s.cov_ok = cov.GetCovarianceMatrixInTangentSpace(blocks, s.cov.data());
      s.cov = s.cov.transpose().eval();  // Ceres fills row-major
      // Ceres's quaternion manifolds step by the quaternion exponential of δ: a rotation of
      // 2|δ|. The rotation vector is 2δ, so its block scales by 2 (found by the Monte-Carlo test).
      Eigen::Matrix<double, 6, 6> j = Eigen::Matrix<double, 6, 6>::Identity();
      j.topLeftCorner<3, 3>() *= 2.0;
      s.cov = j * s.cov * j.transpose();
    }
  }
  return s;
}

}  // namespace

std::string EyeInHandRefineOptions::Validate() const {
  if (!(sigma_deg >= 0) || !std::isfinite(sigma_deg)) return "sigma_deg must be >= 0 (0: estimated)";
  if (!(sigma_mm >= 0) || !std::isfinite(sigma_mm)) return "sigma_mm must be >= 0 (0: estimated)";
  if ((sigma_deg > 0) != (sigma_mm > 0)) return "give both sigma_deg and sigma_mm, or neither (estimated)";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  return "";
}

namespace {

std::pair<Isometry3, Isometry3> FinishRefinement(const Solved& s, const std::vector<FlangeCameraObservation>& obs,
                                                 const Isometry3& x_init, const Isometry3& z_init, double sigma_rot,
                                                 double sigma_t, bool pose_covariance, EyeInHandRefinement* out);

// The shared refinement: the two unknowns (x, z) as in PoseResidual, their initial values, the
// initial residual RMS for the first weights. Fills *out and returns the refined (x, z).
std::pair<Isometry3, Isometry3> RefineCore(const std::vector<FlangeCameraObservation>& obs, const Isometry3& x_init,
                                           const Isometry3& z_init, double rms_rotation_deg, double rms_translation_mm,
                                           const EyeInHandRefineOptions& options, bool stand,
                                           EyeInHandRefinement* out) {
  ThrowIfInvalid(options.Validate(), "EyeInHandRefineOptions");
  if (obs.size() < 3)
    throw InputError({"", 0, "poses"}, std::to_string(obs.size()) + " poses given; at least 3 are needed");
  for (const FlangeCameraObservation& o : obs)
    if (!o.base_from_flange.matrix().allFinite() || !o.camera_from_board.matrix().allFinite())
      throw InputError({"", 0, "poses"}, "non-finite flange or board pose");
  const int n = static_cast<int>(obs.size());
  *out = EyeInHandRefinement();
  double sigma_rot = DegToRad(options.sigma_deg), sigma_t = options.sigma_mm;
  Isometry3 x0 = x_init, z0 = z_init;
  if (options.use_pose_covariance && sigma_rot <= 0 && AllPosesHaveCovariance(obs)) {
    // Each pose weighed by its own covariance plus the noise the images do not see (the robot's
    // pose error), added to every pose isotropically in rotation and in translation. A first fit
    // with one weight for all gives the residual noise per axis.
    const double r0 = std::max(DegToRad(rms_rotation_deg) / std::sqrt(3.0), 1e-9);
    const double t0 = std::max(rms_translation_mm / std::sqrt(3.0), 1e-9);
    const Solved first = Solve(obs, x0, z0, std::vector<Mat6>(obs.size(), IsotropicWhitening(r0, t0)),
                               options.max_iterations, false, stand);
    const double dof = std::max(1, 3 * n - 6);
    double own_rot2 = 0, own_t2 = 0;
    for (const FlangeCameraObservation& o : obs) {
      own_rot2 += o.camera_from_board_covariance.topLeftCorner<3, 3>().trace() / (3.0 * n);
      own_t2 += o.camera_from_board_covariance.bottomRightCorner<3, 3>().trace() / (3.0 * n);
    }
    // The extra noise's shape: the excess per block (or the poses' own mean variance when neither
    // block shows one). Its size: the smallest multiple k for which the weighted residuals'
    // χ²/(6n − 12) is at most 1 (k = 0 when the images' noise explains them), by bisection.
    double shape_rot2 = std::max(0.0, first.rot_ss / dof - own_rot2);
    double shape_t2 = std::max(0.0, first.trans_ss / dof - own_t2);
    if (shape_rot2 <= 0 && shape_t2 <= 0) shape_rot2 = own_rot2, shape_t2 = own_t2;
    x0.linear() = first.qx.toRotationMatrix(), x0.translation() = first.tx;
    z0.linear() = first.qz.toRotationMatrix(), z0.translation() = first.tz;
    const double dof6 = std::max(1, 6 * n - 12);
    auto factor = [&](double k) {
      return Solve(obs, x0, z0, PoseWhitening(obs, k * shape_rot2, k * shape_t2), options.max_iterations, false, stand)
                 .chi2 /
             dof6;
    };
    double k = 0;
    if (factor(0) > 1) {
      double lo = 0, hi = 1;
      for (int i = 0; i < 20 && factor(hi) > 1; ++i) lo = hi, hi *= 4;
      for (int i = 0; i < 30; ++i) {
        const double mid = 0.5 * (lo + hi);
        (factor(mid) > 1 ? lo : hi) = mid;
      }
      k = hi;
    }
    const double extra_rot2 = k * shape_rot2, extra_t2 = k * shape_t2;
    const Solved s =
        Solve(obs, x0, z0, PoseWhitening(obs, extra_rot2, extra_t2), options.max_iterations, true, stand);
    const auto xz = FinishRefinement(s, obs, x_init, z_init, 0, 0, true, out);
    out->extra_noise_deg = RadToDeg(std::sqrt(extra_rot2));
    out->extra_noise_mm = std::sqrt(extra_t2);
    return xz;
  }
  if (sigma_rot <= 0) {
    // First fit with the initial residuals' RMS as weights, then each noise from its own
    // residuals (3n − 6 degrees of freedom apiece: 12 parameters over 6n equations).
    sigma_rot = std::max(DegToRad(rms_rotation_deg) / std::sqrt(3.0), 1e-9);
    sigma_t = std::max(rms_translation_mm / std::sqrt(3.0), 1e-9);
    const Solved first = Solve(obs, x0, z0, std::vector<Mat6>(obs.size(), IsotropicWhitening(sigma_rot, sigma_t)),
                               options.max_iterations, false, stand);
    const double dof = std::max(1, 3 * n - 6);
    sigma_rot = std::max(std::sqrt(first.rot_ss / dof), 1e-12);
    sigma_t = std::max(std::sqrt(first.trans_ss / dof), 1e-12);
    x0.linear() = first.qx.toRotationMatrix(), x0.translation() = first.tx;
    z0.linear() = first.qz.toRotationMatrix(), z0.translation() = first.tz;
    out->noise_estimated = true;
  }
  const Solved s = Solve(obs, x0, z0, std::vector<Mat6>(obs.size(), IsotropicWhitening(sigma_rot, sigma_t)),
                         options.max_iterations, true, stand);
  return FinishRefinement(s, obs, x_init, z_init, sigma_rot, sigma_t, false, out);
}

// Fills *out from the final solve and returns the refined (x, z). With per-pose covariances the
// covariance is scaled by the variance factor χ²/(6n − 12) when it exceeds 1: residuals beyond
// the poses' own noise (the robot's pose error) widen it; it is never narrowed.
std::pair<Isometry3, Isometry3> FinishRefinement(const Solved& s, const std::vector<FlangeCameraObservation>& obs,
                                                 const Isometry3& x_init, const Isometry3& z_init, double sigma_rot,
                                                 double sigma_t, bool pose_covariance, EyeInHandRefinement* out) {
  out->converged = s.summary.termination_type == ceres::CONVERGENCE;
  out->iterations = CeresIterations(s.summary);
  out->initial_cost = s.summary.initial_cost;
  out->final_cost = s.summary.final_cost;
  const int dof = std::max<int>(1, 6 * static_cast<int>(obs.size()) - 12);
  out->pose_covariance = pose_covariance;
  out->variance_factor = s.chi2 / dof;
  const double scale = pose_covariance ? std::max(1.0, out->variance_factor) : 1.0;
  out->sigma_deg = pose_covariance ? RadToDeg(std::sqrt(s.rot_ss / (3.0 * obs.size()))) : RadToDeg(sigma_rot);
  out->sigma_mm = pose_covariance ? std::sqrt(s.trans_ss / (3.0 * obs.size())) : sigma_t;
  if (s.cov_ok) {
    out->flange_from_camera_covariance = scale * s.cov;
    for (int k = 0; k < 3; ++k) {
      out->rotation_sigma_deg[k] = RadToDeg(std::sqrt(std::max(0.0, scale * s.cov(k, k))));
      out->translation_sigma_mm[k] = std::sqrt(std::max(0.0, scale * s.cov(3 + k, 3 + k)));
    }
  }
  if (!s.summary.IsSolutionUsable()) return {x_init, z_init};
  Isometry3 x = Isometry3::Identity(), z = Isometry3::Identity();
  x.linear() = s.qx.toRotationMatrix(), x.translation() = s.tx;
  z.linear() = s.qz.toRotationMatrix(), z.translation() = s.tz;
  return {x, z};
}

}  // namespace

EyeInHandResult RefineCameraOnFlange(const std::vector<FlangeCameraObservation>& obs, const EyeInHandResult& initial,
                                     const EyeInHandRefineOptions& options, EyeInHandRefinement* refinement) {
  EyeInHandRefinement out;
  const auto [x, z] = RefineCore(obs, initial.flange_from_camera, initial.base_from_board, initial.rms_rotation_deg,
                                 initial.rms_translation_mm, options, false, &out);
  EyeInHandResult r = initial;
  r.flange_from_camera = x;
  r.base_from_board = z;
  r.rotation_residual_deg.clear();
  r.translation_residual_mm.clear();
  double sr = 0, st = 0;
  for (const FlangeCameraObservation& o : obs) {
    const Isometry3 pred = (o.base_from_flange * r.flange_from_camera).inverse() * r.base_from_board;
    const double dr = RadToDeg(Eigen::AngleAxisd(o.camera_from_board.linear() * pred.linear().transpose()).angle());
    const double dt = (o.camera_from_board.translation() - pred.translation()).norm();
    r.rotation_residual_deg.push_back(dr);
    r.translation_residual_mm.push_back(dt);
    sr += dr * dr, st += dt * dt;
  }
  r.rms_rotation_deg = std::sqrt(sr / obs.size());
  r.rms_translation_mm = std::sqrt(st / obs.size());
  if (refinement) *refinement = out;
  return r;
}

HandEyeResult RefineStandCamera(const std::vector<StandCameraObservation>& obs, const HandEyeResult& initial,
                                const EyeInHandRefineOptions& options, EyeInHandRefinement* refinement) {
  std::vector<FlangeCameraObservation> f;
  double sr = 0, st = 0;
  for (const StandCameraObservation& o : obs) {
    f.push_back(o);
    const Isometry3 pred = initial.camera_from_base * o.base_from_flange * initial.flange_from_board;
    sr += std::pow(RadToDeg(Eigen::AngleAxisd(o.camera_from_board.linear() * pred.linear().transpose()).angle()), 2);
    st += (o.camera_from_board.translation() - pred.translation()).squaredNorm();
  }
  const double n = std::max<double>(1, obs.size());
  EyeInHandRefinement out;
  const auto [c, b] = RefineCore(f, initial.camera_from_base, initial.flange_from_board, std::sqrt(sr / n),
                                 std::sqrt(st / n), options, true, &out);
  HandEyeResult r = initial;
  r.camera_from_base = c;
  r.flange_from_board = b;
  r.rotation_residual_rad.clear();
  r.translation_residual_mm.clear();
  for (const StandCameraObservation& o : obs) {
    const Isometry3 pred = r.camera_from_base * o.base_from_flange * r.flange_from_board;
    r.rotation_residual_rad.push_back(
        Eigen::AngleAxisd(o.camera_from_board.linear() * pred.linear().transpose()).angle());
    r.translation_residual_mm.push_back((o.camera_from_board.translation() - pred.translation()).norm());
  }
  if (refinement) *refinement = out;
  return r;
}

namespace internal {

nlohmann::json RefinementJson(const EyeInHandRefinement& f, const std::string& pose, const std::string& frame) {
  nlohmann::json cov = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int k = 0; k < 6; ++k) row.push_back(f.flange_from_camera_covariance(i, k));
    cov.push_back(row);
  }
  return {
      {"converged", f.converged},
      {"iterations", f.iterations},
      {"noise_sigma_deg", f.sigma_deg},
      {"noise_sigma_mm", f.sigma_mm},
      {"noise_estimated_from_residuals", f.noise_estimated},
      {"weights", f.pose_covariance ? "each pose's covariance (from its image)" : "one noise level for all poses"},
      {"variance_factor", f.variance_factor},
      {"extra_noise_sigma_deg", f.extra_noise_deg},
      {"extra_noise_sigma_mm", f.extra_noise_mm},
      {pose + "_rotation_sigma_deg", {f.rotation_sigma_deg.x(), f.rotation_sigma_deg.y(), f.rotation_sigma_deg.z()}},
      {pose + "_translation_sigma_mm",
       {f.translation_sigma_mm.x(), f.translation_sigma_mm.y(), f.translation_sigma_mm.z()}},
      {pose + "_covariance", cov},
      {"covariance_order", "rotation vector (rad, " + frame + ", left perturbation), translation (mm)"}};
}

}  // namespace internal

}  // namespace ramtk::calib
