// Noise-level function of a fringe set, estimated from the data: the variance of the residual
// against the model intensity, Poisson–Gaussian a + b·I (read noise + photon shot noise, b = DN per
// photo-electron) and, to test for noise beyond that, a + b·I + c·I². Measured from differences
// of the residual between neighbouring analysed pixels along the fringes (same phase, so model
// errors cancel and only noise remains).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "fringe_internal.h"

namespace ramtk::diagnose::fringe {
namespace {

// Quantisation of an integer-valued sensor: the smallest variance a sample can have (DN²).
constexpr double kMinVariance = 1.0 / 12.0;
constexpr int kBins = 24;

struct Bin {
  double level = 0, variance = 0;
  long count = 0;
};

// Weighted least squares of bin variances on [1, I, (I²)] with weights n/(2·v̂²) (the variance of a
// mean of n scaled χ²₁ samples), iterated so the weights use the fitted variance. Returns the
// coefficients and their covariance, scaled by the reduced χ² when it exceeds 1 (neighbouring
// pixels are not quite independent). `chi2` receives the lack-of-fit statistic.
void FitBins(const std::vector<Bin>& bins, int terms, Eigen::VectorXd* coef, Eigen::MatrixXd* cov, double* chi2) {
  const int m = static_cast<int>(bins.size());
  Eigen::MatrixXd a(m, terms);
  Eigen::VectorXd y(m), v(m);
  for (int i = 0; i < m; ++i) {
    for (int t = 0; t < terms; ++t) a(i, t) = std::pow(bins[i].level, t);
    y(i) = bins[i].variance;
    v(i) = std::max(bins[i].variance, kMinVariance);
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(terms);
  Eigen::MatrixXd normal;
  for (int iter = 0; iter < 4; ++iter) {
    Eigen::VectorXd w(m);
    for (int i = 0; i < m; ++i) w(i) = bins[i].count / (2.0 * v(i) * v(i));
    normal = a.transpose() * w.asDiagonal() * a;
    x = normal.ldlt().solve(a.transpose() * w.asDiagonal() * y);
    v = (a * x).cwiseMax(kMinVariance);
  }
  double c2 = 0;
  for (int i = 0; i < m; ++i) c2 += bins[i].count / (2.0 * v(i) * v(i)) * std::pow(y(i) - v(i), 2);
  const double dof = std::max(1, m - terms);
  *coef = x;
  *cov = normal.inverse() * std::max(1.0, c2 / dof);
  *chi2 = c2;
}

}  // namespace

double NoiseLevel::Variance(double level) const {
  const double l = std::max(level, 0.0);
  return std::max(a + b * l + c * l * l, kMinVariance);
}

NoiseLevel EstimateNoiseLevel(const FringeFit& fit) {
  struct Pair {
    float level, d2;
  };
  std::vector<Pair> pairs;
  const size_t nf = static_cast<size_t>(fit.frames);
  for (size_t i = 0; i < fit.pixels.size(); ++i) {
    const PixelFit& p = fit.pixels[i];
    const int nx = fit.vertical ? p.x : p.x + 1, ny = fit.vertical ? p.y + 1 : p.y;
    if (nx >= fit.width || ny >= fit.height) continue;
    const int j = fit.index.at<int>(ny, nx);
    if (j < 0) continue;
    const PixelFit& q = fit.pixels[j];
    // Phase-shift frames only: there the N-step model is exact up to the projector's response,
    // whose error neighbours along the fringe share; the Gray-code model (edge profile, stripe
    // contrast) carries small errors that scale with B and differ between neighbours.
    for (int f : fit.phase_frame) {
      const float ri = fit.residual[i * nf + f], rj = fit.residual[static_cast<size_t>(j) * nf + f];
      if (!std::isfinite(ri) || !std::isfinite(rj)) continue;
      // Model intensity = measured − residual (not the measured value: its own noise would leak
      // into the level and bias the weights).
      const double level =
          0.5 * (fit.images[f].at<float>(p.y, p.x) - ri + fit.images[f].at<float>(q.y, q.x) - rj);
      pairs.push_back({static_cast<float>(level), (ri - rj) * (ri - rj)});
    }
  }
  NoiseLevel out;
  out.pairs = static_cast<long>(pairs.size());
  if (pairs.size() < 100) {
    // Too few pairs for a level function: one variance for all samples.
    double s = 0;
    for (const Pair& q : pairs) s += q.d2;
    out.a = pairs.empty() ? kMinVariance : std::max(s / pairs.size() / 2.0 / ((fit.steps - 3.0) / fit.steps), kMinVariance);
    return out;
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.level < y.level; });
  // Quantile bins of the level; in each, the mean of d²/2 after leaving out differences beyond 6
  // robust sigmas of that bin (outliers judged at the bin's own noise level).
  std::vector<Bin> bins;
  const size_t per = pairs.size() / kBins;
  for (int k = 0; k < kBins; ++k) {
    const size_t lo = k * per, hi = k + 1 == kBins ? pairs.size() : lo + per;
    std::vector<float> d2;
    for (size_t i = lo; i < hi; ++i) d2.push_back(pairs[i].d2);
    std::nth_element(d2.begin(), d2.begin() + d2.size() / 2, d2.end());
    const double limit = 36.0 * d2[d2.size() / 2] / (0.6745 * 0.6745);
    Bin b;
    double level = 0, sum = 0;
    for (size_t i = lo; i < hi; ++i)
      if (pairs[i].d2 <= limit) sum += pairs[i].d2, level += pairs[i].level, ++b.count;
    if (b.count < 10) continue;
    b.level = level / b.count;
    b.variance = sum / b.count / 2.0;
    bins.push_back(b);
  }
  Eigen::VectorXd lin, quad;
  Eigen::MatrixXd lin_cov, quad_cov;
  double lin_chi2 = 0, quad_chi2 = 0;
  FitBins(bins, 2, &lin, &lin_cov, &lin_chi2);
  FitBins(bins, 3, &quad, &quad_cov, &quad_chi2);
  out.a = lin(0), out.b = lin(1);
  out.sigma_a = std::sqrt(lin_cov(0, 0)), out.sigma_b = std::sqrt(lin_cov(1, 1));
  out.quadratic_c = quad(2);
  out.sigma_c = std::sqrt(quad_cov(2, 2));
  out.linear_chi2 = lin_chi2;
  out.bins = static_cast<int>(bins.size());
  double top = 0;
  for (const Bin& b : bins) top = std::max(top, b.level);
  out.top_level = top;
  // Beyond Poisson–Gaussian only when the I² term is both significant and material: at the
  // brightest level it carries at least kQuadraticShare of the variance.
  const double at_top = quad(0) + quad(1) * top + quad(2) * top * top;
  out.quadratic_share = at_top > 0 ? quad(2) * top * top / at_top : 0.0;
  out.super_poisson = out.quadratic_c > kQuadraticZ * out.sigma_c && out.quadratic_share >= kQuadraticShare;
  if (out.super_poisson) {
    out.a = quad(0), out.b = quad(1), out.c = quad(2);
    out.sigma_a = std::sqrt(quad_cov(0, 0)), out.sigma_b = std::sqrt(quad_cov(1, 1));
  }
  // The N-step fit leaves (N − 3)/N of a phase sample's variance in its residual: the sensor's own
  // variance is the residual's over that factor.
  const double keep = (fit.steps - 3.0) / fit.steps;
  for (double* v : {&out.a, &out.b, &out.c, &out.sigma_a, &out.sigma_b, &out.quadratic_c, &out.sigma_c}) *v /= keep;
  return out;
}

}  // namespace ramtk::diagnose::fringe

