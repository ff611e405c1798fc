#pragma once
// The fringe decode pipeline: images -> least-squares phase, background, modulation, quality
// mask and phase noise -> temporal unwrapping -> projector-response (gamma) correction ->
// absolute projector coordinate per camera pixel.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/core/termination.h"
#include "ramtk/vision/decode/coordinate_filter.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/decode/nonlinearity.h"

namespace ramtk::vision {

// How pixels with weak fringes are rejected (DecodeOptions::modulation_rule).
enum class ModulationRule {
  // From each pixel's own phase noise once sigma_I is known (ModulationThreshold,
  // detail/decode_internal.h): a pixel is kept when its modulation B is significantly above the
  // noise, B >= noise_floor_factor sqrt(2/N) sigma_I, and the probability that its period order
  // is wrong, from sigma_phi = sqrt(2/N) sigma_I / B and the order decision's margin (Gray bits
  // against sigma_I, the phase's quarter period of a complementary code, a heterodyne beat's
  // half period), is at most max_order_error_probability. Both are one threshold on B,
  // proportional to sigma_I (at least quantisation noise, 1/sqrt(12) DN).
  kSigma,
  // B below min_modulation_fraction of full scale, or the brightest sample below dark_fraction
  // of it (fixed fractions, for comparison).
  kFixed,
};

struct DecodeOptions {
  // Which rule rejects weak-fringe pixels (above). Codec-decoded sequences (codec.h decode)
  // have no sigma_I and keep the fixed min_modulation_fraction under either rule.
  ModulationRule modulation_rule = ModulationRule::kSigma;
  // kSigma: the largest accepted probability of a wrong period order at a pixel. 1e-4: a pixel
  // at the threshold gives one wrong order (an outlier of one or more periods) in 10 000.
  double max_order_error_probability = 1e-4;
  // kSigma: B must exceed this many times sqrt(2/N) sigma_I, the Rayleigh scale of the B that
  // noise alone gives; P(noise alone above it) = exp(-c^2 / 2) = 1e-4 at 4.3.
  double noise_floor_factor = 4.3;
  // kFixed: pixels whose modulation B is below this fraction of full scale are invalid.
  // kSigma: sigma_I, the phase ripple and the harmonic ratios are measured on the valid pixels
  // with B at least this fraction (where the fringes are clearly visible), so weaker pixels do
  // not change the noise model of the others.
  double min_modulation_fraction = 0.02;
  // Pixels with any phase-shift sample at or above this fraction of full scale are saturated.
  double saturation_fraction = 0.998;
  // A set whose every sample is below this fraction of full scale is rejected as an input error;
  // kFixed: pixels whose brightest phase-shift sample is below it are dark.
  double dark_fraction = 0.02;
  // Intensity noise sigma_I (DN) for sigma_phi = sqrt(2/N) sigma_I / B. <= 0: estimated from the
  // sinusoid-fit residuals of the valid pixels (N > 3), or quantisation noise 1/sqrt(12) for N = 3.
  double intensity_sigma_dn = 0;
  // With intensity_sigma_dn <= 0 and N > 3: sigma_I is the random part of the fit residual,
  // measured from second differences of neighbouring pixels' residuals along the fringe (the
  // projector's harmonics and slow gain changes are smooth, systematic errors, not noise; on the
  // real SLMaster set they are ~99 % of the residual's power), and the phase ripple they leave
  // at the pixel scale is measured on the decoded phase and added to sigma_phi
  // (DecodeSummary::phase_ripple_rad). false: sigma_I = the whole residual RMS and no ripple
  // term (on SLMaster a sigma 7x too large).
  bool noise_from_neighbours = true;
  int noise_stride = 4;  // every noise_stride-th pixel in x and y for those estimates (1/16 of them)
  // Those estimates and the fast path's harmonic ratios read every s-th pixel in x and y with
  // s = the larger of their stride and ceil(sqrt(valid pixels / estimate_max_samples)): on a
  // frame of more than ~16 times this many valid pixels they sample more sparsely, so that their
  // cost follows their precision, not the frame's size (200 000 pixels give sigma_I to ~0.05 %,
  // 1 / sqrt(2 pixels (N - 3))). A 3312x2488 frame reads every 6th pixel; 1280x1024 and
  // 2048x1536 ones keep the strides. 0: the strides alone.
  long estimate_max_samples = 200000;
  // Estimate the projector nonlinearity from the phase-shift frames and remove its ripple.
  bool correct_nonlinearity = true;
  NonlinearityOptions nonlinearity;  // used when correct_nonlinearity
  // Heterodyne: reject pixels whose beat orders disagree by more than this (periods).
  double max_order_residual = 0.3;
  // The harmonic ratios (a diagnostic, not used for the coordinate) are averaged over every
  // harmonic_stride-th pixel in x and y (1 = all, as the reference decode).
  int harmonic_stride = 4;
  // Keep the diagnostic maps (DecodedCamera::wrapped, background, sigma_phase, fit_residual).
  // false: they are left empty and, on the fast path, never allocated; a scan needs only the
  // coordinate, its sigma, the modulation and the mask (ScanOptions() sets false). The
  // summary's figures do not change.
  bool keep_diagnostic_maps = true;
  // Optional phase-domain smoothing of the coordinate map, carried into sigma_coordinate
  // (coordinate_filter.h); off by default (radius_px = 0).
  CoordinateFilterOptions coordinate_filter;
  // Called after each stage; returning false stops the decode (termination "cancelled").
  ProgressCallback progress;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct DecodeSummary {
  std::string camera;                               // camera name from the manifest
  Termination termination = Termination::kSuccess;  // kSuccess or kCancelled
  std::string message = "ok";                       // "ok" or "cancelled"
  int width = 0, height = 0;                        // camera image size
  int steps = 0;                                    // N of the (finest) phase-shift block
  double period_px = 0;                             // finest fringe period, projector px
  long valid_pixels = 0;                            // pixels with an absolute coordinate
  double valid_fraction = 0;                        // valid_pixels / all pixels
  long outliers = 0;                                // invalid pixels (all causes below)
  long low_modulation = 0;                          // masked: B below threshold (kSigma: above the noise floor)
  long saturated = 0;                               // masked: a saturated sample
  long dark = 0;                                    // masked: dark pixel (kSigma: B below the noise floor)
  std::string modulation_rule = "sigma";            // "sigma" or "fixed" (DecodeOptions::modulation_rule)
  double modulation_threshold_dn = 0;               // pixels with B below this were rejected, DN
  double noise_floor_dn = 0;                        // kSigma: noise_floor_factor sqrt(2/N) sigma_I, DN
  double gray_contrast_ratio = 0;                   // kSigma: Gray bits' |g - A| over B (0: no Gray code)
  long unwrap_rejected = 0;                         // masked: order not determined
  long edge_corrections = 0;                        // pixels whose period order was corrected at a code edge
  double sigma_intensity_dn = 0;                    // sigma_I used for sigma_phi
  double fit_residual_rms_dn = 0;                   // RMS intensity residual of the sinusoid fit (valid px, N > 3)
  // The residual split (DecodeOptions::noise_from_neighbours; 0 when not estimated): its random
  // (pixel-independent) part and the rest, sqrt(total^2 - random^2), both DN per degree of freedom.
  double sigma_intensity_random_dn = 0;
  double sigma_intensity_systematic_dn = 0;
  // RMS phase ripple that varies across the fringes only (rad; 0 if not estimated): the
  // projector harmonics' pixel-scale error left after the nonlinearity correction, added in
  // quadrature to every pixel's sigma_phi = sqrt((sqrt(2/N) sigma_I / B)^2 + ripple^2).
  double phase_ripple_rad = 0;
  double worst_residual_dn = 0;       // largest per-pixel residual RMS (valid px)
  double phase_residual_rms_rad = 0;  // RMS over valid px of sqrt(2/N) * residual_rms / B
  double median_modulation_dn = 0;    // median B of valid pixels
  double median_sigma_phase_rad = 0;  // median sigma_phi of valid pixels
  NonlinearityEstimate nonlinearity;  // ripple (aliased harmonic content) and correction
  // N >= 5: directly measured harmonic ratios B_h/B_1, h = 2.. (see MeasureHarmonicRatios), and
  // the power-law gamma with the same B_2/B_1 (NaN if out of range or N < 5).
  std::vector<double> harmonic_ratios;
  double gamma_from_harmonics = 0;
  // Solver-style view: iterations = nonlinearity passes; costs = high-pass phase RMS (rad)
  // before and after the nonlinearity correction.
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
  CoordinateFilterSummary coordinate_filter;  // radius_px 0: not filtered
  std::string BriefReport() const;
};

struct DecodedCamera {
  cv::Mat coordinate;        // CV_32F projector coordinate (px along the coded direction), NaN invalid
  cv::Mat wrapped;           // CV_32F wrapped LS phase of the finest block (rad) (*)
  cv::Mat background;        // CV_32F A (DN) (*)
  cv::Mat modulation;        // CV_32F B (DN)
  cv::Mat mask;              // CV_8U 255 = valid
  cv::Mat sigma_phase;       // CV_32F sigma_phi (rad), NaN invalid (*)
  cv::Mat sigma_coordinate;  // CV_32F sigma of the coordinate (projector px), NaN invalid
  cv::Mat fit_residual;      // CV_32F per-pixel RMS residual of the sinusoid fit (DN); 0 for N = 3 (*)
  // (*) empty when DecodeOptions::keep_diagnostic_maps is false.
  DecodeSummary summary;
};

// Decodes frames already in memory (CV_32FC1 in DN, or CV_8UC1 / CV_16UC1 as loaded; full_scale
// = 2^bits - 1), in the order of the manifest's sequence. InputError if the count does not match
// or the set is dark.
DecodedCamera DecodeFrames(const FringeManifest& manifest, const std::vector<cv::Mat>& frames, double full_scale,
                           const DecodeOptions& options, const std::string& camera = "");

// Loads the camera's images named in the manifest and decodes them.
DecodedCamera DecodeCamera(const FringeManifest& manifest, const std::string& camera, const DecodeOptions& options);

// Writes <camera>_coordinate, _modulation, _mask and _sigma_phase as float images with the
// extension `float_extension` ("tiff" or "exr"), the PNG previews and <camera>_summary.json into
// out_dir. Each file is written atomically.
void WriteDecodedCamera(const std::string& out_dir, const std::string& camera, const DecodedCamera& decoded,
                        const std::string& float_extension = "tiff");

// JSON text of a summary.
std::string DecodeSummaryToJson(const DecodeSummary& summary);

}  // namespace ramtk::vision
