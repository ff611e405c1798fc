// Internal to the fringe diagnosis: the per-pixel ideal-model fit, its residuals and the
// candidate extensions (fringe_model.cpp, fringe_candidates.cpp, fringe_pictures.cpp).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/camera/camera_model.h"
#include "ramtk/diagnose/engine/diagnosis.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::diagnose::fringe {

// Noise-level function of the sensor: variance of one sample against its intensity I (DN), estimated
// from the phase-shift residuals (which keep (N − 3)/N of it). A residual's variance is that times
// ResidualVarianceFactor (the per-pixel fit's leverage).
inline constexpr double kQuadraticZ = 5.0;       // I² term significant beyond this many sigmas …
inline constexpr double kQuadraticShare = 0.25;  // … and carrying this share of the brightest variance
struct NoiseLevel {
  double a = 0, b = 0, c = 0;  // variance a + b·I + c·I² (c = 0 unless super_poisson), DN², DN, 1
  double sigma_a = 0, sigma_b = 0;
  double quadratic_c = 0, sigma_c = 0;  // the I² coefficient of the quadratic fit, always reported
  double quadratic_share = 0;           // its share of the variance at the brightest level
  bool super_poisson = false;           // the I² term is significant and material
  double linear_chi2 = 0;               // lack of fit of a + b·I over the bins
  int bins = 0;
  double top_level = 0;  // mean level of the brightest bin (DN)
  long pairs = 0;        // neighbour differences used
  double Variance(double level) const;  // ≥ 1/12 DN² (quantisation)
};

// The camera's sampling kernel (camera_model.h): a pixel's response is a box of side fill_factor
// camera px (0: point sampling, the pixel's centre ray) convolved with an isotropic Gaussian PSF of
// std dev psf_sigma_px camera px. The Gray-code edge profile and the stripes' contrast follow it.
using SamplingKernel = camera::SamplingKernel;

// One analysed pixel: the ideal model's per-pixel parameters.
struct PixelFit {
  int x = 0, y = 0;
  int tile = 0;                   // image region (cross-validation group)
  double a = 0, b = 0;            // background A and modulation B (DN)
  double phi = 0;                 // wrapped phase of the phase-shift block (rad)
  double u = 0;                   // unwrapped projector coordinate (projector px)
  double grad_x = 0, grad_y = 0;  // du/dx, du/dy (projector px per camera px)
  bool clipped = false;           // a phase-shift sample at the clip level
  bool censored = false;          // fitted against the expectation clamped at 0 (ModelSensorRange)
};

// The measured set and the ideal model fitted to it.
struct FringeFit {
  int width = 0, height = 0;
  int steps = 0;                 // N
  int frames = 0;                // N + Gray-code images
  std::vector<int> phase_frame;  // frame index of phase step k
  std::vector<int> gray_frame;   // frame index of Gray image j
  int gray_bits = 0;
  int extent = 0;
  double period_u = 1;  // fringe period, projector px
  double full_scale = 255;
  bool vertical = true;
  SamplingKernel kernel;  // the stated kernel the Gray-code frames are predicted with
  double edge_offset = 0;  // code edges at c·cell + edge_offset projector px (0 or −0.5, FitIdealModel)
  double edge_offset_estimate = 0;  // the code edges' 50 % crossing that chose it
  int tiles_x = 8, tiles_y = 8;
  std::vector<cv::Mat> images;   // CV_32F, DN, in frame order
  std::vector<PixelFit> pixels;  // analysed pixels
  std::vector<float> residual;   // pixels.size() × frames: measured − ideal model; NaN = not
                                 // used (Gray samples within the edge band, EdgeBand)
  std::vector<float> weight;     // same layout: σ̄/σ(I) from the noise-level function (empty = all 1);
                                 // candidates fit and score residual·weight (heteroscedastic)
  cv::Mat index;                 // CV_32S, pixel → index into `pixels`, −1 if not analysed
  long masked_saturated = 0;     // informational counts
  // The sensor's black end: with `censored`, a sample's expected value is that of a noisy value
  // (σ from `noise`) clamped at 0 (SensorExpectation), which bends the mean response of dark
  // samples when the noise is large (high camera gain, no black offset). Clipping at full scale
  // stays the `saturation` candidate's.
  NoiseLevel noise;
  bool censored = false;
  long range_refitted = 0;  // pixels refitted with the censored expectation
};

