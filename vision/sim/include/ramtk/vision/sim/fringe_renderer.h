#pragma once
// Physically based rendering of fringe images: what a camera sees of a scene of spheres and planes
// lit by a pinhole projector showing phase-shift and Gray-code patterns, and the camera sensor
// (blur, shot and read noise, quantisation, saturation).
//
// Pattern convention (also written to the manifest, see docs/formats.md "Fringe image set"):
//  * The fringe coordinate c is the projector's x (vertical fringes) or y (horizontal fringes) in
//    projector pixels, pixel centres at integers (OpenCV convention); L is the projector width
//    (vertical) or height (horizontal).
//  * Phase shift, step k of N, `cycles` periods across L (the convention of the pattern generator
//    and decoder in manifest.h):
//      P_k(c) = 0.5 + 0.5·cos(φ(c) + 2πk/N + ε_k),   φ(c) = 2π·cycles·c / L + φ0,
//    φ0 the phase at the origin (default −π: every period starts dark, as in SLMaster's set), so
//    φ = atan2(−Σ I_k sin δ_k, Σ I_k cos δ_k) with δ_k = 2πk/N; ε_k is the phase-shift error.
//  * Gray code, `bits` images, image i (0 = most significant): P = bit (bits−1−i) of
//    G(floor(c·2^bits / L)), G(n) = n xor (n >> 1). A complementary Gray code for `cycles`
//    periods has bits = log2(cycles) + 1 (the SLMaster set: 64 periods, 7 images).
//  * The projector is ideal and continuous (no pixel grid); its response is P^γ.
// Radiance model at a surface point X with unit normal n and albedo ρ:
//      R = ρ·(ambient + P^γ·max(0, n·l))    if X is inside the projector image and not shadowed,
//      R = ρ·ambient                        otherwise,
// l the unit direction from X to the projector centre (no inverse-square fall-off). A camera pixel
// is the mean of n×n rays through the camera's sampling kernel (RenderOptions::kernel: a box of
// width fill_factor convolved with a Gaussian lens PSF): with the default (fill factor 1, no PSF)
// a regular grid inside the pixel (box pixel response); otherwise n nodes per axis at the
// kernel's quantiles (KernelNodeOffsets), n×n in all (the kernel is separable).

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/sim/scene.h"

