#include "ramtk/diagnose/robot/detail/robot_linear.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "ramtk/kinematics/forward.h"

namespace ramtk::diagnose::robot_detail {
namespace {

// Pseudo-inverse of a symmetric positive semi-definite matrix.
Eigen::MatrixXd PinvSym(const Eigen::MatrixXd& m, double rtol = 1e-9) {
  if (m.rows() == 0) return m;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
  const Eigen::VectorXd ev = es.eigenvalues();
  const double top = ev.cwiseAbs().maxCoeff();
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(ev.size());
  if (top > 0)
    for (int i = 0; i < ev.size(); ++i)
      if (ev[i] > rtol * top) inv[i] = 1.0 / ev[i];
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

Eigen::VectorXd ColumnScales(const std::vector<Mat3X>& blocks, const std::vector<char>& use, int k) {
  Eigen::VectorXd ss = Eigen::VectorXd::Zero(k);
  int n = 0;
  for (size_t i = 0; i < blocks.size(); ++i) {
    if (!use[i]) continue;
    ss += blocks[i].colwise().squaredNorm().transpose();
    ++n;
  }
  Eigen::VectorXd scale(k);
  for (int j = 0; j < k; ++j) scale[j] = ss[j] > 0 && n > 0 ? 1.0 / std::sqrt(ss[j] / n) : 0.0;
  return scale;
}

Eigen::MatrixXd Pooled(const std::vector<Mat3X>& blocks) {
  if (blocks.empty()) return Eigen::MatrixXd();
  Eigen::MatrixXd m(3 * blocks.size(), blocks[0].cols());
  for (size_t i = 0; i < blocks.size(); ++i) m.middleRows(3 * i, 3) = blocks[i];
  return m;
}

}  // namespace

Fit SolveDesign(const std::vector<Row>& rows, const Design& d, const std::vector<char>& train, int num_cycles) {
  const int ns = d.ns, np = d.np;
  const Eigen::VectorXd ks = ColumnScales(d.stat, train, ns);
  const Eigen::VectorXd kp = np > 0 ? ColumnScales(d.cycle, train, np) : Eigen::VectorXd();
  std::vector<Eigen::MatrixXd> a(num_cycles, Eigen::MatrixXd::Zero(np, np)),
      b(num_cycles, Eigen::MatrixXd::Zero(np, ns));
  std::vector<Eigen::VectorXd> g(num_cycles, Eigen::VectorXd::Zero(np));
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(ns, ns);
  Eigen::VectorXd h = Eigen::VectorXd::Zero(ns);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!train[i]) continue;
    const Eigen::MatrixXd js = d.stat[i] * ks.asDiagonal();
    const Eigen::Vector3d& r = rows[i].residual;
    s.noalias() += js.transpose() * js;
    h.noalias() += js.transpose() * r;
    if (np > 0) {
      const int c = rows[i].cycle_pos;
      const Eigen::MatrixXd jp = d.cycle[i] * kp.asDiagonal();
      a[c].noalias() += jp.transpose() * jp;
      b[c].noalias() += jp.transpose() * js;
      g[c].noalias() += jp.transpose() * r;
    }
  }
  std::vector<Eigen::MatrixXd> a_inv(num_cycles);
  Eigen::MatrixXd s_red = s;
  Eigen::VectorXd h_red = h;
  if (np > 0) {
    for (int c = 0; c < num_cycles; ++c) {
      a_inv[c] = PinvSym(a[c]);
      s_red.noalias() -= b[c].transpose() * a_inv[c] * b[c];
      h_red.noalias() -= b[c].transpose() * (a_inv[c] * g[c]);
    }
  }
  const Eigen::MatrixXd s_inv = PinvSym(0.5 * (s_red + s_red.transpose()));
  Fit f;
  const Eigen::VectorXd s_scaled = s_inv * h_red;
  f.s = ks.asDiagonal() * s_scaled;
  f.s_cov_unit = ks.asDiagonal() * s_inv * ks.asDiagonal();
  f.p = Eigen::MatrixXd::Zero(np, num_cycles);
  for (int c = 0; c < num_cycles && np > 0; ++c) f.p.col(c) = kp.asDiagonal() * (a_inv[c] * (g[c] - b[c] * s_scaled));
  f.ok = f.s.allFinite() && f.p.allFinite();
  return f;
}

Eigen::Vector3d FitResidual(const std::vector<Row>& rows, const Design& d, const Fit& f, int i) {
  Eigen::Vector3d r = rows[i].residual;
  if (d.ns > 0) r -= d.stat[i] * f.s;
  if (d.np > 0) r -= d.cycle[i] * f.p.col(rows[i].cycle_pos);
  return r;
}

CvResult CrossValidate(const std::vector<Row>& rows, const Design& d, const std::vector<int>& fold_of_row, int folds,
                       int num_cycles) {
  CvResult cv;
  const size_t n = rows.size();
  cv.heldout_residual.assign(n, Eigen::Vector3d::Zero());
  for (int k = 0; k < folds; ++k) {
    std::vector<char> train(n);
    bool any = false;
    for (size_t i = 0; i < n; ++i) train[i] = fold_of_row[i] != k, any |= fold_of_row[i] == k;
    if (!any) continue;
    const Fit f = SolveDesign(rows, d, train, num_cycles);
    for (size_t i = 0; i < n; ++i) {
      if (train[i]) continue;
      const Eigen::Vector3d r = FitResidual(rows, d, f, static_cast<int>(i));
      cv.heldout_residual[i] = r;
      cv.heldout_ss += r.squaredNorm();
      cv.heldout_n += 3;
    }
  }
  cv.full = SolveDesign(rows, d, std::vector<char>(n, 1), num_cycles);
  for (size_t i = 0; i < n; ++i) {
    cv.train_ss += FitResidual(rows, d, cv.full, static_cast<int>(i)).squaredNorm();
    cv.train_n += 3;
  }
  return cv;
}

