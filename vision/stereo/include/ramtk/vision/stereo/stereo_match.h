#pragma once
// Stereo matching of equal absolute projector coordinate between two decoded cameras.
//
// For every valid left pixel the match is searched on the right camera's own (unrectified,
// distorted) coordinate map along the epipolar curve of the left pixel's ray: the curve is
// parametrised by the inverse depth w = 1/z of the point on the left ray, each sample is a
// bilinear read of the right coordinate map inside one pixel cell whose four corners are valid
// and lie within one period (no unwrap jump, no occlusion edge), and the crossing
// c_right(w) = c_left is refined on that bilinear surface. The points are never taken from a
// rectified or resampled grid, and the phase is never interpolated across a jump. Only the
// left-right check's back pass (right to left) searches a rectified grid of the left map
// (detail::StereoMatchTestHooks::rectified_back_pass, on in production): its matches decide which
// points are kept.
//
// Rejections: invalid or noisy left pixels, no crossing in the depth range, a modulation that
// differs between the cameras (another surface lit by the same projector column on the same
// epipolar curve, or a pixel straddling an edge), and left-right inconsistency (the right pixel's own match back into
// the left image must land on the left pixel) — which removes occlusions, where the left ray's surface is hidden from
// the right camera.

#include <limits>
#include <opencv2/core.hpp>
#include <string>

#include "ramtk/core/progress.h"
#include "ramtk/core/termination.h"
#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {

