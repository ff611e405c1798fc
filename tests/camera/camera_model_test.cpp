// Camera model against OpenCV as the peer: projection vs cv::projectPoints, back-projection vs
// cv::undistortPoints (run to convergence), and the round trip pixel → ray → pixel.
#include "ramtk/camera/camera_model.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>

namespace ramtk::camera {
namespace {

CameraIntrinsics TestCamera(const Distortion& d) {
  CameraIntrinsics c;
  c.fx = 1753.03;
  c.fy = 1753.07;
  c.cx = 639.2;
  c.cy = 511.5;
  c.width = 1280;
  c.height = 1024;
  c.distortion = d;
  return c;
}

std::vector<Distortion> TestDistortions() {
  return {Distortion{}, Distortion{6.26e-4, -3.07e-2, -7.03e-5, -1.24e-4, 1.51e-1},  // caliInfo.yml D1
          Distortion{-0.12, 0.08, 1e-3, -2e-3, -0.02},                               // a stronger wide-angle lens
          Distortion{0.2, -0.3, -1.5e-3, 8e-4, 0.5}};
}

// The analytic Jacobian of the lens model (used for the matcher's epipolar tangent and sigma)
// against central differences: step 1e-6 in normalised coordinates, truncation ~1e-12, rounding
// ~1e-10 relative, so 1e-7 is far above both and far below any error in a term.
TEST(SimCameraModel, DistortionJacobianMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(-0.6, 0.6);
  for (const Distortion& d : TestDistortions()) {
    for (int i = 0; i < 50; ++i) {
      const Vec2 p(xy(rng), xy(rng));
      const Eigen::Matrix2d j = DistortNormalizedJacobian(d, p);
      const double h = 1e-6;
      for (int c = 0; c < 2; ++c) {
        Vec2 e = Vec2::Zero();
        e[c] = h;
        const Vec2 fd = (DistortNormalized(d, p + e) - DistortNormalized(d, p - e)) / (2 * h);
        EXPECT_NEAR(j(0, c), fd.x(), 1e-7);
        EXPECT_NEAR(j(1, c), fd.y(), 1e-7);
      }
    }
  }
}

TEST(SimCameraModel, ProjectionMatchesCvProjectPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-250.0, 250.0), z(500.0, 900.0);
  for (const Distortion& d : TestDistortions()) {
    const CameraIntrinsics cam = TestCamera(d);
    std::vector<cv::Point3d> pts;
    for (int i = 0; i < 200; ++i) pts.emplace_back(xy(rng), xy(rng) * 0.8, z(rng));
    cv::Mat k = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
    cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
    std::vector<cv::Point2d> cv_px;
    cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist, cv_px);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2 px = ProjectPoint(cam, Vec3(pts[i].x, pts[i].y, pts[i].z));
      // Both evaluate the same polynomial in double precision: agreement to ~1e-12 px.
      EXPECT_NEAR(px.x(), cv_px[i].x, 1e-9);
      EXPECT_NEAR(px.y(), cv_px[i].y, 1e-9);
    }
  }
}

TEST(SimCameraModel, BackProjectionMatchesCvUndistortPointsAndRoundTrips) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1279.0), v(0.0, 1023.0);
  for (const Distortion& d : TestDistortions()) {
    const CameraIntrinsics cam = TestCamera(d);
    std::vector<cv::Point2d> px;
    for (int i = 0; i < 200; ++i) px.emplace_back(u(rng), v(rng));
    px.emplace_back(0.0, 0.0);
    px.emplace_back(1279.0, 1023.0);
    cv::Mat k = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
    cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
    std::vector<cv::Point2d> ideal;
    // OpenCV's iteration run long enough to converge (its default of 5 iterations does not).
    cv::undistortPoints(px, ideal, k, dist, cv::noArray(), cv::noArray(),
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-16));
    for (std::size_t i = 0; i < px.size(); ++i) {
      const Vec3 ray = PixelRay(cam, Vec2(px[i].x, px[i].y));
      EXPECT_NEAR(ray.norm(), 1.0, 1e-15);
      // Normalised coordinates agree to 1e-10 (≈ 2e-7 px at f = 1753).
      EXPECT_NEAR(ray.x() / ray.z(), ideal[i].x, 1e-10);
      EXPECT_NEAR(ray.y() / ray.z(), ideal[i].y, 1e-10);
      // Round trip: a point on the ray projects back onto the pixel.
      const Vec2 back = ProjectPoint(cam, 700.0 * ray);
      EXPECT_NEAR(back.x(), px[i].x, 1e-9);
      EXPECT_NEAR(back.y(), px[i].y, 1e-9);
    }
  }
}

}  // namespace
}  // namespace ramtk::camera