std::vector<int> IndependentColumns(const std::vector<Mat3X>& base, const std::vector<Mat3X>& candidate, double rtol) {
  std::vector<int> kept;
  if (candidate.empty()) return kept;
  const Eigen::MatrixXd b = base.empty() || base[0].cols() == 0 ? Eigen::MatrixXd() : Pooled(base);
  const Eigen::MatrixXd c = Pooled(candidate);
  std::vector<Eigen::VectorXd> basis;  // orthonormal
  auto project_out = [&](Eigen::VectorXd v) {
    for (int pass = 0; pass < 2; ++pass)
      for (const Eigen::VectorXd& q : basis) v -= q.dot(v) * q;
    return v;
  };
  for (int j = 0; j < b.cols(); ++j) {
    const double norm = b.col(j).norm();
    if (norm <= 0) continue;
    const Eigen::VectorXd v = project_out(b.col(j) / norm);
    if (v.norm() > rtol) basis.push_back(v.normalized());
  }
  for (int j = 0; j < c.cols(); ++j) {
    const double norm = c.col(j).norm();
    if (norm <= 1e-300) continue;
    const Eigen::VectorXd v = project_out(c.col(j) / norm);
    if (v.norm() > rtol) {
      basis.push_back(v.normalized());
      kept.push_back(j);
    }
  }
  return kept;
}

Design NuisanceDesign(const std::vector<Row>& rows) {
  Design d;
  d.ns = 9;
  d.stat_names = {"sensor_rx_rad", "sensor_ry_rad", "sensor_rz_rad", "sensor_tx_mm", "sensor_ty_mm",
                  "sensor_tz_mm",  "ball_x_mm",     "ball_y_mm",     "ball_z_mm"};
  for (const Row& r : rows) {
    d.stat.push_back(r.j_setup);
    d.cycle.emplace_back(3, 0);
  }
  return d;
}

void AddParamColumns(const std::vector<Row>& rows, const std::vector<int>& params, bool per_cycle, Design* d) {
  const int k = static_cast<int>(params.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    Mat3X& block = per_cycle ? d->cycle[i] : d->stat[i];
    Mat3X grown(3, block.cols() + k);
    grown.leftCols(block.cols()) = block;
    for (int j = 0; j < k; ++j) grown.col(block.cols() + j) = rows[i].j_param.col(params[j]);
    block = grown;
  }
  for (int p : params) (per_cycle ? d->cycle_names : d->stat_names).push_back(kinematics::ParamName(p));
  (per_cycle ? d->np : d->ns) += k;
}

void AddStaticColumns(const std::vector<Mat3X>& cols, const std::vector<std::string>& names, Design* d) {
  const int k = static_cast<int>(names.size());
  for (size_t i = 0; i < d->stat.size(); ++i) {
    Mat3X grown(3, d->stat[i].cols() + k);
    grown.leftCols(d->stat[i].cols()) = d->stat[i];
    grown.rightCols(k) = cols[i];
    d->stat[i] = grown;
  }
  d->stat_names.insert(d->stat_names.end(), names.begin(), names.end());
  d->ns += k;
}

std::vector<Mat3X> SelectColumns(const std::vector<Mat3X>& blocks, const std::vector<int>& keep) {
  std::vector<Mat3X> out;
  out.reserve(blocks.size());
  for (const Mat3X& b : blocks) {
    Mat3X m(3, keep.size());
    for (size_t j = 0; j < keep.size(); ++j) m.col(j) = b.col(keep[j]);
    out.push_back(m);
  }
  return out;
}

Eigen::Matrix<double, 6, 1> GravityTorques(const kinematics::RobotModel& model, const kinematics::JointVector& q,
                                           const Eigen::Vector3d& ball_in_flange) {
  constexpr double kDensityKgPerMm = 0.1, kPayloadKg = 20.0, kG = 9.81;
  const kinematics::ChainFrames f = kinematics::ComputeChainFrames(model, q);
  std::vector<std::pair<double, Eigen::Vector3d>> masses;  // (kg, position) of link k = index + 1
  std::vector<int> link_of;
  for (int k = 1; k <= kinematics::kNumJoints; ++k) {
    const Eigen::Vector3d a = f.base_from_link[k - 1].translation(), b = f.base_from_link[k].translation();
    masses.emplace_back(kDensityKgPerMm * (b - a).norm(), 0.5 * (a + b));
    link_of.push_back(k);
  }
  masses.emplace_back(kPayloadKg, f.base_from_link[6] * ball_in_flange);
  link_of.push_back(kinematics::kNumJoints);
  Eigen::Matrix<double, 6, 1> tau = Eigen::Matrix<double, 6, 1>::Zero();
  for (int j = 1; j <= kinematics::kNumJoints; ++j) {
    const Eigen::Vector3d o = f.base_from_link[j - 1].translation();
    const Eigen::Vector3d z = f.base_from_link[j - 1].linear().col(2);
    for (size_t m = 0; m < masses.size(); ++m) {
      if (link_of[m] < j) continue;
      const Eigen::Vector3d force(0, 0, -masses[m].first * kG);
      tau[j - 1] += z.dot((masses[m].second - o).cross(force)) / 1000.0;
    }
  }
  return tau;
}

}  // namespace ramtk::diagnose::robot_detail
