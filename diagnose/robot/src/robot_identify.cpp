// Identifiability of the robot candidates: how much of a candidate the current model absorbs, how
// alike two candidates' residual signatures are once that is projected out, whether their held-out
// scores differ beyond the cross-validation scatter, and which poses would tell them apart.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "robot_candidates.h"

namespace ramtk::diagnose::robot_detail {
namespace {

Eigen::MatrixXd PooledColumns(const Design& d, int first_stat, int first_cycle) {
  const int n = static_cast<int>(d.stat.size());
  const int k = (d.ns - first_stat) + (d.np - first_cycle);
  Eigen::MatrixXd m(3 * n, k);
  for (int i = 0; i < n; ++i) {
    m.block(3 * i, 0, 3, d.ns - first_stat) = d.stat[i].rightCols(d.ns - first_stat);
    m.block(3 * i, d.ns - first_stat, 3, d.np - first_cycle) = d.cycle[i].rightCols(d.np - first_cycle);
  }
  return m;
}

}  // namespace

namespace {

// Orthonormal basis of the columns of m (each scaled to unit norm first: mm and rad columns mix).
Eigen::MatrixXd Basis(const Eigen::MatrixXd& m) {
  Eigen::MatrixXd n = m;
  for (int j = 0; j < n.cols(); ++j)
    if (n.col(j).norm() > 0) n.col(j).normalize();
  if (n.cols() == 0) return Eigen::MatrixXd(m.rows(), 0);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(n, Eigen::ComputeThinU);
  const Eigen::VectorXd sv = svd.singularValues();
  int rank = 0;
  for (int j = 0; j < sv.size(); ++j) rank += sv[j] > 1e-9 * sv[0] ? 1 : 0;
  return svd.matrixU().leftCols(rank);
}

}  // namespace

double AbsorbedShare(const Design& base, const Design& extended) {
  if (extended.ns <= base.ns && extended.np <= base.np) return 1.0;
  const Eigen::MatrixXd q = Basis(PooledColumns(base, 0, 0));
  const Eigen::MatrixXd x = PooledColumns(extended, base.ns, base.np);
  double share = 0;
  int used = 0;
  for (int j = 0; j < x.cols(); ++j) {
    const double norm2 = x.col(j).squaredNorm();
    if (!(norm2 > 0)) continue;
    share += (q.transpose() * x.col(j)).squaredNorm() / norm2;
    ++used;
  }
  return used ? share / used : 1.0;
}

double NestedShare(const Design& container, const Design& extended, int first_stat, int first_cycle) {
  if (extended.ns <= first_stat && extended.np <= first_cycle) return 1.0;
  Design common = extended;  // the shared base: the first columns of `extended`
  for (size_t i = 0; i < common.stat.size(); ++i) {
    common.stat[i] = Mat3X(extended.stat[i].leftCols(first_stat));
    common.cycle[i] = Mat3X(extended.cycle[i].leftCols(first_cycle));
  }
  common.ns = first_stat, common.np = first_cycle;
  const Eigen::MatrixXd qb = Basis(PooledColumns(common, 0, 0));
  const Eigen::MatrixXd qc = Basis(PooledColumns(container, 0, 0));
  const Eigen::MatrixXd x = PooledColumns(extended, first_stat, first_cycle);
  double share = 0;
  int used = 0;
  for (int j = 0; j < x.cols(); ++j) {
    // The part of the column the common base does not explain, and how much of it the container holds.
    const Eigen::VectorXd v = x.col(j) - qb * (qb.transpose() * x.col(j));
    const double norm2 = v.squaredNorm();
    if (!(norm2 > 1e-6 * x.col(j).squaredNorm())) continue;
    share += (qc.transpose() * v).squaredNorm() / norm2;
    ++used;
  }
  return used ? share / used : 1.0;
}

Eigen::VectorXd Signature(const std::vector<Row>& rows, const Design& base, const Fit& base_fit, const Design& d,
                          const Fit& f) {
  Eigen::VectorXd v(3 * rows.size());
  for (size_t i = 0; i < rows.size(); ++i)
    v.segment<3>(3 * i) = FitResidual(rows, base, base_fit, static_cast<int>(i)) -
                          FitResidual(rows, d, f, static_cast<int>(i));
  return v;
}

double HeldoutDifferenceZ(const RowSet& rs, const std::vector<Eigen::Vector3d>& a,
                          const std::vector<Eigen::Vector3d>& b) {
  std::map<int, double> by_pose;
  for (size_t i = 0; i < rs.rows.size(); ++i) by_pose[rs.rows[i].pose] += a[i].squaredNorm() - b[i].squaredNorm();
  const int g = static_cast<int>(by_pose.size());
  if (g < 3) return 0.0;
  double sum = 0;
  for (const auto& [pose, v] : by_pose) sum += v;
  const double mean = sum / g;
  double ss = 0;
  for (const auto& [pose, v] : by_pose) ss += (v - mean) * (v - mean);
  const double se = std::sqrt(ss * g / (g - 1.0));
  return se > 0 ? sum / se : 0.0;
}

std::string SeparatingData(const RowSet& rs, const Eigen::VectorXd& difference, const std::vector<std::string>& effects) {
  // The joint along which the two candidates' predictions part most: R² of |d|² against a
  // quadratic in q_j; then where in that joint's range they differ most.
  const int n = static_cast<int>(rs.rows.size());
  Eigen::VectorXd d2(n);
  for (int i = 0; i < n; ++i) d2[i] = difference.segment<3>(3 * i).squaredNorm();
  int best_j = 0;
  double best_r2 = -1;
  for (int j = 0; j < 6; ++j) {
    Eigen::MatrixXd a(n, 3);
    for (int i = 0; i < n; ++i) a(i, 0) = 1, a(i, 1) = rs.rows[i].q[j], a(i, 2) = rs.rows[i].q[j] * rs.rows[i].q[j];
    const Eigen::VectorXd c = a.colPivHouseholderQr().solve(d2);
    const double tot = (d2.array() - d2.mean()).square().sum();
    const double r2 = tot > 0 ? 1.0 - (d2 - a * c).squaredNorm() / tot : 0.0;
    if (r2 > best_r2) best_r2 = r2, best_j = j;
  }
  double lo = INFINITY, hi = -INFINITY, at = 0, top = -1;
  for (int i = 0; i < n; ++i) {
    const double q = rs.rows[i].q[best_j] * 180.0 / 3.14159265358979323846;
    lo = std::min(lo, q), hi = std::max(hi, q);
    if (d2[i] > top) top = d2[i], at = q;
  }
  std::ostringstream out;
  out.precision(3);
  out << "more poses over a wider range of q" << best_j + 1 << " (now " << lo << " .. " << hi
      << " deg; the two predictions differ most near q" << best_j + 1 << " = " << at << " deg)";
  auto has = [&](const std::string& prefix) {
    for (const std::string& e : effects)
      if (e.rfind(prefix, 0) == 0) return true;
    return false;
  };
  if (has("thermal") || has("temperature") || has("sensor_frame_drift"))
    out << "; a temperature column (temp_*) to tell heat from time";
  if (has("joint_compliance")) out << "; repeats with a different payload (compliance scales with the load)";
  return out.str();
}

}  // namespace ramtk::diagnose::robot_detail
