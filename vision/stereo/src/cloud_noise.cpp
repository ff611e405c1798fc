// Local surface-fit noise of an organised cloud (cloud_noise.h).
#include "ramtk/vision/stereo/cloud_noise.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

LocalFitNoise MeasureLocalFitNoise(const PointCloud& cloud, cv::Size size, int window) {
  if (window < 4) throw InputError({"", 0, "window"}, "must be >= 4 pixels");
  if (cloud.left_pixels.size() != cloud.size() || cloud.sigma_mm.size() != cloud.size())
    throw InputError({"", 0, "cloud"}, "needs left_pixels and sigma for every point");
  cv::Mat index(size, CV_32S, cv::Scalar(-1));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const int x = static_cast<int>(cloud.left_pixels[i].x()), y = static_cast<int>(cloud.left_pixels[i].y());
    if (x >= 0 && y >= 0 && x < size.width && y < size.height) index.at<int>(y, x) = static_cast<int>(i);
  }
  const int n = window * window;
  Eigen::MatrixXd A(n, 6);
  for (int k = 0; k < n; ++k) {
    const double du = k % window - (window - 1) / 2.0, dv = k / window - (window - 1) / 2.0;
    A.row(k) << 1, du, dv, du * du, du * dv, dv * dv;
  }
  const Eigen::MatrixXd pinv = (A.transpose() * A).ldlt().solve(A.transpose());
  std::vector<double> observed, predicted, ratio;
  Eigen::VectorXd z(n);
  for (int y0 = 0; y0 + window <= size.height; y0 += window)
    for (int x0 = 0; x0 + window <= size.width; x0 += window) {
      bool full = true;
      double pred_sq = 0;
      for (int k = 0; k < n && full; ++k) {
        const int i = index.at<int>(y0 + k / window, x0 + k % window);
        if (i < 0) {
          full = false;
          break;
        }
        const Eigen::Vector3f& p = cloud.points_in_left[static_cast<std::size_t>(i)];
        z[k] = p.z();
        const double dz = p.z() / p.norm();  // z component of the unit ray
        pred_sq += std::pow(cloud.sigma_mm[static_cast<std::size_t>(i)] * dz, 2);
      }
      if (!full) continue;
      const Eigen::VectorXd r = z - A * (pinv * z);
      const double rms = std::sqrt(r.squaredNorm() / (n - 6));
      const double pred = std::sqrt(pred_sq / n);
      observed.push_back(rms);
      predicted.push_back(pred);
      ratio.push_back(rms / pred);
    }
  LocalFitNoise out;
  out.patches = static_cast<long>(observed.size());
  out.median_rms_mm = Median(observed);
  out.median_predicted_mm = Median(predicted);
  out.ratio = Median(ratio);
  return out;
}

}  // namespace ramtk::vision

namespace ramtk::vision {

NeighbourCorrelation EstimateNeighbourCorrelation(const std::vector<Eigen::Vector2f>& pixels,
                                                  const std::vector<double>& normalised_residuals, cv::Size image_size,
                                                  int max_lag) {
  if (pixels.size() != normalised_residuals.size())
    throw InputError({"", 0, "normalised_residuals"}, "has " + std::to_string(normalised_residuals.size()) +
                                                          " values for " + std::to_string(pixels.size()) + " pixels");
  if (max_lag < 1) throw InputError({"", 0, "max_lag"}, "must be >= 1");
  NeighbourCorrelation out;
  if (pixels.empty()) return out;
  // Residuals on the pixel grid (NaN = no point), centred on their mean. The grid spans only the
  // points' bounding box: outside it every pair holds a NaN and adds nothing (a ball's points
  // cover a few percent of a frame, and the 12 lags each scanned the whole 8 Mpx of a thesis frame).
  double mean = 0;
  for (double z : normalised_residuals) mean += z / static_cast<double>(normalised_residuals.size());
  auto in_image = [&](int x, int y) { return x >= 0 && y >= 0 && x < image_size.width && y < image_size.height; };
  int x_lo = image_size.width, y_lo = image_size.height, x_hi = -1, y_hi = -1;
  for (const Eigen::Vector2f& p : pixels) {
    const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
    if (!in_image(x, y)) continue;
    x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x), y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
  }
  if (x_hi < 0) return out;
  cv::Mat grid(y_hi - y_lo + 1, x_hi - x_lo + 1, CV_64F, cv::Scalar(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const int x = static_cast<int>(std::lround(pixels[i].x())), y = static_cast<int>(std::lround(pixels[i].y()));
    if (!in_image(x, y)) continue;
    grid.at<double>(y - y_lo, x - x_lo) = normalised_residuals[i] - mean;
  }
  double variance = 0;
  long count = 0;
  for (int y = 0; y < grid.rows; ++y)
    for (int x = 0; x < grid.cols; ++x) {
      const double z = grid.at<double>(y, x);
      if (std::isfinite(z)) variance += z * z, ++count;
    }
  if (count < 2 || !(variance > 0)) return out;
  variance /= static_cast<double>(count);
  // Half of the lag window (dv > 0, or dv == 0 and du > 0); rho(-lag) = rho(lag).
  double sum_rho = 0;
  for (int dv = 0; dv <= max_lag; ++dv)
    for (int du = -max_lag; du <= max_lag; ++du) {
      if (dv == 0 && du <= 0) continue;
      double cross = 0;
      long n = 0;
      for (int y = 0; y + dv < grid.rows; ++y)
        for (int x = std::max(0, -du); x < grid.cols && x + du < grid.cols; ++x) {
          const double a = grid.at<double>(y, x), b = grid.at<double>(y + dv, x + du);
          if (std::isfinite(a) && std::isfinite(b)) cross += a * b, ++n;
        }
      if (n == 0) continue;
      const double rho = cross / static_cast<double>(n) / variance;
      sum_rho += 2 * rho;
      out.pairs += n;
      if (dv == 0 && du == 1) out.rho_right = rho;
      if (dv == 1 && du == 0) out.rho_down = rho;
    }
  out.factor = std::max(0.25, 1 + sum_rho);
  return out;
}

}  // namespace ramtk::vision
