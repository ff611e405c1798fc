#pragma once
// Pinhole camera with OpenCV's lens models: the 5-coefficient distortion (k1, k2, p1, p2, k3), the
// rational / thin-prism / tilted-sensor model of its 8, 12 and 14-coefficient vectors, and the
// fisheye (equidistant) model of cv::fisheye.
//
// Conventions (the same as OpenCV's calib3d):
//  * Camera frame: x right, y down, z forward (optical axis); millimetres.
//  * Pixel coordinates: the centre of the top-left pixel is (0, 0); u grows to the right, v down.
//  * Projection (cv::projectPoints): x' = X/Z, y' = Y/Z; r² = x'² + y'²;
//      x'' = x'(1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x'y' + p2 (r² + 2x'²)
//      y'' = y'(1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2y'²) + 2 p2 x'y'
//      u = fx x'' + cx,  v = fy y'' + cy.
//  * Rational (LensModel::kRational, cv::projectPoints with 8, 12 or 14 coefficients): the radial
//    factor is (1 + k1 r² + k2 r⁴ + k3 r⁶) / (1 + k4 r² + k5 r⁴ + k6 r⁶); thin prism adds
//    s1 r² + s2 r⁴ to x'' and s3 r² + s4 r⁴ to y''; the tilted sensor maps (x'', y'') through
//    OpenCV's computeTiltProjectionMatrix(τx, τy) before K.
//  * Fisheye (LensModel::kFisheye, cv::fisheye::projectPoints without skew): r = |(x', y')|,
//    θ = atan r, θd = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), (x'', y'') = (θd / r) (x', y').
//  * Back-projection inverts the distortion with Gauss-Newton to machine precision (OpenCV's
//    cv::undistortPoints runs a fixed number of fixed-point iterations by default).

#include <Eigen/Core>
#include <optional>
#include <string>

#include "ramtk/core/rotation.h"

namespace ramtk::camera {

using Vec2 = Eigen::Vector2d;

// Which of OpenCV's lens models a Distortion follows.
enum class LensModel {
  kPinhole5,  // k1 k2 p1 p2 k3 (cv::projectPoints with 4 or 5 coefficients)
  kRational,  // rational radial, thin prism and sensor tilt (cv::projectPoints with 8, 12 or 14)
  kFisheye,   // equidistant fisheye k1..k4 (cv::fisheye::projectPoints)
};

// OpenCV distortion coefficients. The first five are OpenCV's (k1, k2, p1, p2, k3); the rest are
// zero in the 5-coefficient model. The fisheye model uses k1, k2, k3, k4 (its θ³, θ⁵, θ⁷, θ⁹
// terms) and no others.
struct Distortion {
  double k1 = 0.0;                         // radial, r² (fisheye: θ³)
  double k2 = 0.0;                         // radial, r⁴ (fisheye: θ⁵)
  double p1 = 0.0;                         // tangential
  double p2 = 0.0;                         // tangential
  double k3 = 0.0;                         // radial, r⁶ (fisheye: θ⁷)
  double k4 = 0.0;                         // rational: denominator r² (fisheye: θ⁹)
  double k5 = 0.0;                         // rational: denominator r⁴
  double k6 = 0.0;                         // rational: denominator r⁶
  double s1 = 0.0;                         // thin prism: x'' += s1 r²
  double s2 = 0.0;                         // thin prism: x'' += s2 r⁴
  double s3 = 0.0;                         // thin prism: y'' += s3 r²
  double s4 = 0.0;                         // thin prism: y'' += s4 r⁴
  double tilt_x_deg = 0.0;                 // sensor tilt τx, degrees (OpenCV's coefficient vector holds radians)
  double tilt_y_deg = 0.0;                 // sensor tilt τy, degrees
  LensModel model = LensModel::kPinhole5;  // which formula the coefficients enter
  // Whether the model is the identity (an ideal pinhole): never for the fisheye model.
  bool IsZero() const {
    return model != LensModel::kFisheye && k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0 && k4 == 0 && k5 == 0 &&
           k6 == 0 && s1 == 0 && s2 == 0 && s3 == 0 && s4 == 0 && tilt_x_deg == 0 && tilt_y_deg == 0;
  }
};

// The model's name in calibration files and on the command line: "pinhole5", "rational", "fisheye".
const char* LensModelName(LensModel model);
// Parses a model name: those of LensModelName, "thin-prism" (rational), and ROS's "plumb_bob",
// "rational_polynomial", "equidistant". Returns false for anything else.
bool ParseLensModel(const std::string& name, LensModel* model);

// DistortNormalized and its Jacobian for the rational and fisheye models (lens_models.cpp).
Vec2 DistortNormalizedGeneral(const Distortion& d, const Vec2& undistorted);
Eigen::Matrix2d DistortNormalizedJacobianGeneral(const Distortion& d, const Vec2& undistorted);

// The camera's sampling kernel: a pixel's value is the irradiance averaged over a square box
// aperture `fill_factor` px wide (centred on the pixel centre; 0 = point sampling), convolved with
// an isotropic Gaussian lens PSF of standard deviation `psf_sigma_px` px. Per axis the kernel's
// variance is fill_factor²/12 + psf_sigma_px² px², and a smooth signal c sampled through it reads
// c + ½·variance·(c_uu + c_vv) at second order (the stereo matcher's kernel term).
struct SamplingKernel {
  double fill_factor = 1.0;   // width of the square box aperture, px, in [0, 1] (0 = point sampling)
  double psf_sigma_px = 0.0;  // σ of the isotropic Gaussian lens PSF, px, in [0, 10]
  // Per-axis variance of the kernel, px².
  double VariancePx2() const { return fill_factor * fill_factor / 12.0 + psf_sigma_px * psf_sigma_px; }
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
  bool operator==(const SamplingKernel& o) const {
    return fill_factor == o.fill_factor && psf_sigma_px == o.psf_sigma_px;
  }
  bool operator!=(const SamplingKernel& o) const { return !(*this == o); }
};

// Intrinsics of one pinhole camera (or projector) and its image size.
struct CameraIntrinsics {
  double fx = 1.0;        // focal length along u, pixels
  double fy = 1.0;        // focal length along v, pixels
  double cx = 0.0;        // principal point u, pixels
  double cy = 0.0;        // principal point v, pixels
  Distortion distortion;  // lens distortion (zero = ideal pinhole)
  int width = 0;          // image width, pixels
  int height = 0;         // image height, pixels
  // The sampling kernel, when the calibration states one; empty = not stated (the stereo
  // matcher then applies no kernel or interpolation correction: docs/formats.md).
  std::optional<SamplingKernel> sampling_kernel = std::nullopt;

