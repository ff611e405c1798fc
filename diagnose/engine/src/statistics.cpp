#include "ramtk/diagnose/engine/statistics.h"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace ramtk::diagnose {
namespace {

double SigmaAt(const std::vector<double>& sigma, size_t i) { return sigma.size() == 1 ? sigma[0] : sigma[i]; }

void CheckSigma(const std::vector<double>& residuals, const std::vector<double>& sigma) {
  if (sigma.size() != 1 && sigma.size() != residuals.size())
    throw std::invalid_argument("sigma must hold one value or one per residual");
  for (double s : sigma)
    if (!(s > 0.0)) throw std::invalid_argument("sigma must be positive");
}

}  // namespace

std::string TestResult::Describe() const {
  std::ostringstream out;
  out.precision(4);
  out << name << ": statistic " << statistic;
  if (dof > 0) out << " (dof " << dof << ")";
  out << ", p = " << p_value;
  return out.str();
}

double ChiSquareUpperTail(double statistic, double dof) {
  if (dof <= 0) return 1.0;
  if (statistic <= 0) return 1.0;
  boost::math::chi_squared dist(dof);
  return boost::math::cdf(boost::math::complement(dist, statistic));
}

double NormalUpperTail(double z) {
  boost::math::normal dist;
  return boost::math::cdf(boost::math::complement(dist, z));
}

TestResult VarianceTest(const std::vector<double>& residuals, const std::vector<double>& sigma) {
  CheckSigma(residuals, sigma);
  TestResult t;
  t.name = "variance";
  for (size_t i = 0; i < residuals.size(); ++i) {
    const double z = residuals[i] / SigmaAt(sigma, i);
    t.statistic += z * z;
  }
  t.dof = static_cast<double>(residuals.size());
  t.p_value = ChiSquareUpperTail(t.statistic, t.dof);
  return t;
}

TestResult LjungBoxTest(const std::vector<double>& ordered_residuals, int max_lag, const std::string& name) {
  const int n = static_cast<int>(ordered_residuals.size());
  TestResult t;
  t.name = "ljung_box(" + name + ")";
  if (max_lag <= 0) max_lag = std::min(20, n / 5);
  if (n < 8 || max_lag < 1) return t;  // too short to say anything: p = 1
  const std::vector<double> acf = Autocorrelation(ordered_residuals, max_lag);
  for (int k = 1; k <= max_lag; ++k) t.statistic += acf[k] * acf[k] / (n - k);
  t.statistic *= n * (n + 2.0);
  t.dof = max_lag;
  t.p_value = ChiSquareUpperTail(t.statistic, t.dof);
  return t;
}

TestResult TrendTest(const std::vector<double>& residuals, const std::vector<double>& sigma,
                     const std::vector<double>& variable, int degree, const std::string& name) {
  CheckSigma(residuals, sigma);
  if (variable.size() != residuals.size()) throw std::invalid_argument("variable and residuals differ in length");
  TestResult t;
  t.name = "trend(" + name + ")";
  const int n = static_cast<int>(residuals.size());
  if (n <= degree + 2) return t;
  // Weighted least squares of r/σ on [1, x, x², ...] with x scaled to [−1, 1]; the explained
  // sum of squares beyond the constant is χ²(degree) under the null with known σ.
  const auto [lo, hi] = std::minmax_element(variable.begin(), variable.end());
  const double centre = 0.5 * (*lo + *hi), half = 0.5 * (*hi - *lo);
  if (!(half > 0.0)) return t;
  Eigen::MatrixXd a(n, degree + 1);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const double w = 1.0 / SigmaAt(sigma, i);
    const double x = (variable[i] - centre) / half;
    double p = 1.0;
    for (int d = 0; d <= degree; ++d, p *= x) a(i, d) = w * p;
    b(i) = w * residuals[i];
  }
  const Eigen::VectorXd full = a.colPivHouseholderQr().solve(b);
  const Eigen::VectorXd constant_only = a.col(0).colPivHouseholderQr().solve(b);
  const double ss_const = (b - a.col(0) * constant_only).squaredNorm();
  const double ss_full = (b - a * full).squaredNorm();
  t.statistic = std::max(0.0, ss_const - ss_full);
  t.dof = degree;
  t.p_value = ChiSquareUpperTail(t.statistic, t.dof);
  return t;
}

TestResult HarmonicTrendTest(const std::vector<double>& residuals, const std::vector<double>& sigma,
                             const std::vector<double>& angle_rad, int harmonics, const std::string& name) {
  CheckSigma(residuals, sigma);
  if (angle_rad.size() != residuals.size()) throw std::invalid_argument("angle and residuals differ in length");
  TestResult t;
  t.name = "trend(" + name + ")";
  const int n = static_cast<int>(residuals.size()), m = 2 * harmonics;
  if (n <= m + 2) return t;
  Eigen::MatrixXd a(n, m + 1);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const double w = 1.0 / SigmaAt(sigma, i);
    a(i, 0) = w;
    for (int k = 1; k <= harmonics; ++k) {
      a(i, 2 * k - 1) = w * std::sin(k * angle_rad[i]);
      a(i, 2 * k) = w * std::cos(k * angle_rad[i]);
    }
    b(i) = w * residuals[i];
  }
  const Eigen::VectorXd full = a.colPivHouseholderQr().solve(b);
  const Eigen::VectorXd constant_only = a.col(0).colPivHouseholderQr().solve(b);
  const double ss_const = (b - a.col(0) * constant_only).squaredNorm();
  const double ss_full = (b - a * full).squaredNorm();
  t.statistic = std::max(0.0, ss_const - ss_full);
  // Over a short range of angle the columns are nearly dependent: count the rank actually used.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-8);
  t.dof = std::max<Eigen::Index>(1, qr.rank() - 1);
  t.p_value = ChiSquareUpperTail(t.statistic, t.dof);
  return t;
}

std::vector<double> HolmCorrection(const std::vector<double>& p_values) {
  const size_t m = p_values.size();
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return p_values[a] < p_values[b]; });
  std::vector<double> corrected(m);
  double running = 0.0;
  for (size_t rank = 0; rank < m; ++rank) {
    const size_t i = order[rank];
    running = std::max(running, std::min(1.0, (m - rank) * p_values[i]));
    corrected[i] = running;
  }
  return corrected;
}

}  // namespace ramtk::diagnose
