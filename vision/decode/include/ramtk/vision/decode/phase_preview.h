#pragma once
// PNG previews of decoded maps a person can look at: invalid pixels are black.

#include <opencv2/core.hpp>

namespace ramtk::vision {

// Projector coordinate as a colour ramp (turbo) over its valid range; CV_8UC3 (BGR).
cv::Mat CoordinatePreview(const cv::Mat& coordinate, const cv::Mat& mask);
// Wrapped phase [-pi, pi) as grey ramps; CV_8UC1.
cv::Mat WrappedPhasePreview(const cv::Mat& wrapped, const cv::Mat& mask);
// A non-negative map (modulation, sigma) scaled so its 99th percentile is white; CV_8UC1.
cv::Mat ScalarPreview(const cv::Mat& values, const cv::Mat& mask);

}  // namespace ramtk::vision
