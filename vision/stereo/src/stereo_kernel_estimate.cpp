// The sampling kernel's variance from the matched pixels' modulation (stereo_kernel_estimate.h).
#include "ramtk/vision/stereo/detail/stereo_kernel_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <vector>

namespace ramtk::vision::detail {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kMaxGradient2 = 4.0;      // |g|² above this (rad/px)²: differences across a jump
constexpr double kMinModulationShare = 0.25;  // of the pairs' median B
constexpr double kMaxModulationRatio = 1.5;   // B_left / B_right (either way): not one surface point
constexpr int kBands = 16;                    // jackknife bands of right-image rows

// Pixels whose 7 × 7 neighbourhood holds only valid pixels (a finite coordinate inside the mask):
// their differences (3 px wide at most) stay off every edge.
cv::Mat Interior(const DecodedCamera& d) {
  cv::Mat valid(d.coordinate.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < valid.rows; ++y) {
    const float* c = d.coordinate.ptr<float>(y);
    const uchar* m = d.mask.empty() ? nullptr : d.mask.ptr<uchar>(y);
    uchar* v = valid.ptr<uchar>(y);
    for (int x = 0; x < valid.cols; ++x) v[x] = (std::isfinite(c[x]) && (!m || m[x])) ? 255 : 0;
  }
  cv::Mat interior;
  cv::erode(valid, interior, cv::Mat::ones(7, 7, CV_8U), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  return interior;
}

// |g|² at pixel (x, y) of a camera from the coordinate's central differences, less their noise's
// expectation (from sigma_coordinate), and the variance that noise leaves in it, (rad/px)².
struct Gradient2 {
  double g2 = 0, var = 0;
};

inline Gradient2 GradientSquared(const DecodedCamera& d, int x, int y, double scale2) {
  auto c = [&](int u, int v) { return static_cast<double>(d.coordinate.ptr<float>(v)[u]); };
  auto s2 = [&](int u, int v) {
    const double s = d.sigma_coordinate.empty() ? 0.0 : d.sigma_coordinate.ptr<float>(v)[u];
    return std::isfinite(s) ? s * s : 0.0;
  };
  const double gu = 0.5 * (c(x + 1, y) - c(x - 1, y)), gv = 0.5 * (c(x, y + 1) - c(x, y - 1));
  const double vu = 0.25 * (s2(x + 1, y) + s2(x - 1, y)), vv = 0.25 * (s2(x, y + 1) + s2(x, y - 1));
  Gradient2 g;
  g.g2 = scale2 * (gu * gu + gv * gv - vu - vv);
  g.var = scale2 * scale2 * (4 * (gu * gu * vu + gv * gv * vv) + 2 * (vu * vu + vv * vv));
  return g;
}

// ΔB / B at pixel (x, y) (the modulation's Laplacian over B, per px²) from the samples 2 and 3 px
// away along each axis ((S3 − S2) / 5 per axis, S_d the sum of the two samples d px away): the
// samples a bilinear read next to (x, y) uses are not in it. Its noise variance (the decoded
// modulation's relative noise σ_B / B = σ_φ, the coordinate's σ in phase) in *var.
inline double LaplacianOverB(const DecodedCamera& d, int x, int y, double scale2, double* var) {
  auto b = [&](int u, int v) { return static_cast<double>(d.modulation.ptr<float>(v)[u]); };
  const double lap =
      (b(x + 3, y) + b(x - 3, y) + b(x, y + 3) + b(x, y - 3) - b(x + 2, y) - b(x - 2, y) - b(x, y + 2) - b(x, y - 2)) /
      5.0;
  const double s = d.sigma_coordinate.empty() ? 0.0 : d.sigma_coordinate.ptr<float>(y)[x];
  *var = (std::isfinite(s) ? scale2 * s * s : 0.0) * 8.0 / 25.0;
  return lap / b(x, y);
}

struct Pair {
  double b_left, b_right;          // modulation, DN
  double log_bias_left;            // the interpolated log B_left's noise bias
  Gradient2 g2_left, g2_right;     // |g|², (rad/px)²
  double lap_left, lap_right, lap_var_left, lap_var_right;  // ΔB / B and its noise variance
};

// The pair of right pixel (x, y) and its left match (u, v): the left modulation interpolated, its
// gradient at the nearest pixel; false where a neighbour is missing.
bool MakePair(const DecodedCamera& left, const DecodedCamera& right, const cv::Mat& left_interior, int x, int y,
              double u, double v, double scale2, Pair* p) {
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= left.coordinate.cols || v0 + 1 >= left.coordinate.rows) return false;
  const double fu = u - u0, fv = v - v0;
  double b = 0, w2 = 0, s2 = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      if (!left_interior.ptr<uchar>(v0 + j)[u0 + i]) return false;
      const double w = (i ? fu : 1 - fu) * (j ? fv : 1 - fv);
      b += w * left.modulation.ptr<float>(v0 + j)[u0 + i];
      w2 += w * w;
      const double s = left.sigma_coordinate.empty() ? 0.0 : left.sigma_coordinate.ptr<float>(v0 + j)[u0 + i];
      if (std::isfinite(s)) s2 += w * scale2 * s * s;
    }
  p->b_left = b;
  // A pixel's log B̂ is unbiased at second order (the Rician bias of B̂ cancels the logarithm's),
  // an interpolated one is not: E[log Σ w_i·B̂_i] = log B + ½·(σ_B/B)²·(1 − Σ w_i²).
  p->log_bias_left = 0.5 * s2 * (1 - w2);
  p->g2_left = GradientSquared(left, u0 + (fu >= 0.5), v0 + (fv >= 0.5), scale2);
  p->b_right = right.modulation.ptr<float>(y)[x];
  p->g2_right = GradientSquared(right, x, y, scale2);
  p->lap_left = LaplacianOverB(left, u0 + (fu >= 0.5), v0 + (fv >= 0.5), scale2, &p->lap_var_left);
  p->lap_right = LaplacianOverB(right, x, y, scale2, &p->lap_var_right);
  return p->g2_left.g2 <= kMaxGradient2 && p->g2_right.g2 <= kMaxGradient2 && p->b_left > 0 && p->b_right > 0;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Huber-robust weighted line y = a + k·x over the points outside [skip_begin, skip_end); the slope
// k, with x's noise variance vx taken out of its spread (the errors-in-variables correction).
// The weighted sums of one least-squares slope with the regressor's noise removed
// (errors-in-variables: Σw·x² less Σw·var(x)).
struct Sums {
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, sv = 0;
  void Add(double w, double x, double y, double vx) {
    sw += w, sx += w * x, sy += w * y, sxx += w * x * x, sxy += w * x * y, sv += w * vx;
  }
  Sums Minus(const Sums& o) const {
    return {sw - o.sw, sx - o.sx, sy - o.sy, sxx - o.sxx, sxy - o.sxy, sv - o.sv};
  }
  Sums& operator+=(const Sums& o) {
    sw += o.sw, sx += o.sx, sy += o.sy, sxx += o.sxx, sxy += o.sxy, sv += o.sv;
    return *this;
  }
  // Slope and intercept; false if the sums hold no slope.
  bool Solve(double* k, double* a) const {
    const double det = sw * (sxx - sv) - sx * sx;
    if (!(det > 0)) return false;
    *k = (sw * sxy - sx * sy) / det;
    *a = (sy - *k * sx) / sw;
    return true;
  }
};

// Huber-weighted slope of y on x (weights w, regressor noise variances vx) by iteratively
// reweighted least squares. The Huber threshold is fixed from the unweighted fit's residuals
// (1.345 robust σ, their median absolute value), and the iterations stop when the slope moves by
// less than 1e-6 px² + 1e-4 of itself. The leave-one-band-out slopes of the jackknife are the
// final weights' sums less each band's (the final Huber weights held: a one-step jackknife), in
// *jack (kBands values; bands of equal pair counts, in the pairs' row order). NaN: no slope.
double RobustSlope(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& w,
                   const std::vector<double>& vx, std::vector<double>* jack) {
  const std::size_t n = x.size();
  jack->assign(kBands, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> h(n, 1.0);
  Sums all;
  for (std::size_t i = 0; i < n; ++i) all.Add(w[i], x[i], y[i], vx[i]);
  double k = 0, a = 0;
  if (!all.Solve(&k, &a)) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> z(n);
  for (std::size_t i = 0; i < n; ++i) z[i] = std::abs(y[i] - a - k * x[i]) * std::sqrt(w[i]);
  const double c = 1.345 * 1.4826 * Median(z);
  for (int iter = 0; iter < 10 && c > 0; ++iter) {
    Sums s;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = std::abs(y[i] - a - k * x[i]) * std::sqrt(w[i]);
      h[i] = r > c ? c / r : 1.0;
      s.Add(w[i] * h[i], x[i], y[i], vx[i]);
    }
    const double k_before = k;
    if (!s.Solve(&k, &a)) return std::numeric_limits<double>::quiet_NaN();
    if (std::abs(k - k_before) <= 1e-6 + 1e-4 * std::abs(k)) break;
  }
  Sums total;
  std::vector<Sums> band(kBands);
  for (std::size_t i = 0; i < n; ++i) band[i * kBands / n].Add(w[i] * h[i], x[i], y[i], vx[i]);
  for (const Sums& b : band) total += b;
  for (int b = 0; b < kBands; ++b) {
    double kb = 0, ab = 0;
    if (total.Minus(band[b]).Solve(&kb, &ab)) (*jack)[b] = kb;
  }
  return k;
}

}  // namespace

