// PNG preview images of decoded maps.
#include "ramtk/vision/decode/phase_preview.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace ramtk::vision {

cv::Mat CoordinatePreview(const cv::Mat& coordinate, const cv::Mat& mask) {
  double lo = 0, hi = 1;
  cv::minMaxLoc(coordinate, &lo, &hi, nullptr, nullptr, mask);
  if (!(hi > lo)) hi = lo + 1;
  cv::Mat clean = coordinate.clone();
  clean.setTo(lo, mask == 0);
  cv::Mat grey;
  clean.convertTo(grey, CV_8U, 255.0 / (hi - lo), -lo * 255.0 / (hi - lo));
  cv::Mat colour;
  cv::applyColorMap(grey, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar::all(0), mask == 0);
  return colour;
}

cv::Mat WrappedPhasePreview(const cv::Mat& wrapped, const cv::Mat& mask) {
  cv::Mat grey;
  wrapped.convertTo(grey, CV_8U, 255.0 / (2 * CV_PI), 127.5);
  grey.setTo(0, mask == 0);
  return grey;
}

cv::Mat ScalarPreview(const cv::Mat& values, const cv::Mat& mask) {
  std::vector<float> v;
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x)
      if (mask.at<uchar>(y, x) && std::isfinite(values.at<float>(y, x))) v.push_back(values.at<float>(y, x));
  double top = 1;
  if (!v.empty()) {
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(0.99 * v.size()));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    top = std::max(1e-12f, v[k]);
  }
  cv::Mat clean = values.clone();
  clean.setTo(0, mask == 0);
  cv::patchNaNs(clean, 0);
  cv::Mat grey;
  clean.convertTo(grey, CV_8U, 255.0 / top);
  return grey;
}

}  // namespace ramtk::vision
