// Least-squares wrapped phase, background, modulation and fit residual for any N >= 3.
#include "ramtk/vision/fringe/phase_shift.h"

#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>

namespace ramtk::vision {

PhaseShiftResult ComputePhaseShift(const std::vector<cv::Mat>& frames) {
  const int n = static_cast<int>(frames.size());
  CV_Assert(n >= 3);
  const cv::Size size = frames[0].size();
  PhaseShiftResult r;
  r.steps = n;
  r.wrapped.create(size, CV_32F);
  r.background.create(size, CV_32F);
  r.modulation.create(size, CV_32F);
  r.residual_ss.create(size, CV_32F);
  r.max_sample.create(size, CV_32F);
  std::vector<double> sn(n), cs(n);
  for (int k = 0; k < n; ++k) {
    sn[k] = std::sin(2.0 * CV_PI * k / n);
    cs[k] = std::cos(2.0 * CV_PI * k / n);
  }
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& range) {
    std::vector<const float*> rows(n);
    for (int y = range.start; y < range.end; ++y) {
      for (int k = 0; k < n; ++k) rows[k] = frames[k].ptr<float>(y);
      float* phi = r.wrapped.ptr<float>(y);
      float* a = r.background.ptr<float>(y);
      float* b = r.modulation.ptr<float>(y);
      float* res = r.residual_ss.ptr<float>(y);
      float* mx = r.max_sample.ptr<float>(y);
      for (int x = 0; x < size.width; ++x) {
        double s = 0, c = 0, sum = 0, sum2 = 0, top = -1e30;
        for (int k = 0; k < n; ++k) {
          const double v = rows[k][x];
          s += v * sn[k];
          c += v * cs[k];
          sum += v;
          sum2 += v * v;
          top = std::max(top, v);
        }
        const double mean = sum / n;
        const double amp2 = s * s + c * c;
        double p = std::atan2(-s, c);
        if (p >= CV_PI) p -= 2 * CV_PI;
        phi[x] = static_cast<float>(p);
        a[x] = static_cast<float>(mean);
        b[x] = static_cast<float>(2.0 / n * std::sqrt(amp2));
        // Orthogonal basis: residual = sum I^2 - N*A^2 - (2/N)*(S^2 + C^2).
        res[x] = static_cast<float>(std::max(0.0, sum2 - n * mean * mean - 2.0 / n * amp2));
        mx[x] = static_cast<float>(top);
      }
    }
  });
  return r;
}

cv::Mat PhaseSigma(const cv::Mat& modulation, int steps, double sigma_intensity) {
  cv::Mat out(modulation.size(), CV_32F);
  const double k = std::sqrt(2.0 / steps) * sigma_intensity;
  for (int y = 0; y < out.rows; ++y) {
    const float* b = modulation.ptr<float>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < out.cols; ++x)
      o[x] = b[x] > 0 ? static_cast<float>(k / b[x]) : std::numeric_limits<float>::infinity();
  }
  return out;
}

}  // namespace ramtk::vision
