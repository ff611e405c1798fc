#pragma once
// The cameras' sampling-kernel variance from a stereo pair's decoded modulation
// (StereoMatchOptions::kernel_estimate, KernelVarianceEstimate).
//
// A pixel sampling a fringe of local phase gradient g (rad per camera px; g = 2π·∇c / P, c the
// decoded projector coordinate, P the fringe period in projector px) and modulation B through a
// symmetric kernel of per-axis variance k reads, at second order, the modulation
//     B·(1 + ½·k·q),   q = ΔB/B − |g|²
// (the amplitude of ∫K(s)·B(s)·e^{iφ(s)} ds; box: sinc·sinc, Gaussian: exp(−½·k·|g|²) for a
// uniform B). A matte surface point has the same B in both cameras up to a gain ratio, and the
// projector's own blur is common to both, so over matched pairs (right pixel, its left match)
//     log(B_left / B_right) = a + ½·k_left·q_left − ½·k_right·q_right.
// With both kernels unknown and equal, k is the slope on x = ½·(q_left − q_right); with one
// camera's kernel known, its term moves to the left-hand side and the other's is fitted. The
// ΔB/B term matters where the ball's limb compresses B's fall-off in one camera more than in
// the other (without it a 4×4 box render of SLMaster's rig reads 0.10 px² for 0.078).
// The fit is weighted by the log ratio's noise (1 / (1/B_left² + 1/B_right²)), Huber-robust,
// with the regressor's noise taken out of its spread (errors in variables, from the
// coordinate's σ), and its σ is the delete-a-band jackknife over bands of right-image rows.

#include <opencv2/core.hpp>
#include <optional>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/stereo/stereo_match.h"

namespace ramtk::vision::detail {

// Pixel pairs: right pixel (x, y) with a finite back match (back_u, back_v) in the left image
// (left px, CV_32F, NaN unmatched). Pairs within 3 px of an invalid pixel in either camera, with
// |g| above 2 rad/px (a jump), with a modulation below a quarter of the pairs' median, or whose
// modulations differ by more than 1.5× are left out. `left_known` / `right_known`: a camera's
// stated kernel variance (px²); both given: nothing is estimated. Returns the estimate with
// status "estimated", or "too few pixels" (fewer than `min_pixels` pairs); `applied` and the
// per-camera variances are left to the caller.
KernelVarianceEstimate EstimateKernelVariance(const DecodedCamera& left, const DecodedCamera& right,
                                              const cv::Mat& back_u, const cv::Mat& back_v, double period,
                                              std::optional<double> left_known, std::optional<double> right_known,
                                              long min_pixels = 1000);

}  // namespace ramtk::vision::detail
