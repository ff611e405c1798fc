#pragma once
// Projector response nonlinearity (gamma) estimated from the phase-shift frames themselves and
// its phase error removed, with no separate calibration capture.
//
// A non-sinusoidal fringe profile (harmonics h of the phase) leaks into an N-step LS phase as a
// periodic error of the *measured* phase phi': harmonics h = mN +- 1 alias onto a ripple
//   dphi(phi') = sum_m s_m sin(m N phi') + c_m cos(m N phi').
// On a surface whose true phase is smooth at the scale of a fringe period, this ripple is the
// only part of the unwrapped phase that oscillates N times per period. We high-pass the
// unwrapped phase with a box filter (window about two camera fringe periods), apply the same
// high-pass to each basis function, solve for s_m, c_m by least squares over all valid pixels
// (residuals beyond `outlier_rad`, e.g. at depth steps, are left out), and subtract the ripple.
// The first-order coefficient s_1 is the identifiable harmonic content (to first order
// s_1 = r_{N+1} - r_{N-1}, r_h = B_h/B_1); it is also converted into the equivalent projector
// gamma of a pure power-law response (I ∝ (0.5 + 0.5 cos)^gamma).

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ramtk::vision {

struct NonlinearityOptions {
  int orders = 3;            // ripple orders m = 1..orders (of N*phi')
  int passes = 2;            // estimate/correct passes (the second refines outlier rejection)
  int window_px = 0;         // box window (odd, camera px); 0 = about two camera fringe periods
  double outlier_rad = 0.5;  // high-pass residuals beyond this are left out of the fit
  long min_pixels = 500;     // fewer usable pixels: no correction (estimate.applied = false)
  // The first pass's first-order ripple (s_1, c_1) must be significant against its own
  // leave-one-band-out (jackknife) scatter, T² = aᵀC⁻¹a over kRippleBands bands of rows, else the
  // phase is left as it was (estimate.applied = false; the fit is still reported). The method
  // assumes the surface's own phase is smooth over the window; on a ball a few tens of pixels
  // across, or a scene with edges, the high-pass keeps the surface's shape at ~10x the phase
  // noise and a ripple fitted to it is spurious: it differs from band to band, while a
  // projector's ripple is the same everywhere. The default is Hotelling's T² critical value at
  // p = 0.001 for 2 coefficients from 16 bands (2·15/14 · F(2, 14) = 25.2). Spurious fits on the
  // campaign twin's 12-step balls had biased each apex by up to 27 µm (docs/scan.md,
  // "Projector nonlinearity on small balls"). 0 disables the test.
  double min_ripple_t2 = 25.2;
  // The fit reads only 1/k of the rows of each of those bands (the last ones of even bands, the
  // first ones of odd bands: each pair's rows adjoin), k = the smaller of
  // row_subsample and (valid pixels / row_subsample_min_pixels), at least 1; the ripple is still
  // removed from every pixel. A fit to more than ~100 k pixels gains little from more of them:
  // its coefficients' noise is ~sigma_hp / sqrt(pixels / 2) (sigma_hp the high-passed phase's
  // RMS: ~0.01 rad on a smooth surface, ~0.17 rad on the real SLMaster scene, whose shape stays in
  // the high-pass), 3e-5 to 8e-4 rad at 100 k pixels, while the sweep cost ~0.5 s per camera of a
  // 3312x2488 frame and ~10 ms of the ~25 ms decode of a 1280x1024 camera. The test's T² falls by
  // ~k for a real ripple (its power), not under the null (its false-alarm rate). 1 = every row.
  int row_subsample = 4;
  long row_subsample_min_pixels = 100000;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct NonlinearityEstimate {
  int steps = 0;                       // N of the phase-shift block
  std::vector<double> sin_rad;         // s_m, m = 1..orders (radians)
  std::vector<double> cos_rad;         // c_m
  double ripple_rms_rad = 0;           // RMS of the fitted ripple sum_m (s_m, c_m)
  double residual_rms_before_rad = 0;  // RMS of the high-passed phase before correction
  double residual_rms_after_rad = 0;   // ... and after
  // Power-law gamma giving the same s_1; NaN if out of range or the ripple was not significant
  // (not applied): a gamma fitted to noise would mislead.
  double equivalent_gamma = 1;
  int window_px = 0;      // window used
  long pixels_used = 0;   // pixels in the final fit
  int passes = 0;         // passes run
  bool applied = false;   // false if too few pixels or the ripple is not significant: phase unchanged
  double ripple_t2 = 0;   // T² of (s_1, c_1) against its jackknife covariance (first pass)
  int row_subsample = 1;  // k: the fit read 1/k of each band's rows
  std::string BriefReport() const;
};

// `abs_phase` (CV_32F, radians of the finest block, unwrapped) is corrected in place where
// `mask` (CV_8U) is non-zero; `wrapped` is the measured LS phase of the same block. Only the
// mask's bounding box is processed, the basis functions at valid pixels, with parallel box filters
// and accumulation; the reference over whole maps (detail::CorrectPhaseNonlinearityReference,
// detail/decode_internal.h) gives the same within float rounding of the basis functions.
NonlinearityEstimate CorrectPhaseNonlinearity(cv::Mat& abs_phase, const cv::Mat& wrapped, const cv::Mat& mask,
                                              int steps, const NonlinearityOptions& options = {});

// Direct harmonic content for N >= 5 steps (harmonics h < N/2 are resolved per pixel): the
// signed ratio r_h = B_h / B_1 of a memoryless response, phase-locked to h*phi and averaged over
// the pixels where `mask` is non-zero, for h = 2 .. ceil(N/2) - 1. Empty for N < 5.
std::vector<double> MeasureHarmonicRatios(const std::vector<cv::Mat>& frames, const cv::Mat& mask);
// r_2 = B_2 / B_1 of a power-law response (0.5 + 0.5 cos)^gamma: (gamma - 1) / (gamma + 2).
double SecondHarmonicOfGamma(double gamma);
// Inverse of SecondHarmonicOfGamma over [0.3, 5]; NaN if out of range.
double GammaFromSecondHarmonic(double r2);

// First-order ripple coefficient s_1 that a projector gamma produces in an N-step LS phase.
double RippleOfGamma(double gamma, int steps);
// Inverse of RippleOfGamma: the first root in [1, 5], else in [0.3, 1]; NaN if none.
double EquivalentGamma(double ripple_sin1, int steps);

}  // namespace ramtk::vision
