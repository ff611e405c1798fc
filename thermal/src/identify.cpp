#include "ramtk/thermal/identify.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/jacobian.h"

namespace ramtk::thermal {

using kinematics::kNumParams;

std::string IdentificationOptions::Validate() const {
  for (int p : params) {
    if (p < 0 || p >= kNumParams) return "parameter index out of range";
  }
  for (int p : poses) {
    if (p < 0) return "negative pose position";
  }
  if (!(singular_value_rtol >= 0.0 && singular_value_rtol < 1.0)) return "singular_value_rtol must be in [0, 1)";
  if (!(rank_rtol > 0.0 && rank_rtol < 1.0)) return "rank_rtol must be in (0, 1)";
  return "";
}

std::string IdentificationSummary::BriefReport() const {
  char buf[400];
  std::snprintf(buf, sizeof(buf),
                "identification %s: %zu params, %d poses (%d equations), rank %d, cond %.3g, %d cycles, "
                "cost %.4g -> %.4g mm^2, RMS %.4f mm, worst %.4f mm",
                message.c_str(), params.size(), num_poses, num_equations, rank, condition_number, num_cycles,
                initial_cost, final_cost, rms_residual_mm, worst_residual_mm);
  return std::string(buf) + (weighted ? ", each centre difference weighted by its covariance" : "");
}

double IdentificationSummary::Sigma(int k, int c) const {
  if (c < 0 || c >= static_cast<int>(covariance.size()) || k < 0 || k >= covariance[c].rows()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::sqrt(std::max(0.0, covariance[c](k, k)));
}

namespace {

// Generalised least squares per column of y: every pose's 3 rows whitened by L⁻¹ (C = L·Lᵀ of
// that column's difference), columns equilibrated, SVD with the same truncation as eq. (3-10).
// With `inverse_info` and `chi2` given, also each column's (Aᵀ C⁻¹ A)⁻¹ (truncated like the solve)
// and its whitened residual χ².
Eigen::MatrixXd SolveWeighted(const Eigen::MatrixXd& a, const Eigen::MatrixXd& y, const std::vector<int>& poses,
                              const IdentificationOptions& options, std::vector<Eigen::MatrixXd>* inverse_info = nullptr,
                              Eigen::VectorXd* chi2 = nullptr) {
  const auto& cov = options.difference_covariance_mm2;
  if (static_cast<Eigen::Index>(cov.size()) != y.cols()) {
    throw InputError({"", 0, "difference_covariance_mm2"},
                     "has " + std::to_string(cov.size()) + " cycles, the differences " + std::to_string(y.cols()));
  }
  const int m = static_cast<int>(poses.size());
  const Eigen::Index k = a.cols();
  Eigen::MatrixXd x(k, y.cols());
  Eigen::MatrixXd aw(a.rows(), k);
  Eigen::VectorXd yw(y.rows());
  for (Eigen::Index c = 0; c < y.cols(); ++c) {
    for (int i = 0; i < m; ++i) {
      if (poses[i] >= static_cast<int>(cov[c].size())) {
        throw InputError({"", 0, "difference_covariance_mm2"},
                         "cycle " + std::to_string(c) + " lacks pose position " + std::to_string(poses[i]));
      }
      const Eigen::LLT<Mat3> llt(cov[c][poses[i]]);
      if (llt.info() != Eigen::Success) {
        throw InputError({"", 0, "difference_covariance_mm2"}, "not positive definite at cycle " + std::to_string(c) +
                                                                   ", pose position " + std::to_string(poses[i]));
      }
      aw.middleRows(3 * i, 3) = llt.matrixL().solve(a.middleRows(3 * i, 3));
      yw.segment<3>(3 * i) = llt.matrixL().solve(Vec3(y.block<3, 1>(3 * i, c)));
    }
    Eigen::VectorXd scale(k);
    for (Eigen::Index j = 0; j < k; ++j) {
      const double n = aw.col(j).norm();
      scale[j] = n > 0.0 ? 1.0 / n : 1.0;
    }
    Eigen::BDCSVD<Eigen::MatrixXd> svd(aw * scale.asDiagonal(), Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& s = svd.singularValues();
    const double smax = s.size() > 0 ? s[0] : 0.0;
    Eigen::VectorXd s_inv = Eigen::VectorXd::Zero(s.size());
    for (Eigen::Index i = 0; i < s.size(); ++i) {
      if (s[i] > options.singular_value_rtol * smax && s[i] > 0.0) s_inv[i] = 1.0 / s[i];
    }
    x.col(c) = scale.asDiagonal() * (svd.matrixV() * s_inv.asDiagonal() * (svd.matrixU().transpose() * yw));
    if (inverse_info != nullptr) {
      const Eigen::MatrixXd vs = svd.matrixV() * s_inv.asDiagonal();
      inverse_info->push_back(scale.asDiagonal() * (vs * vs.transpose()) * scale.asDiagonal());
    }
    if (chi2 != nullptr) {
      if (chi2->size() != y.cols()) chi2->setZero(y.cols());
      (*chi2)[c] = (yw - aw * x.col(c)).squaredNorm();
    }
  }
  return x;
}

void CheckEquationCount(int m, int k) {
  if (k == 0) throw InputError({"", 0, "params"}, "no parameters to identify");
  if (3 * m < k) {
    throw InputError({"", 0, "poses"}, std::to_string(m) + " poses give " + std::to_string(3 * m) +
                                           " equations, fewer than the " + std::to_string(k) +
                                           " parameters to identify (need at least " + std::to_string((k + 2) / 3) +
                                           " poses)");
  }
}

}  // namespace

DriftModel::DriftModel(const RobotModel& model, const ThermalSetup& setup, const std::vector<JointVector>& taught)
    : model_(model), taught_(taught), a_full_(3 * taught.size(), kNumParams) {
  const Mat3 r = setup.sensor_from_base.linear();
  for (std::size_t i = 0; i < taught.size(); ++i) {
    a_full_.block(3 * i, 0, 3, kNumParams) =
        r * kinematics::ComputePointParamJacobian(model, taught[i], setup.ball_in_flange);
  }
}

Eigen::MatrixXd DriftModel::Solve(const Eigen::MatrixXd& y, const IdentificationOptions& options,
                                  IdentificationSummary* summary) const {
  ThrowIfInvalid(options.Validate(), "IdentificationOptions");
  std::vector<int> params = options.params.empty() ? model_.FreeParams() : options.params;
  std::vector<int> poses = options.poses;
  if (poses.empty()) {
    for (int i = 0; i < NumPoses(); ++i) poses.push_back(i);
  }
  for (int p : poses) {
    if (p >= NumPoses()) throw InputError({"", 0, "poses"}, "pose position " + std::to_string(p) + " out of range");
  }
  const int m = static_cast<int>(poses.size());
  const int k = static_cast<int>(params.size());
  CheckEquationCount(m, k);
  if (y.rows() != 3 * m) {
    throw InputError({"", 0, "Y"},
                     "differences have " + std::to_string(y.rows()) + " rows, expected " + std::to_string(3 * m));
  }
  Eigen::MatrixXd a(3 * m, k);
  for (int i = 0; i < m; ++i) {
    for (int c = 0; c < k; ++c) a.block(3 * i, c, 3, 1) = a_full_.block(3 * poses[i], params[c], 3, 1);
  }
  Eigen::VectorXd scale(k);
  for (int c = 0; c < k; ++c) {
    const double n = a.col(c).norm();
    scale[c] = n > 0.0 ? 1.0 / n : 1.0;
  }
  const Eigen::MatrixXd as = a * scale.asDiagonal();
  Eigen::BDCSVD<Eigen::MatrixXd> svd(as, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double smax = s.size() > 0 ? s[0] : 0.0;
  Eigen::VectorXd s_inv = Eigen::VectorXd::Zero(s.size());
  int dropped = 0;
  for (int i = 0; i < s.size(); ++i) {
    if (s[i] > options.singular_value_rtol * smax && s[i] > 0.0) {
      s_inv[i] = 1.0 / s[i];
    } else {
      ++dropped;
    }
  }
  // Eq. (3-10) on the equilibrated columns.
  Eigen::MatrixXd x_sub;
  const bool weighted = !options.difference_covariance_mm2.empty();
  std::vector<Eigen::MatrixXd> inverse_info;  // per column, (Aᵀ W A)⁻¹
  Eigen::VectorXd chi2 = Eigen::VectorXd::Zero(y.cols());
  if (!weighted) {
    const Eigen::MatrixXd x_scaled = svd.matrixV() * s_inv.asDiagonal() * (svd.matrixU().transpose() * y);
    x_sub = scale.asDiagonal() * x_scaled;
    if (summary != nullptr) {
      const Eigen::MatrixXd vs = svd.matrixV() * s_inv.asDiagonal();
      inverse_info.assign(static_cast<std::size_t>(y.cols()),
                          scale.asDiagonal() * (vs * vs.transpose()) * scale.asDiagonal());
      chi2 = (y - a * x_sub).colwise().squaredNorm().transpose();
    }
  } else {
    x_sub = SolveWeighted(a, y, poses, options, summary != nullptr ? &inverse_info : nullptr,
                          summary != nullptr ? &chi2 : nullptr);
  }
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(kNumParams, y.cols());
  for (int c = 0; c < k; ++c) x.row(params[c]) = x_sub.row(c);

  if (summary != nullptr) {
    IdentificationSummary& out = *summary;
    out = IdentificationSummary{};
    out.params = params;
    out.iterations = 1;
    out.num_poses = m;
    out.num_equations = 3 * m;
    out.singular_values = s;
    const double smin = s.size() > 0 ? s[s.size() - 1] : 0.0;
    out.condition_number = smin > 0.0 ? smax / smin : std::numeric_limits<double>::infinity();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(as);
    qr.setThreshold(options.rank_rtol);
    out.rank = static_cast<int>(qr.rank());
    for (int i = out.rank; i < k; ++i) out.dependent_params.push_back(params[qr.colsPermutation().indices()[i]]);
    for (int i = 0; i < s.size(); ++i) {
      if (s[i] > options.rank_rtol * smax) continue;
      NullCombination combo;
      const Eigen::VectorXd v = svd.matrixV().col(i);
      for (int c = 0; c < k; ++c) {
        if (std::abs(v[c]) > 0.05) {
          combo.params.push_back(params[c]);
          combo.coefficients.push_back(v[c]);
        }
      }
      out.null_space.push_back(combo);
    }
    out.termination = dropped == 0 ? Termination::kSuccess : Termination::kPartial;
    out.message = dropped == 0 ? "solved" : "rank deficient (" + std::to_string(dropped) + " dropped)";
    out.weighted = weighted;
    const Eigen::MatrixXd residual = y - a * x_sub;
    out.num_cycles = static_cast<int>(y.cols());
    out.initial_cost = 0.5 * y.squaredNorm();
    out.final_cost = 0.5 * residual.squaredNorm();
    out.rms_residual_mm = residual.size() > 0 ? std::sqrt(residual.squaredNorm() / residual.size()) : 0.0;
    out.worst_residual_mm = residual.size() > 0 ? residual.cwiseAbs().maxCoeff() : 0.0;
    // Pooled residual χ² over the columns that hold data (the reference cycle's column is
    // identically zero and carries no degrees of freedom).
    double chi2_sum = 0.0;
    for (Eigen::Index c = 0; c < y.cols(); ++c) {
      if (y.col(c).isZero(0.0)) continue;
      chi2_sum += chi2[c];
      out.residual_dof += 3 * m - k;
    }
    out.reduced_chi2 = out.residual_dof > 0 ? chi2_sum / out.residual_dof : std::numeric_limits<double>::quiet_NaN();
    char buf[200];
    if (!weighted) {
      out.covariance_scale = out.reduced_chi2;
      std::snprintf(buf, sizeof(buf),
                    "sigma from s^2 (A^T A)^-1, s^2 = residual chi^2 / dof = %.4g mm^2 (s = %.4g mm per coordinate, "
                    "%d dof; unweighted: the noise is estimated from the residual)",
                    out.reduced_chi2, std::sqrt(out.reduced_chi2), out.residual_dof);
    } else {
      out.covariance_scale =
          std::isfinite(out.reduced_chi2) ? std::max(1.0, out.reduced_chi2) : 1.0;
      std::snprintf(buf, sizeof(buf),
                    "sigma from max(1, reduced chi^2) (A^T C^-1 A)^-1, reduced chi^2 = %.4g (%d dof; the centre "
                    "covariances are a lower bound: inflated, never shrunk)",
                    out.reduced_chi2, out.residual_dof);
    }
    out.covariance_scaling = buf;
    // The reference cycle's ΔX is zero by definition: its covariance is zero.
    out.covariance.reserve(inverse_info.size());
    for (std::size_t c = 0; c < inverse_info.size(); ++c) {
      const bool reference = y.col(static_cast<Eigen::Index>(c)).isZero(0.0);
      out.covariance.push_back(reference ? Eigen::MatrixXd::Zero(k, k) : Eigen::MatrixXd(out.covariance_scale * inverse_info[c]));
    }
  }
  return x;
}

double ResidualSigmaY(const IdentificationSummary& s) {
  const double dof = s.num_equations - static_cast<double>(s.params.size());
  return dof > 0 ? s.rms_residual_mm * std::sqrt(s.num_equations / dof) : s.rms_residual_mm;
}

Eigen::MatrixXd DriftModel::Covariance(const IdentificationOptions& options, double sigma_y_mm) const {
  const std::vector<int> params = options.params.empty() ? model_.FreeParams() : options.params;
  std::vector<int> poses = options.poses;
  if (poses.empty()) {
    for (int i = 0; i < NumPoses(); ++i) poses.push_back(i);
  }
  Eigen::MatrixXd a(3 * poses.size(), params.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    for (std::size_t c = 0; c < params.size(); ++c)
      a.block(3 * i, c, 3, 1) = a_full_.block(3 * poses[i], params[c], 3, 1);
  }
  const Eigen::MatrixXd info = a.transpose() * a;
  return sigma_y_mm * sigma_y_mm * info.completeOrthogonalDecomposition().pseudoInverse();
}

std::vector<Eigen::MatrixXd> DriftModel::WeightedCovariances(const IdentificationOptions& options) const {
  const auto& cov = options.difference_covariance_mm2;
  if (cov.empty()) throw InputError({"", 0, "difference_covariance_mm2"}, "no covariances given");
  const std::vector<int> params = options.params.empty() ? model_.FreeParams() : options.params;
  std::vector<int> poses = options.poses;
  if (poses.empty()) {
    for (int i = 0; i < NumPoses(); ++i) poses.push_back(i);
  }
  const Eigen::Index k = static_cast<Eigen::Index>(params.size());
  std::vector<Eigen::MatrixXd> out;
  for (std::size_t c = 0; c < cov.size(); ++c) {
    Eigen::MatrixXd info = Eigen::MatrixXd::Zero(k, k);
    for (int pose : poses) {
      if (pose < 0 || pose >= static_cast<int>(cov[c].size()) || pose >= NumPoses())
        throw InputError({"", 0, "difference_covariance_mm2"},
                         "cycle " + std::to_string(c) + " lacks pose position " + std::to_string(pose));
      const Eigen::LLT<Mat3> llt(cov[c][pose]);
      if (llt.info() != Eigen::Success)
        throw InputError({"", 0, "difference_covariance_mm2"}, "not positive definite at cycle " + std::to_string(c) +
                                                                   ", pose position " + std::to_string(pose));
      Eigen::MatrixXd a(3, k);
      for (Eigen::Index j = 0; j < k; ++j) a.col(j) = a_full_.block(3 * pose, params[j], 3, 1);
      const Eigen::MatrixXd aw = llt.matrixL().solve(a);  // C^-1/2 A
      info += aw.transpose() * aw;
    }
    out.push_back(info.completeOrthogonalDecomposition().pseudoInverse());
  }
  return out;
}

Eigen::MatrixXd IdentifyCycles(const RobotModel& model, const ThermalSetup& setup, const CycleSeries& ball,
                               const IdentificationOptions& options, IdentificationSummary* summary) {
  const DriftModel drift_model(model, setup, ball.taught);
  return drift_model.Solve(ball.DifferencesFromReference(options.poses), options, summary);
}

std::string IdentifiabilityOptions::Validate() const {
  if (!(max_condition >= 1.0)) return "max_condition must be >= 1";
  if (!(min_component > 0.0 && min_component < 1.0)) return "min_component must be in (0, 1)";
  return "";
}

std::string UnobservableCombination::Describe() const {
  std::string out;
  for (std::size_t i = 0; i < params.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%s%+.3f*", out.empty() ? "" : " ", coefficients[i]);
    out += buf + kinematics::ParamName(params[i]);
  }
  return out;
}

std::string IdentifiabilitySummary::BriefReport() const {
  char buf[200];
  std::snprintf(buf, sizeof(buf), "identifiability: %zu params, %d poses, condition number %.3g of the column-scaled "
                "matrix (limit %.3g): ",
                params.size(), num_poses, condition_number, max_condition);
  return buf + message;
}

namespace {

struct ScaledSvd {
  Eigen::VectorXd s;
  Eigen::MatrixXd v;
  double condition = 0.0;
};

ScaledSvd AnalyseSet(const DriftModel& dm, const std::vector<int>& params, const std::vector<int>& poses) {
  const int m = static_cast<int>(poses.size());
  const int k = static_cast<int>(params.size());
  Eigen::MatrixXd a(3 * m, k);
  for (int i = 0; i < m; ++i) {
    for (int c = 0; c < k; ++c) a.block(3 * i, c, 3, 1) = dm.FullSensitivity().block(3 * poses[i], params[c], 3, 1);
  }
  for (int c = 0; c < k; ++c) {
    const double n = a.col(c).norm();
    if (n > 0.0) a.col(c) /= n;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinV);
  ScaledSvd out{svd.singularValues(), svd.matrixV(), 0.0};
  const double smin = out.s.size() > 0 ? out.s[out.s.size() - 1] : 0.0;
  // A singular value at rounding level is a zero one.
  const bool singular = !(smin > 1e-13 * out.s[0]);
  out.condition = singular ? std::numeric_limits<double>::infinity() : out.s[0] / smin;
  return out;
}

// "joints 1 and 5 axes parallel at these poses (largest angle 0.021 deg)" when every named
// parameter moves along or about a joint axis (d, θ) and those axes stay within 1° of parallel.
std::string ParallelAxesCause(const DriftModel& dm, const std::vector<int>& params, const std::vector<int>& poses,
                              const std::vector<JointVector>& taught) {
  std::vector<int> joints;
  for (int p : params) {
    const auto kind = kinematics::ParamKindOf(p);
    if (kind != kinematics::ParamKind::kD && kind != kinematics::ParamKind::kTheta) return "";
    const int j = kinematics::ParamJointOf(p);
    if (std::find(joints.begin(), joints.end(), j) == joints.end()) joints.push_back(j);
  }
  if (joints.size() < 2 || taught.empty()) return "";
  std::sort(joints.begin(), joints.end());
  double worst = 0.0;
  for (int pose : poses) {
    const kinematics::ChainFrames f = kinematics::ComputeChainFrames(dm.model(), taught[pose]);
    const Vec3 z0 = f.base_from_link[joints[0]].linear().col(2);
    for (std::size_t i = 1; i < joints.size(); ++i) {
      const Vec3 zi = f.base_from_link[joints[i]].linear().col(2);
      worst = std::max(worst, std::atan2(z0.cross(zi).norm(), std::abs(z0.dot(zi))));
    }
  }
  if (RadToDeg(worst) > 1.0) return "";
  std::string names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    names += (i == 0 ? "" : i + 1 == joints.size() ? " and " : ", ") + std::to_string(joints[i] + 1);
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), " axes parallel at these poses (largest angle %.3g deg)", RadToDeg(worst));
  return "joints " + names + buf;
}

UnobservableCombination Weakest(const ScaledSvd& svd, const std::vector<int>& params, double min_component) {
  UnobservableCombination c;
  c.condition_number = svd.condition;
  const Eigen::VectorXd v = svd.v.col(svd.v.cols() - 1);
  // Sign convention: the largest component positive.
  Eigen::Index largest = 0;
  v.cwiseAbs().maxCoeff(&largest);
  const double sign = v[largest] < 0.0 ? -1.0 : 1.0;
  std::vector<int> order(params.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return std::abs(v[x]) > std::abs(v[y]); });
  for (int i : order) {
    if (std::abs(v[i]) <= min_component) break;
    c.params.push_back(params[i]);
    c.coefficients.push_back(sign * v[i]);
  }
  return c;
}

}  // namespace

IdentifiabilitySummary CheckIdentifiability(const DriftModel& drift_model, const std::vector<int>& params,
                                            const std::vector<int>& poses, const IdentifiabilityOptions& options) {
  ThrowIfInvalid(options.Validate(), "IdentifiabilityOptions");
  IdentifiabilitySummary out;
  out.requested = params.empty() ? drift_model.model().FreeParams() : params;
  std::vector<int> pose_list = poses;
  if (pose_list.empty()) {
    for (int i = 0; i < drift_model.NumPoses(); ++i) pose_list.push_back(i);
  }
  for (int p : pose_list) {
    if (p < 0 || p >= drift_model.NumPoses())
      throw InputError({"", 0, "poses"}, "pose position " + std::to_string(p) + " out of range");
  }
  for (int p : out.requested) {
    if (p < 0 || p >= kNumParams) throw InputError({"", 0, "params"}, "parameter index out of range");
  }
  out.num_poses = static_cast<int>(pose_list.size());
  out.max_condition = options.max_condition;
  CheckEquationCount(out.num_poses, static_cast<int>(out.requested.size()));
  const std::vector<JointVector>& taught = drift_model.taught();
  std::vector<int> current = out.requested;
  ScaledSvd svd = AnalyseSet(drift_model, current, pose_list);
  while (!(svd.condition <= options.max_condition)) {
    UnobservableCombination combo = Weakest(svd, current, options.min_component);
    combo.cause = ParallelAxesCause(drift_model, combo.params, pose_list, taught);
    if (!options.reduce || current.size() <= 1) {
      out.combinations.push_back(combo);
      out.params = current;
      out.singular_values = svd.s;
      out.condition_number = svd.condition;
      out.termination = Termination::kNoResult;
      std::string names;
      for (std::size_t i = 0; i < combo.params.size(); ++i) {
        names += (i == 0 ? "" : ", ") + kinematics::ParamName(combo.params[i]);
      }
      out.message = "not identifiable: " + combo.Describe() + " is not observable" +
                    (combo.cause.empty() ? "" : " (" + combo.cause + ")") + "; drop one of " + names +
                    " or add poses that separate them";
      return out;
    }
    // Drop the member of the combination whose removal leaves the best-conditioned set; ties go
    // to the larger component, then to the later parameter.
    int best = -1;
    double best_condition = std::numeric_limits<double>::infinity();
    ScaledSvd best_svd;
    for (int p : combo.params) {
      std::vector<int> trial;
      for (int q : current) {
        if (q != p) trial.push_back(q);
      }
      ScaledSvd t = AnalyseSet(drift_model, trial, pose_list);
      if (best < 0 || t.condition < best_condition * (1.0 - 1e-9)) {
        best = p;
        best_condition = t.condition;
        best_svd = std::move(t);
      }
    }
    current.erase(std::find(current.begin(), current.end(), best));
    out.dropped.push_back(best);
    out.combinations.push_back(combo);
    svd = std::move(best_svd);
  }
  out.params = current;
  out.singular_values = svd.s;
  out.condition_number = svd.condition;
  if (out.dropped.empty()) {
    out.termination = Termination::kSuccess;
    out.message = "identifiable";
  } else {
    out.termination = Termination::kPartial;
    out.message = "identifiable after dropping " + ParamListToString(out.dropped) + " (";
    for (std::size_t i = 0; i < out.combinations.size(); ++i) {
      const UnobservableCombination& c = out.combinations[i];
      out.message += (i == 0 ? "" : "; ") + kinematics::ParamName(out.dropped[i]) + " from " + c.Describe() +
                     (c.cause.empty() ? "" : ", " + c.cause);
    }
    out.message += ")";
  }
  return out;
}

std::vector<int> SelectPoses(const DriftModel& drift_model, const std::vector<int>& params, int count) {
  const int n = drift_model.NumPoses();
  const int k = static_cast<int>(params.size());
  if (count > n)
    throw InputError({"", 0, "poses"},
                     "cannot select " + std::to_string(count) + " of " + std::to_string(n) + " poses");
  Eigen::MatrixXd a(3 * n, k);
  for (int c = 0; c < k; ++c) a.col(c) = drift_model.FullSensitivity().col(params[c]);
  for (int c = 0; c < k; ++c) {
    const double norm = a.col(c).norm();
    if (norm > 0.0) a.col(c) /= norm;
  }
  std::vector<int> chosen;
  std::vector<bool> used(n, false);
  Eigen::MatrixXd info = 1e-6 * Eigen::MatrixXd::Identity(k, k);
  for (int step = 0; step < count; ++step) {
    int best = -1;
    double best_value = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      if (used[i]) continue;
      const Eigen::MatrixXd block = a.middleRows(3 * i, 3);
      const Eigen::MatrixXd trial = info + block.transpose() * block;
      const double value = Eigen::LDLT<Eigen::MatrixXd>(trial).vectorD().array().log().sum();
      if (value > best_value) {
        best_value = value;
        best = i;
      }
    }
    used[best] = true;
    chosen.push_back(best);
    const Eigen::MatrixXd block = a.middleRows(3 * best, 3);
    info += block.transpose() * block;
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

std::vector<int> TraditionalParams(const RobotModel& model) {
  std::vector<int> out;
  const ParamVector p = model.Params();
  for (int i = 0; i < kNumParams; ++i) {
    const auto kind = kinematics::ParamKindOf(i);
    if ((kind == kinematics::ParamKind::kD || kind == kinematics::ParamKind::kA) && !model.structural_zero[i] &&
        std::abs(p[i]) > 1e-9) {
      out.push_back(i);
    }
  }
  return out;
}

std::vector<int> ParseParamList(const std::string& text, const RobotModel& model, const std::string& field) {
  if (text == "traditional") return TraditionalParams(model);
  if (text == "all" || text == "free" || text.empty()) return model.FreeParams();
  std::vector<int> out;
  std::stringstream ss(text);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto b = name.find_first_not_of(" \t");
    const auto e = name.find_last_not_of(" \t");
    name = b == std::string::npos ? "" : name.substr(b, e - b + 1);
    const int index = kinematics::ParamIndexFromName(name);
    if (index < 0) {
      throw InputError({"", 0, field}, "unknown parameter '" + name +
                                           "' (names are d1..d6, theta1..theta6, a1..a6, alpha1..alpha6, "
                                           "beta1..beta6, or 'traditional' / 'all')");
    }
    if (model.structural_zero[index]) {
      throw InputError({"", 0, field}, "parameter '" + name + "' is a structural zero of " + model.name);
    }
    for (int p : out) {
      if (p == index) throw InputError({"", 0, field}, "parameter '" + name + "' given twice");
    }
    out.push_back(index);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string ParamListToString(const std::vector<int>& params) {
  std::string s;
  for (int p : params) s += (s.empty() ? "" : ",") + kinematics::ParamName(p);
  return s;
}

double ToFileUnits(int index, double value) { return kinematics::IsAngleParam(index) ? RadToDeg(value) : value; }

double SigmaToFileUnits(int index, double sigma) { return ToFileUnits(index, sigma); }

}  // namespace ramtk::thermal
