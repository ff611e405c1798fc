#include "ramtk/core/rotation.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace ramtk {
namespace {
// Below this value of cos(b) (KUKA) or sin(b) (ZXZ) the first and third angles are coupled.
constexpr double kGimbalEps = 1e-12;
}  // namespace

Mat3 RotX(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

Mat3 RotY(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}

Mat3 RotZ(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

Mat3 RotationFromKukaAbc(const KukaAbc& abc) { return RotZ(abc.a) * RotY(abc.b) * RotX(abc.c); }

KukaAbc KukaAbcFromRotation(const Mat3& r) {
  KukaAbc out;
  const double cb = std::hypot(r(0, 0), r(1, 0));
  out.b = std::atan2(-r(2, 0), cb);
  if (cb > kGimbalEps) {
    out.a = std::atan2(r(1, 0), r(0, 0));
    out.c = std::atan2(r(2, 1), r(2, 2));
  } else {  // R = RotZ(a)·RotY(±pi/2) with c := 0
    out.a = std::atan2(-r(0, 1), r(1, 1));
    out.c = 0.0;
  }
  return out;
}

Mat3 RotationFromEulerZxz(const EulerZxz& zxz) { return RotZ(zxz.a) * RotX(zxz.b) * RotZ(zxz.c); }

EulerZxz EulerZxzFromRotation(const Mat3& r) {
  EulerZxz out;
  const double sb = std::hypot(r(0, 2), r(1, 2));
  out.b = std::atan2(sb, r(2, 2));
  if (sb > kGimbalEps) {
    out.a = std::atan2(r(0, 2), -r(1, 2));
    out.c = std::atan2(r(2, 0), r(2, 1));
  } else {  // R = RotZ(a)·RotX(0 or pi) with c := 0
    out.a = std::atan2(r(1, 0), r(0, 0));
    out.c = 0.0;
  }
  return out;
}

double RotationAngleBetween(const Mat3& a, const Mat3& b) {
  return LogSO3(a.transpose() * b).norm();
}

Mat3 ExpSO3(const Vec3& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

Vec3 LogSO3(const Mat3& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.axis() * aa.angle();
}

Mat3 NearestRotation(const Mat3& m) {
  Eigen::JacobiSVD<Mat3> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 d = Mat3::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

Mat3 Skew(const Vec3& v) {
  Mat3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

double OrthonormalityError(const Mat3& rotation) {
  const double ortho = (rotation.transpose() * rotation - Mat3::Identity()).cwiseAbs().maxCoeff();
  return std::max(ortho, std::abs(rotation.determinant() - 1.0));
}

}  // namespace ramtk
