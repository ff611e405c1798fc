#pragma once
// Temporal phase unwrapping: Gray code (plain and complementary) and heterodyne (2 or 3
// frequencies). Output is the absolute projector coordinate in projector pixels.
//
// Period-edge errors are corrected, not masked: with a complementary Gray code the code gives
// the half-period cell k2 (resolution P/2), so its centre lies within P/4 of the true
// coordinate even when a blurred code edge is read one cell off; the period order is then
// n = round(centre/P - t) with t the fractional phase. A plain Gray code has no such margin:
// n is the code cell and a misread edge gives a whole-period jump.

#include <opencv2/core.hpp>
#include <vector>

namespace ramtk::vision {

struct UnwrapResult {
  cv::Mat coordinate;  // CV_32F, projector pixels (NaN where invalid)
  cv::Mat valid;       // CV_8U, 255 where the order was determined
  long corrected = 0;  // pixels whose order differs from the coarse code cell (edge errors fixed)
  long rejected = 0;   // pixels set invalid (order outside the projector or inconsistent beats)
};

// Fraction of a period in [0, 1) for the wrapped phase `phi` of a block with the given origin.
double PeriodFraction(double phi, double phase_at_origin_rad);

// Binary cell index (CV_32S) from Gray-code images thresholded at `threshold` (per pixel, e.g.
// the phase-shift background A). Image 0 is the most significant bit.
cv::Mat DecodeGrayCode(const std::vector<cv::Mat>& frames, const cv::Mat& threshold);

// Unwraps a phase-shift block of `cycles` periods across `extent` projector pixels with the
// Gray-code cells from DecodeGrayCode (bits = log2(cycles), +1 if complementary).
UnwrapResult UnwrapGrayCode(const cv::Mat& wrapped, double phase_at_origin_rad, double cycles, int extent,
                            const cv::Mat& cells, int bits, bool complementary);

// Heterodyne unwrapping of 2 or 3 wrapped phases with decreasing `cycles` whose beat covers the
// projector once. `max_order_residual` (periods) rejects pixels whose beats disagree.
UnwrapResult UnwrapHeterodyne(const std::vector<cv::Mat>& wrapped, const std::vector<double>& cycles,
                              double phase_at_origin_rad, int extent, double max_order_residual = 0.3);

}  // namespace ramtk::vision
