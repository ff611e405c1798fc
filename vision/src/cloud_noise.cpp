// Local surface-fit noise of an organised cloud (cloud_noise.h).
#include "ramtk/vision/cloud_noise.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
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
