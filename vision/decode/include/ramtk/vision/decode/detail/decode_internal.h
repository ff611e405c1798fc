#pragma once
// Internal interface of the fast decode path (decode_fast.cpp, decode_fused.cpp,
// harmonic_ratios_fast.cpp) and of the references it is tested against (decode_reference.cpp,
// nonlinearity.cpp), used by decode.cpp and the tests.

#include <cstdint>
#include <cstring>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/decode/nonlinearity.h"

namespace ramtk::vision::detail {

// Whether the eight bytes at p are all zero (eight masked pixels, skipped at once).
inline bool EightZero(const uchar* p) {
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v == 0;
}

struct FastDecodeInput {
  int width = 0, height = 0;
  // Phase-shift frames per frequency, finest first (all CV_8U, all CV_16U or all CV_32F).
  std::vector<std::vector<const cv::Mat*>> ps_frames;
  std::vector<int> steps;                                // N per frequency
  std::vector<std::vector<float>> sin_table, cos_table;  // sin/cos(2 pi k / N) per frequency
  std::vector<const cv::Mat*> gray_frames;               // Gray-code frames (empty: none)
  bool complementary = false;                            // the Gray code has the extra half-period bit
  bool heterodyne = false;                               // coordinate from several frequencies (after the pass)
  double phase_at_origin_rad = 0;
  double period = 0;                          // finest period, projector px
  int extent = 0;                             // projector px along the coded direction
  float b_min = 0, saturation = 0, dark = 0;  // thresholds, DN
  float b_sample = 0;                         // residual sums only over valid pixels with B >= this, DN
  bool keep_diagnostic_maps = true;           // false: no background / fit_residual maps
};

struct FastDecodeOutput {
  // background and fit_residual are empty without FastDecodeInput::keep_diagnostic_maps
  // (fit_residual is kept for the heterodyne unwrap).
  cv::Mat wrapped, background, modulation, fit_residual, coordinate, mask;
  std::vector<cv::Mat> coarse_wrapped;  // heterodyne: wrapped phase of frequencies 1.. (0 where masked)
  float b_sample_dn = 0;                // FastDecodeInput::b_sample (for the heterodyne unwrap's sums)
};

struct FastDecodeCounts {
  long dark = 0, saturated = 0, low_modulation = 0, unwrap_rejected = 0, corrected = 0, valid = 0;
  long sampled = 0;                                          // valid pixels with B >= b_sample
  double residual_ss = 0, phase_ss = 0, worst_residual = 0;  // over those pixels
  double brightest = 0;                                      // the brightest sample of the finest phase-shift frames
};

// The fast path of DecodeFrames (arguments already validated; frames all CV_8UC1, CV_16UC1 or CV_32FC1).
DecodedCamera DecodeFramesFast(const FringeManifest& manifest, const std::vector<cv::Mat>& frames, double full_scale,
                               const DecodeOptions& options, const std::string& camera);

// LS phase atan2(-S, C) in [-pi, pi).
float WrappedPhase(float s, float c);
// WrappedPhase of n pixels, on two lanes where the build has them (the same bits).
void WrappedPhaseRow(const float* s, const float* c, int n, float* phi);

// The fused pass. Pixels masked by darkness, saturation or modulation get phase 0 and a NaN
// coordinate; for heterodyne sets the coordinate and the counts of valid pixels are left to the caller.
void DecodeFused(const FastDecodeInput& in, FastDecodeOutput* out, FastDecodeCounts* counts);

// MeasureHarmonicRatios over every `stride`-th pixel in x and y, on frames of any sample type.
std::vector<double> MeasureHarmonicRatiosFast(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                                              int stride);

// The intensity noise split into its random part and the total fit residual. The random part
// comes from the second difference r(-1) - 2 r(0) + r(+1) of the fit residual vectors of three
// neighbouring pixels along the fringe (the row or column whose phase changes least): noise that
// is independent from pixel to pixel adds up (6 sigma^2 per degree of freedom), while the
// phase-dependent residual (projector harmonics, gamma) and slow gain changes cancel to second
// order. Every `stride`-th pixel in x and y; N >= 4 equally spaced steps over 2 pi; frames
// CV_8U, CV_16U or CV_32F. Noise correlated between pixels (demosaicing, compression) would be
// under-estimated.
struct IntensityNoise {
  double random_dn = 0;  // sigma of the pixel-independent part, DN
  double total_dn = 0;   // RMS fit residual per degree of freedom over the same pixels, DN
  long pairs = 0;        // pixel triples used
};
IntensityNoise EstimateIntensityNoise(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask, int stride);

// RMS phase ripple (rad) that varies across the fringes but not along them: the excess of the
// decoded phase's second differences across the fringes over those along them (robust MAD
// variances), divided by the white-noise gain 6. The pixel-scale error a phase-dependent
// residual (projector harmonics not removed by the nonlinearity correction) leaves in the
// points; 0 if too few pixels. Every `stride`-th pixel.
double EstimatePhaseRipple(const cv::Mat& coordinate, const cv::Mat& mask, double period_px, int stride);

// EstimatePhaseRipple when DecodeOptions::noise_from_neighbours and N > 3, else 0; `valid`
// pixels in the mask (EstimateStride).
double PhaseRipple(const DecodeOptions& options, const cv::Mat& coordinate, const cv::Mat& mask, int n,
                   double period_px, long valid);

// The sampling stride of a per-pixel estimate over `valid` pixels: `stride`, or the smallest
// larger one that reads at most ~max_samples of them (DecodeOptions::estimate_max_samples;
// 0: `stride`).
int EstimateStride(int stride, long valid, long max_samples);

// Sets sum->sigma_intensity_dn (and the random/systematic split) from the options, the fit
// residual RMS already in `sum`, and the finest phase-shift frames (both decode paths).
void ChooseIntensitySigma(const DecodeOptions& options, const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                          int n, long valid, DecodeSummary* sum);

// One row of a decode's sigma maps (the fast path): sigma_phi = sqrt(k_sigma^2 / B^2 + ripple^2),
// +inf where B <= 0 or NaN, into `sp` (if not null) and sigma_phi * to_px (as float) into `sc`;
// where the mask byte is 0, NaN in both and in the coordinate `c` (otherwise left as it is).
void SigmaRow(const uchar* mk, const float* b, int width, double k_sigma, double ripple, double to_px, float* c,
              float* sp, float* sc);

// The period-order decision of a sequence, for the probability that it goes wrong.
struct OrderDecision {
  int gray_bits = 0;            // Gray-code bits, each compared with the pixel's background A
  bool complementary = false;   // the Gray code's half-period bit: the phase picks the order within +-1/4 period
  double heterodyne_ratio = 0;  // heterodyne: finest cycles over the first beat's cycles; 0 = none
  double gray_contrast = 1;     // a Gray bit's |sample - A| over the sinusoids' B (GrayContrastRatio)
};
// The order decision of a manifest's sequence (none for a single period across the projector).
OrderDecision OrderDecisionOf(const FringeManifest& m);

// The Gray bits' contrast over the sinusoids' modulation: the median over every `stride`-th
// pixel of `sample` (x and y) of median_j |g_j - A| / B, A and B from the finest phase-shift
// frames (a binary pattern keeps more contrast than a sinusoid through the optics' blur, and a
// projector may drive them differently). 1 without Gray frames or with fewer than 100 pixels.
double GrayContrastRatio(const std::vector<const cv::Mat*>& ps_frames, const std::vector<const cv::Mat*>& gray_frames,
                         const cv::Mat& sample, int stride);

// Probability that a pixel's period order is wrong at B / sigma_I = `b_over_sigma` with N steps:
// every Gray bit at contrast gray_contrast x B against noise sigma_I sqrt(1 + 1/N) (sample and A), one-sided
// (an upper bound: the half-period bit of a complementary code is half corrected by the phase);
// a complementary code's phase beyond +-pi/2 of its cell centre; a heterodyne order beyond +-1/2
// period, with sigma = sigma_phi sqrt(1 + 2 ratio^2) / 2 pi (the beat of two phases, scaled up).
double OrderErrorProbability(const OrderDecision& d, int n, double b_over_sigma);

struct ModulationThreshold {
  double floor_dn = 0;      // noise_floor_factor sqrt(2/N) sigma_I
  double threshold_dn = 0;  // the larger of the floor and the B where OrderErrorProbability = the option
};
// ModulationRule::kSigma's threshold on B for sigma_I (clamped to >= 1/sqrt(12) DN).
ModulationThreshold SigmaModulationThreshold(const OrderDecision& d, int n, double sigma_i,
                                             const DecodeOptions& options);

// The pixels sigma_I and the other noise figures are measured on: `mask` where B >= b_sample
// (all of `mask` when b_sample <= 0).
cv::Mat NoiseSampleMask(const cv::Mat& mask, const cv::Mat& modulation, float b_sample);

// Masks the pixels of `mask` whose B is below t.threshold_dn (coordinate NaN), counting those
// below t.floor_dn into *dark and the others into *low. Returns the pixels removed.
long ApplyModulationThreshold(const ModulationThreshold& t, const cv::Mat& modulation, cv::Mat& mask,
                              cv::Mat& coordinate, long* dark, long* low);

// The decode of a sequence whose one block is a codec with its own decode function (codec.h
// PatternCodec::decode, decode_codec.cpp): the frames as float, the codec's coordinate, modulation
// and sigma, the mask where the coordinate is finite, and the summary's counts and medians.
DecodedCamera DecodeFramesWithCodec(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                                    const DecodeOptions& options, const std::string& camera);

// The reference decode: float frames, one pass per stage over every pixel (phase_shift.h,
// unwrap.h, CorrectPhaseNonlinearityReference). Runs in place of DecodeFramesFast under the test
// hook DecodeTestHooks::reference_path.
DecodedCamera DecodeFramesReference(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                                    const DecodeOptions& options, const std::string& camera);

// The reference ripple estimator over whole maps (nonlinearity.cpp): the same estimate and
// correction as CorrectPhaseNonlinearity within float rounding of the basis functions.
NonlinearityEstimate CorrectPhaseNonlinearityReference(cv::Mat& abs_phase, const cv::Mat& wrapped,
                                                       const cv::Mat& mask, int steps,
                                                       const NonlinearityOptions& options = {});

}  // namespace ramtk::vision::detail
