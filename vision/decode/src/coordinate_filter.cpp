#include "ramtk/vision/decode/coordinate_filter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {
namespace {

using Basis = Eigen::Matrix<double, 6, 1>;

Basis QuadraticBasis(int dx, int dy) {
  Basis b;
  b << 1.0, dx, dy, double(dx) * dx, double(dx) * dy, double(dy) * dy;
  return b;
}

// Weights k_i of the fitted surface's value at the centre, for the window offsets whose `use` is
// true (row-major over the window); false if the fit is singular.
bool CentreWeights(int r, const std::vector<char>& use, std::vector<double>* k) {
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  const int w = 2 * r + 1;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (use[(dy + r) * w + dx + r]) {
        const Basis b = QuadraticBasis(dx, dy);
        m.noalias() += b * b.transpose();
      }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(m);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-10)) return false;
  const Basis u = ldlt.solve(Basis::Unit(0));
  k->assign(use.size(), 0.0);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (use[(dy + r) * w + dx + r]) (*k)[(dy + r) * w + dx + r] = QuadraticBasis(dx, dy).dot(u);
  return true;
}

}  // namespace

std::string CoordinateFilterOptions::Validate() const {
  if (radius_px < 0 || radius_px > 6) return "radius_px: expected 0..6";
  if (!(min_valid_fraction > 0 && min_valid_fraction <= 1)) return "min_valid_fraction: expected a fraction in (0, 1]";
  if (!(max_departure_sigma > 0)) return "max_departure_sigma: must be positive";
  return "";
}

CoordinateFilterSummary FilterCoordinate(const CoordinateFilterOptions& options, double ripple_px,
                                         DecodedCamera* decoded) {
  ThrowIfInvalid(options.Validate(), "CoordinateFilterOptions");
  CoordinateFilterSummary sum;
  sum.radius_px = options.radius_px;
  const int r = options.radius_px;
  if (r == 0 || decoded->coordinate.empty()) return sum;
  const cv::Mat coord = decoded->coordinate.clone();  // the filter reads the unfiltered values
  const cv::Mat sigma = decoded->sigma_coordinate.clone();
  const int w = 2 * r + 1, n = w * w;
  const int min_valid = std::max(6, static_cast<int>(std::ceil(options.min_valid_fraction * n)));
  const double ripple2 = ripple_px * ripple_px;
  std::vector<double> full_k;
  CentreWeights(r, std::vector<char>(n, 1), &full_k);
  const int rows = coord.rows, cols = coord.cols;
  std::vector<long> filtered(rows, 0), sparse(rows, 0), departed(rows, 0);
  std::vector<float> ratio(static_cast<std::size_t>(rows) * cols, std::numeric_limits<float>::quiet_NaN());
  const bool with_phase = !decoded->sigma_phase.empty();
  const double to_rad = decoded->summary.period_px > 0 ? 2 * CV_PI / decoded->summary.period_px : 0.0;
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 8), [&](const tbb::blocked_range<int>& range) {
    std::vector<char> use(n);
    std::vector<double> k;
    for (int y = range.begin(); y < range.end(); ++y) {
      float* out_c = decoded->coordinate.ptr<float>(y);
      float* out_s = decoded->sigma_coordinate.ptr<float>(y);
      for (int x = 0; x < cols; ++x) {
        const float c0 = coord.at<float>(y, x);
        if (!std::isfinite(c0)) continue;
        int valid = 0;
        for (int dy = -r; dy <= r; ++dy) {
          const int yy = y + dy;
          for (int dx = -r; dx <= r; ++dx) {
            const int xx = x + dx;
            const bool ok = yy >= 0 && yy < rows && xx >= 0 && xx < cols && std::isfinite(coord.at<float>(yy, xx)) &&
                            std::isfinite(sigma.at<float>(yy, xx));
            use[(dy + r) * w + dx + r] = ok;
            valid += ok;
          }
        }
        if (valid < min_valid) {
          ++sparse[y];
          continue;
        }
        const std::vector<double>* weights = &full_k;
        if (valid < n) {
          if (!CentreWeights(r, use, &k)) {
            ++sparse[y];
            continue;
          }
          weights = &k;
        }
        // Offsets from the centre's value keep the sums well conditioned (coordinates ~1e3 px).
        double f = 0, var_f = 0;
        const double own_random2 = std::max(0.0, double(sigma.at<float>(y, x)) * sigma.at<float>(y, x) - ripple2);
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int i = (dy + r) * w + dx + r;
            if (!use[i]) continue;
            const double ki = (*weights)[i];
            const double s = sigma.at<float>(y + dy, x + dx);
            f += ki * (coord.at<float>(y + dy, x + dx) - c0);
            var_f += ki * ki * std::max(0.0, s * s - ripple2);
          }
        const double cov_own = (*weights)[r * w + r] * own_random2;
        // filtered − own = f (offsets): its random part's variance, plus at most the ripple's (all of
        // it when the filter removes the ripple at this pixel, none when the ripple is smooth).
        const double var_departure = std::max(0.0, var_f - 2 * cov_own + own_random2) + ripple2;
        if (std::abs(f) > options.max_departure_sigma * std::sqrt(var_departure)) {
          ++departed[y];
          continue;
        }
        const double s_new = std::sqrt(var_f + ripple2);
        ratio[static_cast<std::size_t>(y) * cols + x] = static_cast<float>(s_new / sigma.at<float>(y, x));
        out_c[x] = static_cast<float>(c0 + f);
        out_s[x] = static_cast<float>(s_new);
        if (with_phase) decoded->sigma_phase.at<float>(y, x) = static_cast<float>(s_new * to_rad);
        ++filtered[y];
      }
    }
  });
  for (int y = 0; y < rows; ++y) {
    sum.filtered += filtered[y];
    sum.kept_sparse += sparse[y];
    sum.kept_departure += departed[y];
  }
  ratio.erase(std::remove_if(ratio.begin(), ratio.end(), [](float v) { return !std::isfinite(v); }), ratio.end());
  if (!ratio.empty()) {
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    sum.median_sigma_ratio = ratio[ratio.size() / 2];
  }
  return sum;
}

}  // namespace ramtk::vision
