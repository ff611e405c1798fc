#pragma once
// Shared by the reference (nonlinearity.cpp) and fast (nonlinearity_fast.cpp) ripple estimators.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "ramtk/vision/decode/nonlinearity.h"

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

// Whether the ripple's significance is tested first on a fit of the first order alone (a test
// is asked for, min_ripple_t2 > 0, and there are higher orders): T² reads only the first-order
// coefficients, and a ripple that is not significant is never fitted with all orders (on a
// 12-step set or a linear projector that is every time, at a third of the basis's cost). A
// significant one is fitted with every order from the start, as without the test.
inline bool FirstOrderRippleGate(const NonlinearityOptions& options) {
  return options.min_ripple_t2 > 0 && options.orders > 1;
}

// Fills the estimate's ripple RMS (from its coefficients) and its equivalent gamma (only for an
// applied correction; NaN otherwise) and returns it.
NonlinearityEstimate FinishRippleEstimate(NonlinearityEstimate* est);

}  // namespace ramtk::vision::detail