// E[max(X, 0)] for X ~ N(mu, σ²(mu)) for a censored pixel, else mu.
double SensorExpectation(const FringeFit& fit, const PixelFit& p, double mu);

// Noise-level function of the set (fringe_noise.cpp), from residual differences along the fringes.
NoiseLevel EstimateNoiseLevel(const FringeFit& fit);

// Residual variance over sample variance for frame f: 1 − 3/N for a phase-shift frame (the fit
// absorbs 3 of N degrees of freedom), 1 + 3/N for a Gray-code frame (its prediction A ± B' carries
// the variance of the fitted A and B, σ²/N + 2σ²/N).
double ResidualVarianceFactor(const FringeFit& fit, int f);

// Models the sensor's black end with the noise-level function `noise`: pixels whose phase samples
// come within 4σ of 0 (and not more than 2σ below it: light is not negative) are refitted (A, B, φ)
// against the censored expectation, and every residual is recomputed against it.
void ModelSensorRange(const NoiseLevel& noise, FringeFit* fit);

// Shift of phase step k (nominal, rad).
double StepShift(int k, int steps);

// Fits the ideal model with the camera's sampling kernel `kernel`. Throws InputError when the
// sequence is not one phase-shift block plus one Gray-code block, or when no pixel can be analysed.
FringeFit FitIdealModel(const vision::FringeManifest& manifest, const std::vector<cv::Mat>& images, double full_scale,
                        const SamplingKernel& kernel = {});

// Value of Gray image j at coordinate u for a pixel whose box footprint spans `width_u` projector
// px along u, blurred by a Gaussian of std dev `sigma_u` (projector px); in [0, 1].
double GrayPattern(const FringeFit& fit, int j, double u, double width_u, double sigma_u);

// Footprint of pixel p's kernel along u (projector px) for the Gray edge profile: the box's width
// along the steeper image axis, and a Gaussian spread (the other axis's box as its std dev, the PSF
// times |∇u|).
void Footprint(const SamplingKernel& kernel, const PixelFit& p, double* width_u, double* spread_u);

// Half-width (projector px) of the band around a Gray-code edge whose samples are left out: the
// support of the kernel's box along u, 0.5·fill·(|∂u/∂x| + |∂u/∂y|), plus half a projector pixel
// (a code edge lies on a projector pixel boundary, whose position relative to the phase's pixel
// centres and whose own aperture the model does not know). The PSF is modelled, not left out.
// FitIdealModel widens it by 4 standard deviations of u's noise.
double EdgeBand(const SamplingKernel& kernel, const PixelFit& p);

// Distance (projector px) from u to the nearest edge of Gray image j.
double EdgeDistance(const FringeFit& fit, int j, double u);

// Ideal intensity of Gray image j at pixel p with an extra Gaussian blur of `blur_u` projector px
// (0: the ideal model; the stated kernel's footprint is always included).
double GrayIntensity(const FringeFit& fit, const PixelFit& p, int j, double blur_u);
// The same with `kernel` in place of the stated one.
double GrayIntensityWith(const FringeFit& fit, const SamplingKernel& kernel, const PixelFit& p, int j, double blur_u);

// Ideal intensity of pixel p in frame f (what the residual is measured against).
double IdealIntensity(const FringeFit& fit, const PixelFit& p, int f);

// Noise floor: RMS of the residual differences between neighbouring analysed pixels along the
// fringe direction, over √2 (outliers beyond 6 robust sigmas left out).
double NoiseFloor(const FringeFit& fit, long* pairs);


// Fits every candidate with cross-validation over tiles; returns them with heldout/train RMS
// filled (kNoEffect first). `sigma` is the noise floor (for the parameter sigmas).
std::vector<CandidateFit> FitCandidates(const FringeFit& fit, int folds, double sigma);

// Pictures of the base residual into `folder`; returns their captions.
std::vector<Picture> WriteFringePictures(const FringeFit& fit, double floor, const std::string& folder,
                                         unsigned long long seed);

}  // namespace ramtk::diagnose::fringe