  // The 3×3 camera matrix K.
  Mat3 K() const;
};

// The 5-coefficient model's distortion of ideal normalised coordinates (x', y') → (x'', y''),
// whatever d.model says (the kernels that have checked the model call it directly).
inline Vec2 DistortPinhole5(const Distortion& d, const Vec2& undistorted) {
  const double x = undistorted.x(), y = undistorted.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return {x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
          y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y};
}
// Applies the distortion to ideal normalised coordinates (x', y') → (x'', y''). Inline: the
// stereo matcher calls it for every sample along every epipolar curve.
inline Vec2 DistortNormalized(const Distortion& d, const Vec2& undistorted) {
  if (d.model != LensModel::kPinhole5) return DistortNormalizedGeneral(d, undistorted);
  return DistortPinhole5(d, undistorted);
}
// Jacobian of DistortNormalized with respect to the ideal (x', y').
inline Eigen::Matrix2d DistortNormalizedJacobian(const Distortion& d, const Vec2& undistorted) {
  if (d.model != LensModel::kPinhole5) return DistortNormalizedJacobianGeneral(d, undistorted);
  const double x = undistorted.x(), y = undistorted.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double dradial_dr2 = d.k1 + r2 * (2.0 * d.k2 + 3.0 * r2 * d.k3);
  Eigen::Matrix2d j;
  j(0, 0) = radial + x * dradial_dr2 * 2.0 * x + 2.0 * d.p1 * y + d.p2 * 6.0 * x;
  j(0, 1) = x * dradial_dr2 * 2.0 * y + 2.0 * d.p1 * x + d.p2 * 2.0 * y;
  j(1, 0) = y * dradial_dr2 * 2.0 * x + d.p1 * 2.0 * x + 2.0 * d.p2 * y;
  j(1, 1) = radial + y * dradial_dr2 * 2.0 * y + d.p1 * 6.0 * y + 2.0 * d.p2 * x;
  return j;
}
// Inverts DistortNormalized: the ideal (x', y') whose distorted image is `distorted`. Gauss-Newton
// from the distorted point; converges to ~1e-15 for any lens OpenCV calibrates (|r| < ~1.5; a
// fisheye's field up to its distortion's turning point).
Vec2 UndistortNormalized(const Distortion& d, const Vec2& distorted);
// The same, starting Gauss-Newton from `initial` (e.g. a neighbouring solution): one or two
// iterations instead of four to six.
Vec2 UndistortNormalized(const Distortion& d, const Vec2& distorted, const Vec2& initial);

// Projects a point in the camera frame (Z > 0) to pixel coordinates (cv::projectPoints).
Vec2 ProjectPoint(const CameraIntrinsics& camera, const Vec3& point_in_camera);
// Unit direction, in the camera frame, of the ray that images at `pixel` (cv::undistortPoints,
// then normalised).
Vec3 PixelRay(const CameraIntrinsics& camera, const Vec2& pixel);
// The same, with the ideal normalised coordinates of a nearby pixel as the starting guess.
Vec3 PixelRay(const CameraIntrinsics& camera, const Vec2& pixel, const Vec2& initial_ideal);

}  // namespace ramtk::camera