namespace ramtk::diagnose::fringe {
namespace {

// A pixel's fitted dark end may lie this many σ(0) below 0 and still count as noise clamped at black.
constexpr double kBelowBlack = 2.0;

double Phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double PhiDensity(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * 3.14159265358979323846); }

// Expectation of a clamped normal and its derivative in mu (σ held fixed).
double ClampedMean(double mu, double s, double top, double* slope) {
  const double alpha = -mu / s;
  const double pa = Phi(alpha);
  if (!std::isfinite(top)) {  // clamped at 0 only
    if (slope) *slope = 1.0 - pa;
    return mu * (1.0 - pa) + s * PhiDensity(alpha);
  }
  const double beta = (top - mu) / s, pb = Phi(beta);
  if (slope) *slope = pb - pa;
  return top * (1.0 - pb) + mu * (pb - pa) + s * (PhiDensity(alpha) - PhiDensity(beta));
}

}  // namespace

double ResidualVarianceFactor(const FringeFit& fit, int f) {
  const double n = fit.steps;
  for (int k : fit.phase_frame)
    if (k == f) return 1.0 - 3.0 / n;
  return 1.0 + 3.0 / n;
}

double SensorExpectation(const FringeFit& fit, const PixelFit& p, double mu) {
  if (!fit.censored || !p.censored) return mu;
  const double s = std::sqrt(fit.noise.Variance(mu));
  if (mu > 6 * s) return mu;
  return ClampedMean(mu, s, INFINITY, nullptr);
}

