#pragma once
// Shared by the reference (nonlinearity.cpp) and fast (nonlinearity_fast.cpp) ripple estimators.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

namespace ramtk::vision::detail {

// Median camera fringe period (px) from the gradient of the unwrapped phase (CV_32F) over the
// pixels where `mask` is non-zero, sampled on the even rows and columns; 0 if none.
double CameraFringePeriod(const cv::Mat& phase, const cv::Mat& mask);

// Bands of rows of the mask's bounding box for the ripple's jackknife test: row y (relative to
// the box's first row, box height h) is in band y * kRippleBands / h.
inline constexpr int kRippleBands = 16;
inline int RippleBand(int y, int height) { return static_cast<int>(static_cast<long>(y) * kRippleBands / height); }

// NonlinearityOptions::row_subsample as applied to a mask with `valid` pixels: k >= 1.
int RippleRowSubsample(long valid, int row_subsample, long min_pixels);

// The rows of a box `height` rows tall that the fit reads with subsample k, as [first, last)
// ranges relative to the box's first row: every row for k = 1, else ceil(rows / k) rows of each
// band (the rows y with RippleBand(y) = b), the last ones of an even band and the first ones of
// an odd band, so that each pair of bands gives one range (the fast path's strips then compute
// the window margin once per pair, not once per band).
std::vector<std::pair<int, int>> RippleFitRows(int height, int k);

// T² of the first-order ripple coefficients (entries 1 and 2; entry 0 is the intercept) of the
// least-squares fit from the summed normal equations, against their leave-one-band-out
// (jackknife) covariance. `ata` are full symmetric terms × terms matrices, one per band. 0 if a
// leave-one-out system is singular or fewer than 4 bands hold pixels.
double FirstOrderRippleT2(const std::vector<Eigen::MatrixXd>& ata, const std::vector<Eigen::VectorXd>& atb);

}  // namespace ramtk::vision::detail
