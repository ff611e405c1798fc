#include "ramtk/camera/camera_model.h"

#include <cmath>

namespace ramtk::camera {

std::string SamplingKernel::Validate() const {
  if (!(fill_factor >= 0.0 && fill_factor <= 1.0)) return "fill_factor: must be in [0, 1]";
  if (!(psf_sigma_px >= 0.0 && psf_sigma_px <= 10.0)) return "psf_sigma_px: must be in [0, 10] px";
  return "";
}

Mat3 CameraIntrinsics::K() const {
  Mat3 k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

Vec2 UndistortNormalized(const Distortion& d, const Vec2& distorted, const Vec2& initial) {
  if (d.IsZero()) return distorted;
  Vec2 p = initial;
  for (int iter = 0; iter < 30; ++iter) {
    const Vec2 residual = DistortNormalized(d, p) - distorted;
    if (residual.lpNorm<Eigen::Infinity>() < 1e-15) break;
    const Eigen::Matrix2d j = DistortNormalizedJacobian(d, p);
    const double det = j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0);
    p.x() -= (j(1, 1) * residual.x() - j(0, 1) * residual.y()) / det;
    p.y() -= (j(0, 0) * residual.y() - j(1, 0) * residual.x()) / det;
  }
  return p;
}

Vec2 UndistortNormalized(const Distortion& d, const Vec2& distorted) {
  return UndistortNormalized(d, distorted, distorted);
}

Vec2 ProjectPoint(const CameraIntrinsics& c, const Vec3& point) {
  const Vec2 ideal(point.x() / point.z(), point.y() / point.z());
  const Vec2 dist = DistortNormalized(c.distortion, ideal);
  return {c.fx * dist.x() + c.cx, c.fy * dist.y() + c.cy};
}

Vec3 PixelRay(const CameraIntrinsics& c, const Vec2& pixel, const Vec2& initial_ideal) {
  const Vec2 distorted((pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy);
  const Vec2 ideal = UndistortNormalized(c.distortion, distorted, initial_ideal);
  return Vec3(ideal.x(), ideal.y(), 1.0).normalized();
}

Vec3 PixelRay(const CameraIntrinsics& c, const Vec2& pixel) {
  return PixelRay(c, pixel, Vec2((pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy));
}

}  // namespace ramtk::camera