void ModelSensorRange(const NoiseLevel& noise, FringeFit* fit) {
  fit->noise = noise;
  fit->censored = true;
  const int n = fit->steps, nf = fit->frames;
  std::vector<double> cos_d(n), sin_d(n);
  for (int k = 0; k < n; ++k) cos_d[k] = std::cos(StepShift(k, n)), sin_d[k] = std::sin(StepShift(k, n));
  std::vector<char> refitted(fit->pixels.size(), 0);
  const double sigma0 = std::sqrt(noise.Variance(0.0));
  cv::parallel_for_(cv::Range(0, static_cast<int>(fit->pixels.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      PixelFit& p = fit->pixels[i];
      const double lo = p.a - p.b;
      if (lo > 4 * std::sqrt(noise.Variance(lo)) || lo < -kBelowBlack * sigma0) continue;
      // Gauss–Newton on x = (A, B cos φ, B sin φ): I_k = A + x1 cos δ_k − x2 sin δ_k, E_k = g(I_k).
      Eigen::Vector3d x(p.a, p.b * std::cos(p.phi), p.b * std::sin(p.phi));
      for (int iter = 0; iter < 4; ++iter) {
        Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
        Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
        for (int k = 0; k < n; ++k) {
          const Eigen::Vector3d row(1.0, cos_d[k], -sin_d[k]);
          const double mu = row.dot(x);
          double slope = 1.0;
          const double e = ClampedMean(mu, std::sqrt(noise.Variance(mu)), INFINITY, &slope);
          const double r = fit->images[fit->phase_frame[k]].at<float>(p.y, p.x) - e;
          jtj += slope * slope * row * row.transpose();
          jtr += slope * r * row;
        }
        jtj.diagonal().array() += 1e-9;
        x += jtj.ldlt().solve(jtr);
      }
      // Light is never negative: a dark end far below 0 is not noise clamped at black but a
      // sinusoid that does not fit (a projector gamma flattens the dark end): keep the plain fit.
      if (x(0) - std::hypot(x(1), x(2)) < -kBelowBlack * sigma0) continue;
      p.a = x(0), p.b = std::hypot(x(1), x(2)), p.phi = std::atan2(x(2), x(1));
      p.censored = true;
      refitted[i] = 1;
    }
  });
  fit->range_refitted = std::count(refitted.begin(), refitted.end(), 1);
  cv::parallel_for_(cv::Range(0, static_cast<int>(fit->pixels.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const PixelFit& p = fit->pixels[i];
      for (int f = 0; f < nf; ++f) {
        float& r = fit->residual[static_cast<size_t>(i) * nf + f];
        if (std::isfinite(r)) r = static_cast<float>(fit->images[f].at<float>(p.y, p.x) - IdealIntensity(*fit, p, f));
      }
    }
  });
}

}  // namespace ramtk::diagnose::fringe
