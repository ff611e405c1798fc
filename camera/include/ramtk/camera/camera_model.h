#pragma once
// Pinhole camera with OpenCV's 5-coefficient distortion (k1, k2, p1, p2, k3).
//
// Conventions (the same as OpenCV's calib3d):
//  * Camera frame: x right, y down, z forward (optical axis); millimetres.
//  * Pixel coordinates: the centre of the top-left pixel is (0, 0); u grows to the right, v down.
//  * Projection (cv::projectPoints): x' = X/Z, y' = Y/Z; r² = x'² + y'²;
//      x'' = x'(1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x'y' + p2 (r² + 2x'²)
//      y'' = y'(1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2y'²) + 2 p2 x'y'
//      u = fx x'' + cx,  v = fy y'' + cy.
//  * Back-projection inverts the distortion with Gauss-Newton to machine precision (OpenCV's
//    cv::undistortPoints runs a fixed number of fixed-point iterations by default).

#include <Eigen/Core>

#include "ramtk/core/rotation.h"

namespace ramtk::camera {

using Vec2 = Eigen::Vector2d;

// OpenCV distortion coefficients, in OpenCV's order (k1, k2, p1, p2, k3).
struct Distortion {
  double k1 = 0.0;  // radial, r²
  double k2 = 0.0;  // radial, r⁴
  double p1 = 0.0;  // tangential
  double p2 = 0.0;  // tangential
  double k3 = 0.0;  // radial, r⁶
  bool IsZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
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

  // The 3×3 camera matrix K.
  Mat3 K() const;
};

// Applies the distortion to ideal normalised coordinates (x', y') → (x'', y''). Inline: the
// stereo matcher calls it for every sample along every epipolar curve.
inline Vec2 DistortNormalized(const Distortion& d, const Vec2& undistorted) {
  const double x = undistorted.x(), y = undistorted.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return {x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
          y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y};
}
// Jacobian of DistortNormalized with respect to the ideal (x', y').
inline Eigen::Matrix2d DistortNormalizedJacobian(const Distortion& d, const Vec2& undistorted) {
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
// from the distorted point; converges to ~1e-15 for any lens OpenCV calibrates (|r| < ~1.5).
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