struct StereoMatchOptions {
  // Depth range searched along each epipolar curve, mm (z in the left-camera frame).
  double min_depth_mm = 100.0;
  double max_depth_mm = 10000.0;
  // The range for the right-to-left pass of the left-right check, z in the right-camera frame;
  // 0 (default): min/max_depth_mm, a close approximation for cameras facing the same way over a
  // wide range. A narrow range (windows around a ball, ScanRoiOptions) needs its own.
  double right_min_depth_mm = 0.0;
  double right_max_depth_mm = 0.0;
  // Left-right consistency: the right match's own match back into the left image must lie
  // within this distance of the left pixel, pixels. <= 0 disables the check.
  double lr_tolerance_px = 0.5;
  // ... or within this many of the back match's own sigma (px along its epipolar curve), if
  // larger: on low-modulation data a pixel is rejected because its sigma says the two matches
  // disagree, not by the fixed distance alone. 0: the fixed tolerance only.
  double lr_sigma_factor = 3.0;
  // Pixels whose coordinate sigma exceeds this fraction of a fringe period are not matched.
  double max_sigma_periods = 0.02;
  // An interpolation cell whose four coordinates span more than this fraction of a period
  // holds a jump (occlusion edge or unwrap error) and is not interpolated.
  double max_cell_span_periods = 0.5;
  // A matte surface point has the same fringe modulation B in both cameras: a candidate whose
  // modulation differs from the left pixel's by more than this factor (either way) is another
  // surface lit by the same projector column, or a pixel straddling an edge.
  double max_modulation_ratio = 1.5;
  // Move each match by the noise's second-order term: the root of a noisy, curved coordinate
  // map lies off the true crossing on average by −½·h''·s²/h'³ along the epipolar curve (h the
  // right map's coordinate along the curve, s² the two coordinates' variance). Where the maps
  // bend (a ball's limb) this is a bias of the points' mean that grows with the noise's variance.
  bool noise_bias_term = true;
  // Sampling step along the epipolar curve in the full search, right-camera pixels (a
  // crossing is bracketed between samples and refined on the bilinear surface).
  double search_step_px = 2.0;
  // Write the matched right pixels (StereoMatch::right_u, right_v). The scan needs only the
  // depths and sigmas: without the two maps a thesis frame's match holds 66 MB less.
  bool right_pixels = true;
  // Keep the sigma map (StereoMatch::sigma_px). The scan's points carry their own sigma
  // (point_sigma_mm), and the summary's median needs only the matched pixels' values: false
  // saves a float map (5 MB on a 1.3 Mpx frame, first touched and then released).
  bool sigma_map = true;
  // A camera whose calibration states no sampling kernel: kAuto estimates its kernel variance
  // from the back pass's matches (stereo_kernel_estimate.h) and applies the kernel terms with it
  // when the estimate is usable; kOff (default) applies no kernel terms unless both cameras state
  // one. Off by default for its cost: on the SLMaster set the estimate and the terms add ~55 ms
  // to a ~145 ms scan (docs/scan.md), against the scan's speed guard beside SLMaster.
  enum class KernelEstimate { kAuto, kOff };
  KernelEstimate kernel_estimate = KernelEstimate::kOff;
  // Called once per 64 rows of each pass; returning false cancels (termination "cancelled").
  ProgressCallback progress;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// The cameras' sampling-kernel variance measured from the stereo data (StereoMatchOptions::
// kernel_estimate): a fringe's modulation B is reduced by the kernel's MTF, 1 − ½·k·|g|² for a
// local phase gradient g (rad per px), so log(B_left / B_right) over matched pixels regresses on
// −½·(|g_left|² − |g_right|²) with slope k.
struct KernelVarianceEstimate {
  // "stated" (both cameras state a kernel; nothing estimated), "off" (not asked), "applied",
  // or why the estimate is not applied: "no back pass", "too few pixels", "too little
  // leverage", "not significant".
  std::string status = "off";
  bool applied = false;  // the kernel terms run with the estimate
  // The estimated per-axis kernel variance k, px², before clamping to [0, 1.5], and its
  // jackknife σ over bands of rows; NaN when not estimated.
  double variance_px2 = std::numeric_limits<double>::quiet_NaN();
  double sigma_px2 = std::numeric_limits<double>::quiet_NaN();
  // The variance the terms use per camera (clamped estimate or stated), px²; NaN if no terms.
  double left_px2 = std::numeric_limits<double>::quiet_NaN();
  double right_px2 = std::numeric_limits<double>::quiet_NaN();
  long pixels = 0;  // matched pixel pairs in the regression
  // The regressor's spread over the pairs (median absolute deviation of ½·(q_left − q_right))
  // over the RMS of its noise: below 2 the fit leans on the predicted noise (errors in
  // variables) and is not applied; NaN when not estimated.
  double leverage = std::numeric_limits<double>::quiet_NaN();
};

struct StereoMatchSummary {
  Termination termination = Termination::kSuccess;  // kSuccess or kCancelled
  std::string message = "ok";                       // "ok" or "cancelled"
  long left_valid = 0;                              // left pixels with a decoded coordinate
  long matched = 0;                                 // left pixels with an accepted match
  long rejected_noisy = 0;                          // left sigma above max_sigma_periods
  long rejected_no_match = 0;                       // no crossing within the depth range
  long rejected_lr = 0;  // a crossing was found but failed the modulation or left-right check
  // No right pixel's own match lands near it (within the left-right tolerance): any crossing
  // would fail the left-right check, so it is not searched (with the check only).
  long rejected_no_back_match = 0;
  long full_searches = 0;  // pixels searched over the whole depth range (no warm start)
  // How the left-right check's back pass searched: "rectified" (the left map's rectified grid),
  // "curve" (along the distorted curves: asked for, or no usable grid for this rig), "" (no check).
  std::string back_pass;
  double median_sigma_px = 0;  // median match sigma along the epipolar curve, right px
  KernelVarianceEstimate kernel;  // the sampling kernel the points pass's terms use
  std::string BriefReport() const;
};

// Per left pixel: the matched right-camera position and the match's standard deviation.
struct StereoMatch {
  cv::Mat right_u, right_v;  // CV_32F right pixel (distorted image coordinates), NaN unmatched;
                             // empty with StereoMatchOptions::right_pixels false
  cv::Mat sigma_px;          // CV_32F sigma of the match along the epipolar curve, right px;
                             // empty with StereoMatchOptions::sigma_map false
  // The matched point itself: its depth z (mm, left-camera frame) on the left pixel's ray, at
  // the crossing (the right pixel is its projection, so the two rays meet there), CV_32F, NaN
  // unmatched; and its sigma along that ray, mm, CV_32F: |dX/dw| sigma_w with w the inverse
  // depth, the first-order equal of the ray intersection's |dX/ds| sigma_px. TriangulateMatches
  // places the point on the left ray at this depth (empty: it intersects the rays itself).
  cv::Mat depth_mm;
  cv::Mat point_sigma_mm;
  // The point's x and y (mm, left-camera frame; with depth_mm its z), CV_32F, NaN unmatched: the
  // left ray's ideal coordinates times the depth as stored, so TriangulateMatches copies the
  // point instead of undistorting the left pixel again (empty: it undistorts).
  cv::Mat x_mm, y_mm;
  // Per right pixel: its own match in the left image (the left-right check's back match) and that
  // match's sigma along its epipolar curve (left px), CV_32F, NaN unmatched; empty unless
  // detail::StereoMatchTestHooks::keep_back_matches (and the check is on).
  cv::Mat back_u, back_v, back_sigma_px;
  StereoMatchSummary summary;
};

// Matches the decoded left camera into the decoded right camera. InputError (file = the
// calibration's source_path) if an image size differs from the calibration's.
StereoMatch MatchStereo(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
                        double period, const StereoMatchOptions& options);

}  // namespace ramtk::vision
