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

namespace {

// Generalised least squares per column of y: every pose's 3 rows whitened by L⁻¹ (C = L·Lᵀ of
// that column's difference), columns equilibrated, SVD with the same truncation as eq. (3-10).
Eigen::MatrixXd SolveWeighted(const Eigen::MatrixXd& a, const Eigen::MatrixXd& y, const std::vector<int>& poses,
                              const IdentificationOptions& options) {
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
  }
  return x;
}

}  // namespace

DriftModel::DriftModel(const RobotModel& model, const ThermalSetup& setup, const std::vector<JointVector>& taught)
    : model_(model), a_full_(3 * taught.size(), kNumParams) {
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
  if (k == 0) throw InputError({"", 0, "params"}, "no parameters to identify");
  if (3 * m < k) {
    throw InputError({"", 0, "poses"}, std::to_string(m) + " poses give " + std::to_string(3 * m) +
                                           " equations, fewer than the " + std::to_string(k) +
                                           " parameters to identify (need at least " + std::to_string((k + 2) / 3) +
                                           " poses)");
  }
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
  if (!weighted) {
    const Eigen::MatrixXd x_scaled = svd.matrixV() * s_inv.asDiagonal() * (svd.matrixU().transpose() * y);
    x_sub = scale.asDiagonal() * x_scaled;
  } else {
    x_sub = SolveWeighted(a, y, poses, options);
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

}  // namespace ramtk::thermal
