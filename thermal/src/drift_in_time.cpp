#include "ramtk/thermal/drift_in_time.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "ramtk/core/error.h"

namespace ramtk::thermal {

using kinematics::kNumParams;

std::string DriftInTimeOptions::Validate() const {
  for (int p : params) {
    if (p < 0 || p >= kNumParams) return "parameter index out of range";
  }
  if (!(robot_noise_mm >= 0.0) || !std::isfinite(robot_noise_mm)) return "robot_noise_mm must be >= 0";
  return "";
}

namespace {

// D(t) = Σ weight · D_knot over a few knots.
using KnotWeights = std::vector<std::pair<int, double>>;

void Add(int knot, double weight, KnotWeights* w) {
  for (auto& [k, v] : *w) {
    if (k == knot) {
      v += weight;
      return;
    }
  }
  w->emplace_back(knot, weight);
}

// Weights of the derivative at x of the quadratic through the knots i, i+1, i+2 (Lagrange).
KnotWeights QuadraticSlope(const std::vector<double>& t, int i, double x) {
  KnotWeights w;
  for (int a = i; a < i + 3; ++a) {
    double sum = 0.0;
    for (int m = i; m < i + 3; ++m) {
      if (m == a) continue;
      double prod = 1.0 / (t[a] - t[m]);
      for (int l = i; l < i + 3; ++l)
        if (l != a && l != m) prod *= (x - t[l]) / (t[a] - t[l]);
      sum += prod;
    }
    w.emplace_back(a, sum);
  }
  return w;
}

// The slope at knot j: of the parabola through it and its neighbours (one-sided at the ends),
// the chord with two knots.
KnotWeights KnotSlope(const std::vector<double>& t, int j) {
  const int n = static_cast<int>(t.size());
  if (n == 2) return {{0, -1.0 / (t[1] - t[0])}, {1, 1.0 / (t[1] - t[0])}};
  return QuadraticSlope(t, std::clamp(j - 1, 0, n - 3), t[j]);
}

KnotWeights Interpolate(const std::vector<double>& t, double x, DriftTimeModel model) {
  const int n = static_cast<int>(t.size());
  const int upper = static_cast<int>(std::upper_bound(t.begin(), t.end(), x) - t.begin());
  const int s = std::clamp(upper - 1, 0, n - 2);
  const double h = t[s + 1] - t[s];
  const double u = (x - t[s]) / h;
  KnotWeights w;
  if (model == DriftTimeModel::kPiecewiseLinear) {
    Add(s, 1.0 - u, &w);
    Add(s + 1, u, &w);
    return w;
  }
  // Cubic Hermite on the segment (extended past the end knots), knot slopes from parabolas: it
  // reproduces any quadratic in time exactly.
  const double u2 = u * u, u3 = u2 * u;
  Add(s, 2 * u3 - 3 * u2 + 1, &w);
  Add(s + 1, -2 * u3 + 3 * u2, &w);
  for (const auto& [k, v] : KnotSlope(t, s)) Add(k, h * (u3 - 2 * u2 + u) * v, &w);
  for (const auto& [k, v] : KnotSlope(t, s + 1)) Add(k, h * (u3 - u2) * v, &w);
  return w;
}

// The weights of the centre of cycle c measured at time x.
KnotWeights WeightsFor(const std::vector<double>& t, int c, double x, DriftTimeModel model) {
  if (model == DriftTimeModel::kConstantPerCycle) return {{c, 1.0}};
  return Interpolate(t, x, model);
}

// A centre's covariance: its scan covariance (when the file has one) plus the repeatability σ²·I;
// the identity when unweighted.
Mat3 CentreCovariance(const CycleSeries& series, int c, int k, double robot_noise_mm, bool weighted) {
  if (!weighted) return Mat3::Identity();
  Mat3 cov = robot_noise_mm * robot_noise_mm * Mat3::Identity();
  if (series.has_covariance) cov += series.cycles[c].covariance_mm2[k];
  return cov;
}

}  // namespace

kinematics::ParamVector DriftInTimeResult::At(double t) const {
  kinematics::ParamVector x = kinematics::ParamVector::Zero();
  if (time_s.size() < 2) return x;
  if (model == DriftTimeModel::kConstantPerCycle) {
    std::size_t nearest = 0;
    for (std::size_t c = 1; c < time_s.size(); ++c)
      if (std::abs(time_s[c] - t) < std::abs(time_s[nearest] - t)) nearest = c;
    return delta_x.col(static_cast<Eigen::Index>(nearest));
  }
  for (const auto& [k, v] : Interpolate(time_s, t, model)) x += v * delta_x.col(k);
  return x;
}

std::string DriftInTimeResult::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "drift identified in time: %zu params, %zu cycles, %d dof, %s %.4g (%s)", params.size(),
                time_s.size(), residual_dof, weighted ? "reduced chi2" : "s^2 (mm^2)", reduced_chi2,
                weighted ? "each centre weighted by its covariance and the repeatability" : "unit weights");
  return buf;
}

