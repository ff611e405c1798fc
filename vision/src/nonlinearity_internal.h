#pragma once
// Shared by the reference (nonlinearity.cpp) and fast (nonlinearity_fast.cpp) ripple estimators.

#include <opencv2/core.hpp>

namespace ramtk::vision::detail {

// Median camera fringe period (px) from the gradient of the unwrapped phase (CV_32F) over the
// pixels where `mask` is non-zero, sampled on the even rows and columns; 0 if none.
double CameraFringePeriod(const cv::Mat& phase, const cv::Mat& mask);

}  // namespace ramtk::vision::detail
