// The rational / thin-prism / tilt and fisheye lens models (camera_model.h): OpenCV's formulas
// (cv::projectPoints, cv::fisheye::projectPoints) and their analytic Jacobians.
#include <cmath>

#include "ramtk/camera/camera_model.h"

namespace ramtk::camera {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

// OpenCV's computeTiltProjectionMatrix(τx, τy): the sensor tilt as a homography of the distorted
// normalised plane.
Eigen::Matrix3d TiltMatrix(const Distortion& d) {
  const double tx = d.tilt_x_deg * kRadPerDeg, ty = d.tilt_y_deg * kRadPerDeg;
  const double cx = std::cos(tx), sx = std::sin(tx), cy = std::cos(ty), sy = std::sin(ty);
  Eigen::Matrix3d rot_x, rot_y, proj_z;
  rot_x << 1, 0, 0, 0, cx, sx, 0, -sx, cx;
  rot_y << cy, 0, -sy, 0, 1, 0, sy, 0, cy;
  const Eigen::Matrix3d rot_xy = rot_y * rot_x;
  proj_z << rot_xy(2, 2), 0, -rot_xy(0, 2), 0, rot_xy(2, 2), -rot_xy(1, 2), 0, 0, 1;
  return proj_z * rot_xy;
}

bool Tilted(const Distortion& d) { return d.tilt_x_deg != 0.0 || d.tilt_y_deg != 0.0; }

// The rational model before the tilt, and (if `jac`) its Jacobian.
Vec2 RationalUntilted(const Distortion& d, const Vec2& p, Eigen::Matrix2d* jac) {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double num = 1.0 + d.k1 * r2 + d.k2 * r4 + d.k3 * r6;
  const double den = 1.0 + d.k4 * r2 + d.k5 * r4 + d.k6 * r6;
  const double inv_den = 1.0 / den;
  const double radial = num * inv_den;
  const Vec2 out(x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x) + d.s1 * r2 + d.s2 * r4,
                 y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y + d.s3 * r2 + d.s4 * r4);
  if (jac != nullptr) {
    const double dnum = d.k1 + 2.0 * d.k2 * r2 + 3.0 * d.k3 * r4;
    const double dden = d.k4 + 2.0 * d.k5 * r2 + 3.0 * d.k6 * r4;
    const double dradial = (dnum * den - num * dden) * inv_den * inv_den;             // d radial / d r²
    const double prism_x = d.s1 + 2.0 * d.s2 * r2, prism_y = d.s3 + 2.0 * d.s4 * r2;  // d / d r²
    Eigen::Matrix2d& j = *jac;
    j(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * d.p1 * y + 6.0 * d.p2 * x + 2.0 * x * prism_x;
    j(0, 1) = 2.0 * x * y * dradial + 2.0 * d.p1 * x + 2.0 * d.p2 * y + 2.0 * y * prism_x;
    j(1, 0) = 2.0 * x * y * dradial + 2.0 * d.p1 * x + 2.0 * d.p2 * y + 2.0 * x * prism_y;
    j(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * d.p1 * y + 2.0 * d.p2 * x + 2.0 * y * prism_y;
  }
  return out;
}

Vec2 Rational(const Distortion& d, const Vec2& p, Eigen::Matrix2d* jac) {
  const Vec2 q = RationalUntilted(d, p, jac);
  if (!Tilted(d)) return q;
  const Eigen::Matrix3d m = TiltMatrix(d);
  const Eigen::Vector3d v = m * Eigen::Vector3d(q.x(), q.y(), 1.0);
  const double inv = v.z() != 0.0 ? 1.0 / v.z() : 1.0;
  if (jac != nullptr) {
    Eigen::Matrix2d t;  // d (v0 / v2, v1 / v2) / d (q0, q1)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) t(i, j) = (m(i, j) - v(i) * inv * m(2, j)) * inv;
    *jac = t * *jac;
  }
  return {v.x() * inv, v.y() * inv};
}

Vec2 Fisheye(const Distortion& d, const Vec2& p, Eigen::Matrix2d* jac) {
  const double r = p.norm();
  const double theta = std::atan(r);
  const double t2 = theta * theta;
  const double poly = 1.0 + t2 * (d.k1 + t2 * (d.k2 + t2 * (d.k3 + t2 * d.k4)));
  const double theta_d = theta * poly;
  // cv::fisheye::projectPoints takes the scale as 1 below r = 1e-8 (its limit at the axis).
  const double scale = r > 1e-8 ? theta_d / r : 1.0;
  if (jac != nullptr) {
    *jac = scale * Eigen::Matrix2d::Identity();
    if (r > 1e-8) {
      const double dtheta_d = 1.0 + t2 * (3.0 * d.k1 + t2 * (5.0 * d.k2 + t2 * (7.0 * d.k3 + t2 * 9.0 * d.k4)));
      const double dscale_dr = (dtheta_d / (1.0 + r * r) - scale) / r;
      *jac += (dscale_dr / r) * p * p.transpose();
    }
  }
  return scale * p;
}

}  // namespace

const char* LensModelName(LensModel model) {
  switch (model) {
    case LensModel::kRational:
      return "rational";
    case LensModel::kFisheye:
      return "fisheye";
    case LensModel::kPinhole5:
    default:
      return "pinhole5";
  }
}

bool ParseLensModel(const std::string& name, LensModel* model) {
  if (name == "pinhole5" || name == "plumb_bob") {
    *model = LensModel::kPinhole5;
  } else if (name == "rational" || name == "thin-prism" || name == "rational_polynomial") {
    *model = LensModel::kRational;
  } else if (name == "fisheye" || name == "equidistant") {
    *model = LensModel::kFisheye;
  } else {
    return false;
  }
  return true;
}

Vec2 DistortNormalizedGeneral(const Distortion& d, const Vec2& undistorted) {
  switch (d.model) {
    case LensModel::kFisheye:
      return Fisheye(d, undistorted, nullptr);
    case LensModel::kRational:
      return Rational(d, undistorted, nullptr);
    case LensModel::kPinhole5:
    default:
      return DistortPinhole5(d, undistorted);
  }
}

Eigen::Matrix2d DistortNormalizedJacobianGeneral(const Distortion& d, const Vec2& undistorted) {
  Eigen::Matrix2d j;
  if (d.model == LensModel::kFisheye) {
    Fisheye(d, undistorted, &j);
  } else {
    Rational(d, undistorted, &j);  // the 5-coefficient model is its special case
  }
  return j;
}

}  // namespace ramtk::camera