DriftInTimeResult IdentifyDriftInTime(const DriftModel& drift_model, const CycleSeries& series,
                                      const DriftInTimeOptions& options) {
  ThrowIfInvalid(options.Validate(), "DriftInTimeOptions");
  const int cycles = series.NumCycles();
  const int poses = series.NumPoses();
  if (cycles < 2) throw InputError({series.path, 0, "cycle"}, "needs the reference and at least one more cycle");
  if (poses != drift_model.NumPoses())
    throw InputError({series.path, 0, "pose"}, "the drift model and the series hold different poses");
  DriftInTimeResult r;
  r.params = options.params.empty() ? drift_model.model().FreeParams() : options.params;
  const int p = static_cast<int>(r.params.size());
  for (const Cycle& c : series.cycles) {
    if (static_cast<int>(c.pose_time_s.size()) != poses)
      throw InputError({series.path, 0, "time_s"}, "cycle " + std::to_string(c.cycle) + " lacks its poses' times");
    r.time_s.push_back(c.time_s);
  }
  for (int c = 1; c < cycles; ++c) {
    if (!(r.time_s[c] > r.time_s[c - 1]))
      throw InputError({series.path, 0, "time_s"}, "cycle " + std::to_string(series.cycles[c].cycle) +
                                                       " is not later than the cycle before it");
  }
  const int n = 3 * poses + p * (cycles - 1);
  const int m = 3 * poses * cycles;
  r.residual_dof = m - n;
  if (r.residual_dof < 0)
    throw InputError({series.path, 0, "pose"}, std::to_string(m) + " centre coordinates cannot determine " +
                                                   std::to_string(n) + " unknowns");
  r.weighted = series.has_covariance || options.robot_noise_mm > 0.0;

  // Normal equations N z = b over z = [Q_0 .. Q_K-1, D_1 .. D_C-1], accumulated centre by centre:
  // each centre touches its pose's Q and at most two knots.
  const Eigen::MatrixXd& a_full = drift_model.FullSensitivity();
  std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> sens(poses, Eigen::Matrix<double, 3, Eigen::Dynamic>(3, p));
  for (int k = 0; k < poses; ++k)
    for (int j = 0; j < p; ++j) sens[k].col(j) = a_full.block(3 * k, r.params[j], 3, 1);
  std::vector<std::vector<Mat3>> weight(cycles, std::vector<Mat3>(poses));
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < poses; ++k) {
      const Mat3 cov = CentreCovariance(series, c, k, options.robot_noise_mm, r.weighted);
      const Eigen::LLT<Mat3> llt(cov);
      if (llt.info() != Eigen::Success)
        throw InputError({series.path, 0, "cov_xx"}, "centre covariance not positive definite at cycle " +
                                                         std::to_string(series.cycles[c].cycle));
      weight[c][k] = llt.solve(Mat3::Identity());
    }
  }
  // Local columns of a centre: its Q (3), then each knot's p (absent for knot 0, D_0 = 0).
  auto local = [&](int c, int k, Eigen::MatrixXd* jac, std::vector<int>* cols) {
    const KnotWeights w = WeightsFor(r.time_s, c, series.cycles[c].pose_time_s[k], options.model);
    cols->clear();
    for (int i = 0; i < 3; ++i) cols->push_back(3 * k + i);
    jac->setZero(3, 3 + p * static_cast<int>(w.size()));
    jac->leftCols(3).setIdentity();
    int used = 3;
    for (const auto& [knot, v] : w) {
      if (knot == 0 || v == 0.0) continue;
      jac->middleCols(used, p) = v * sens[k];
      for (int i = 0; i < p; ++i) cols->push_back(3 * poses + (knot - 1) * p + i);
      used += p;
    }
    jac->conservativeResize(3, used);
  };
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd jac;
  std::vector<int> cols;
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < poses; ++k) {
      local(c, k, &jac, &cols);
      const Eigen::MatrixXd jw = jac.transpose() * weight[c][k];
      const Eigen::MatrixXd nn = jw * jac;
      const Eigen::VectorXd bb = jw * series.cycles[c].position_mm[k];
      for (std::size_t i = 0; i < cols.size(); ++i) {
        rhs[cols[i]] += bb[static_cast<Eigen::Index>(i)];
        for (std::size_t j = 0; j < cols.size(); ++j)
          normal(cols[i], cols[j]) += nn(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      }
    }
  }
  // Equilibrated (unit diagonal) symmetric pseudo-inverse: mm and rad columns compare.
  const Eigen::VectorXd scale = normal.diagonal().cwiseMax(std::numeric_limits<double>::min()).cwiseSqrt().cwiseInverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scale.asDiagonal() * normal * scale.asDiagonal());
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const double cutoff = lambda.maxCoeff() * 1e-12;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    if (lambda[i] > cutoff) inv[i] = 1.0 / lambda[i];
  Eigen::MatrixXd covariance =
      scale.asDiagonal() * (eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose()) * scale.asDiagonal();
  const Eigen::VectorXd z = covariance * rhs;

  double chi2 = 0.0;
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < poses; ++k) {
      local(c, k, &jac, &cols);
      Eigen::VectorXd zl(static_cast<Eigen::Index>(cols.size()));
      for (std::size_t i = 0; i < cols.size(); ++i) zl[static_cast<Eigen::Index>(i)] = z[cols[i]];
      const Vec3 res = series.cycles[c].position_mm[k] - jac * zl;
      chi2 += res.dot(weight[c][k] * res);
    }
  }
  r.reduced_chi2 = r.residual_dof > 0 ? chi2 / r.residual_dof : std::numeric_limits<double>::quiet_NaN();
  if (!r.weighted) covariance *= r.residual_dof > 0 ? r.reduced_chi2 : 0.0;

  r.delta_x = Eigen::MatrixXd::Zero(kNumParams, cycles);
  r.covariance.assign(cycles, Eigen::MatrixXd::Zero(p, p));
  r.model = options.model;
  for (int c = 1; c < cycles; ++c) {
    const int off = 3 * poses + (c - 1) * p;
    for (int j = 0; j < p; ++j) r.delta_x(r.params[j], c) = z[off + j];
    r.covariance[c] = covariance.block(off, off, p, p);
  }
  return r;
}

}  // namespace ramtk::thermal