namespace ramtk::vision {

// A pinhole camera or projector placed in the scene (left-camera) frame.
struct PinholeView {
  CameraIntrinsics intrinsics;                       // intrinsics and image size
  Isometry3 view_from_left = Isometry3::Identity();  // maps left-camera coordinates into this view
};

// One projected image of the sequence (heterodyne blocks expand to phase-shift frames).
struct PatternFrame {
  BlockType type = BlockType::kPhaseShift;  // kPhaseShift, kGrayCode or kRegistered
  int block = 0;                            // index of its block in the sequence
  int index = 0;                     // step k (phase shift) or image i (Gray code) within the block
  int steps = 0;                     // phase shift: N
  double cycles = 0.0;               // phase shift: periods across the projector
  double phase_at_origin_rad = 0.0;  // phase shift: φ0
  int bits = 0;                      // Gray code: number of images in the block
  double shift_error_rad = 0.0;      // phase shift: ε_k added to the nominal 2πk/N
  const PatternCodec* codec = nullptr;  // kRegistered: the codec that draws image `index` of `source`
  SequenceBlock source;                 // kRegistered: its block
};

// Expands blocks into frames (with zero shift errors). Throws InputError (field "sequence[i]") for
// N < 3, cycles ≤ 0, bits outside 1..16.
std::vector<PatternFrame> ExpandSequence(const std::vector<SequenceBlock>& blocks);

struct RenderOptions {
  int supersampling = 4;         // n: n×n rays per camera pixel
  // The camera's sampling kernel the n×n rays sample: fill factor 1 and no PSF is the box pixel
  // (today's area sampling); fill factor 0 and no PSF is point sampling at the pixel centre.
  camera::SamplingKernel kernel;
  double ambient = 0.0;          // ambient irradiance, fraction of projector white
  double projector_gamma = 1.0;  // projector response P^γ
  // Projector defocus: Gaussian blur std dev in projector pixels across the fringes (along them
  // it changes nothing); 0 = sharp. Applied to the pattern before the response P^γ (exact for
  // γ = 1).
  double projector_blur_px = 0.0;
  FringeDirection direction = FringeDirection::kVertical;  // fringe direction
  bool shadows = true;                                         // trace projector shadow rays
  ProgressCallback progress;                                   // called from worker threads (serialised), rows done
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// Radiance images of one camera and its per-pixel ground truth.
struct RenderedView {
  std::vector<cv::Mat> radiance;  // CV_32F per frame: the pixel mean of R (model above)
  cv::Mat projector_x;            // CV_32F: projector x of the pixel-centre ray's first hit; NaN if unlit
  cv::Mat projector_y;            // CV_32F: projector y, same rule
  cv::Mat depth;                  // CV_32F: z of the pixel-centre hit in this camera's frame (mm); NaN if none
  cv::Mat object_id;              // CV_32S: object id of the pixel-centre hit, −1 if none
  cv::Mat lit_fraction;           // CV_32F: fraction of the n×n rays lit by the projector on the same
                                  // object as the centre ray (1 = a clean interior pixel)
  bool cancelled = false;         // the progress callback asked to stop; images are incomplete
};

// The n sub-ray offsets per axis (px from the pixel centre, equal weights) that sample `kernel`:
// without a PSF, n points on a regular grid over the box aperture (fill_factor·((j + ½)/n − ½));
// with one, the midpoint quantiles (j + ½)/n of box⊗Gaussian scaled so that their variance is the
// kernel's (fill_factor²/12 + σ²), which the second-order kernel term depends on.
std::vector<double> KernelNodeOffsets(const camera::SamplingKernel& kernel, int n);

// Renders `frames` as seen by `camera`. Parallel over rows (TBB).
RenderedView RenderView(const Scene& scene, const PinholeView& camera, const PinholeView& projector,
                        const std::vector<PatternFrame>& frames, const RenderOptions& options);

// The camera sensor: radiance → digital numbers.
struct SensorOptions {
  int bits = 8;                        // 8, 10, 12 or 16; images hold 0 … 2^bits − 1
  double exposure = 0.9;               // fraction of full scale produced by radiance 1 at gain 1
  double full_well_electrons = 10000;  // electrons at full scale: shot-noise variance = signal in e−
  double read_noise_electrons = 10;    // read-noise std dev, e−
  double blur_sigma_px = 0.0;          // Gaussian defocus blur std dev, camera pixels (0 = none)
  // Soft knee of the sensor response (0 = linear): a signal S (DN, noise included) above
  // K = soft_knee_fraction · full scale F reads K + (F − K)·x / sqrt(1 + x²), x = (S − K)/(F − K),
  // an algebraic soft clip that is linear at the knee and approaches F smoothly.
  double soft_knee_fraction = 0.0;
  bool noise = true;  // add shot and read noise
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
  int MaxValue() const { return (1 << bits) - 1; }
};

// Expected digital number (before noise and quantisation) of radiance r: exposure·gain·r·max.
// Blur (if any) is applied to this mean image, then noise with variance
//   σ² = (DN·FW/max + read²)·(max/FW)²   (Gaussian approximation of Poisson shot noise),
// then rounding and clamping to [0, max] (saturation). Returns CV_8U for 8 bits, CV_16U otherwise.
// The noise of row r is drawn from a generator seeded by (seed, stream, r): reproducible and
// independent of thread scheduling.
cv::Mat ApplySensor(const cv::Mat& radiance, double gain, const SensorOptions& options, std::uint64_t seed,
                    std::uint64_t stream);

}  // namespace ramtk::vision