KernelVarianceEstimate EstimateKernelVariance(const DecodedCamera& left, const DecodedCamera& right,
                                              const cv::Mat& back_u, const cv::Mat& back_v, double period,
                                              std::optional<double> left_known, std::optional<double> right_known,
                                              long min_pixels) {
  KernelVarianceEstimate e;
  if (left_known && right_known) {
    e.status = "stated";
    return e;
  }
  if (back_u.empty() || back_v.empty()) {
    e.status = "no back pass";
    return e;
  }
  const cv::Mat left_interior = Interior(left), right_interior = Interior(right);
  const double scale2 = (kTwoPi / period) * (kTwoPi / period);
  // Each row's pairs in parallel, reduced to what the regression reads, then joined in row order
  // (the jackknife's bands are of rows).
  struct Row {
    std::vector<float> b_left, b_right, x, y, vx;
  };
  std::vector<Row> rows(right.coordinate.rows);
  tbb::parallel_for(tbb::blocked_range<int>(0, right.coordinate.rows, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) {
      const uchar* in = right_interior.ptr<uchar>(y);
      const float* bu = back_u.ptr<float>(y);
      const float* bv = back_v.ptr<float>(y);
      Row& row = rows[y];
      for (int x = 0; x < right.coordinate.cols; ++x) {
        Pair p;
        if (!(in[x] && std::isfinite(bu[x]) && std::isfinite(bv[x]) &&
              MakePair(left, right, left_interior, x, y, bu[x], bv[x], scale2, &p)))
          continue;
        // q = ΔB/B − |g|² per camera: log B_measured = log B + ½·k·q.
        const double ql = p.lap_left - p.g2_left.g2, qr = p.lap_right - p.g2_right.g2;
        const double vl = p.g2_left.var + p.lap_var_left, vr = p.g2_right.var + p.lap_var_right;
        double yv = std::log(p.b_left / p.b_right) - p.log_bias_left, xv = 0.5 * (ql - qr), vx = 0.25 * (vl + vr);
        if (left_known) yv -= 0.5 * *left_known * ql, xv = -0.5 * qr, vx = 0.25 * vr;
        if (right_known) yv += 0.5 * *right_known * qr, xv = 0.5 * ql, vx = 0.25 * vl;
        row.b_left.push_back(static_cast<float>(p.b_left));
        row.b_right.push_back(static_cast<float>(p.b_right));
        row.x.push_back(static_cast<float>(xv));
        row.y.push_back(static_cast<float>(yv));
        row.vx.push_back(static_cast<float>(vx));
      }
    }
  });
  // The modulation floor: a share of the pairs' median right B (from every 8th pair).
  std::vector<double> b;
  for (const Row& row : rows)
    for (std::size_t i = 0; i < row.b_right.size(); i += 8) b.push_back(row.b_right[i]);
  const double floor_b = kMinModulationShare * Median(b);
  std::vector<double> xs, ys, ws, vs;
  for (const Row& row : rows)
    for (std::size_t i = 0; i < row.x.size(); ++i) {
      const double bl = row.b_left[i], br = row.b_right[i], ratio = bl / br;
      if (bl < floor_b || br < floor_b || ratio > kMaxModulationRatio || ratio < 1 / kMaxModulationRatio) continue;
      xs.push_back(row.x[i]);
      vs.push_back(row.vx[i]);
      ys.push_back(row.y[i]);
      ws.push_back(1.0 / (1.0 / (bl * bl) + 1.0 / (br * br)));
    }
  e.pixels = static_cast<long>(xs.size());
  if (e.pixels < std::max<long>(min_pixels, 2 * kBands)) {
    e.status = "too few pixels";
    return e;
  }
  e.status = "estimated";
  const std::size_t n = xs.size();
  std::vector<double> jack;
  e.variance_px2 = RobustSlope(xs, ys, ws, vs, &jack);
  // The regressor's robust spread (median absolute deviation) over its noise's RMS.
  double mean_vx = 0;
  for (double v : vs) mean_vx += v / static_cast<double>(n);
  // (from every 4th pair: a gate's figure, not the estimate)
  std::vector<double> sample;
  for (std::size_t i = 0; i < n; i += 4) sample.push_back(xs[i]);
  const double mid = Median(sample);
  std::vector<double> dev;
  for (double v : sample) dev.push_back(std::abs(v - mid));
  e.leverage = mean_vx > 0 ? Median(dev) / std::sqrt(mean_vx) : std::numeric_limits<double>::infinity();
  double mean = 0;
  for (double v : jack) mean += v / kBands;
  double ss = 0;
  for (double v : jack) ss += (v - mean) * (v - mean);
  e.sigma_px2 = std::sqrt((kBands - 1.0) / kBands * ss);
  return e;
}

}  // namespace ramtk::vision::detail
