#include "ramtk/camera/opencv_camera.h"

#include <opencv2/calib3d.hpp>

#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

}  // namespace

cv::Matx33d CameraMatrix(const CameraIntrinsics& c) { return {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}; }

cv::Vec<double, 5> DistortionCoefficients(const CameraIntrinsics& c) {
  const Distortion& d = c.distortion;
  if (d.model != LensModel::kPinhole5)
    throw InputError({"", 0, "distortion"},
                     std::string("the ") + LensModelName(d.model) + " lens model has no 5-coefficient vector");
  return {d.k1, d.k2, d.p1, d.p2, d.k3};
}

cv::Size ImageSize(const CameraIntrinsics& c) { return {c.width, c.height}; }

std::vector<double> DistortionVector(const Distortion& d) {
  if (d.model == LensModel::kFisheye) return {d.k1, d.k2, d.k3, d.k4};
  if (d.model == LensModel::kPinhole5) return {d.k1, d.k2, d.p1, d.p2, d.k3};
  std::vector<double> v{d.k1, d.k2, d.p1, d.p2, d.k3, d.k4, d.k5, d.k6};
  if (d.s1 != 0 || d.s2 != 0 || d.s3 != 0 || d.s4 != 0 || d.tilt_x_deg != 0 || d.tilt_y_deg != 0)
    v.insert(v.end(), {d.s1, d.s2, d.s3, d.s4});
  if (d.tilt_x_deg != 0 || d.tilt_y_deg != 0) v.insert(v.end(), {d.tilt_x_deg * kRadPerDeg, d.tilt_y_deg * kRadPerDeg});
  return v;
}

std::string DistortionFromVector(const std::vector<double>& c, LensModel model, Distortion* distortion) {
  Distortion d;
  const std::size_t n = c.size();
  if (model == LensModel::kFisheye) {
    if (n != 4) return "the fisheye model takes 4 coefficients (k1 k2 k3 k4), got " + std::to_string(n);
    d.model = LensModel::kFisheye;
    d.k1 = c[0], d.k2 = c[1], d.k3 = c[2], d.k4 = c[3];
    *distortion = d;
    return "";
  }
  if (n > 14 || (n > 5 && n != 8 && n != 12 && n != 14))
    return "expected 4, 5, 8, 12 or 14 distortion coefficients, got " + std::to_string(n);
  auto at = [&](std::size_t i) { return i < n ? c[i] : 0.0; };
  d.k1 = at(0), d.k2 = at(1), d.p1 = at(2), d.p2 = at(3), d.k3 = at(4);
  d.k4 = at(5), d.k5 = at(6), d.k6 = at(7);
  d.s1 = at(8), d.s2 = at(9), d.s3 = at(10), d.s4 = at(11);
  d.tilt_x_deg = at(12) / kRadPerDeg, d.tilt_y_deg = at(13) / kRadPerDeg;
  bool extra = false;
  for (std::size_t i = 5; i < n; ++i) extra = extra || c[i] != 0.0;
  d.model = extra ? LensModel::kRational : LensModel::kPinhole5;
  *distortion = d;
  return "";
}

std::vector<cv::Point2d> ProjectPointsOpenCv(const std::vector<cv::Point3d>& points, const cv::Vec3d& rvec,
                                             const cv::Vec3d& tvec, const CameraIntrinsics& camera) {
  std::vector<cv::Point2d> out;
  if (points.empty()) return out;
  const std::vector<double> d = DistortionVector(camera.distortion);
  if (camera.distortion.model == LensModel::kFisheye) {
    cv::fisheye::projectPoints(points, out, rvec, tvec, CameraMatrix(camera), d);
  } else {
    cv::projectPoints(points, rvec, tvec, CameraMatrix(camera), d, out);
  }
  return out;
}

CameraIntrinsics IntrinsicsFromOpenCv(const cv::Matx33d& k, const std::vector<double>& d, cv::Size image_size,
                                      LensModel model) {
  CameraIntrinsics c;
  const std::string error = DistortionFromVector(d, model, &c.distortion);
  if (!error.empty()) throw InputError({"", 0, "distortion"}, error);
  c.fx = k(0, 0);
  c.fy = k(1, 1);
  c.cx = k(0, 2);
  c.cy = k(1, 2);
  c.width = image_size.width;
  c.height = image_size.height;
  return c;
}

}  // namespace ramtk::camera
