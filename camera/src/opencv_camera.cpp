#include "ramtk/camera/opencv_camera.h"

#include "ramtk/core/error.h"

namespace ramtk::camera {

cv::Matx33d CameraMatrix(const CameraIntrinsics& c) { return {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}; }

cv::Vec<double, 5> DistortionCoefficients(const CameraIntrinsics& c) {
  const Distortion& d = c.distortion;
  return {d.k1, d.k2, d.p1, d.p2, d.k3};
}

cv::Size ImageSize(const CameraIntrinsics& c) { return {c.width, c.height}; }

CameraIntrinsics IntrinsicsFromOpenCv(const cv::Matx33d& k, const std::vector<double>& d, cv::Size image_size) {
  for (std::size_t i = 5; i < d.size(); ++i) {
    if (d[i] != 0.0)
      throw InputError({"", 0, "distortion"}, "only the 5-coefficient model (k1 k2 p1 p2 k3) is supported");
  }
  CameraIntrinsics c;
  c.fx = k(0, 0);
  c.fy = k(1, 1);
  c.cx = k(0, 2);
  c.cy = k(1, 2);
  auto coefficient = [&](std::size_t i) { return i < d.size() ? d[i] : 0.0; };
  c.distortion = {coefficient(0), coefficient(1), coefficient(2), coefficient(3), coefficient(4)};
  c.width = image_size.width;
  c.height = image_size.height;
  return c;
}

}  // namespace ramtk::camera
