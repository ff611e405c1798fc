// The rational / thin-prism / tilt and fisheye lens models against OpenCV as the peer:
// projection vs cv::projectPoints and cv::fisheye::projectPoints on random points and random
// coefficients (fixed seeds), back-projection round trips, analytic Jacobians vs central
// differences, and the calibration files that carry the models (YAML, JSON, XML).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>

#include "ramtk/camera/camera_model.h"
#include "ramtk/camera/opencv_camera.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

CameraIntrinsics TestCamera(const Distortion& d) {
  CameraIntrinsics c;
  c.fx = 1210.5;
  c.fy = 1208.25;
  c.cx = 963.7;
  c.cy = 601.2;
  c.width = 1928;
  c.height = 1208;
  c.distortion = d;
  return c;
}

// A random rational lens of `n` coefficients (8, 12 or 14): magnitudes of real wide-angle
// calibrations, the denominator kept away from zero over the test points.
Distortion RandomRational(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> c = {0.15 * u(rng), 0.05 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng),
                           0.02 * u(rng), 0.1 * u(rng),  0.03 * u(rng), 0.01 * u(rng)};
  if (n >= 12)
    for (int i = 0; i < 4; ++i) c.push_back(2e-3 * u(rng));
  if (n >= 14)
    for (int i = 0; i < 2; ++i) c.push_back(0.02 * u(rng));  // radians
  Distortion d;
  EXPECT_EQ(DistortionFromVector(c, LensModel::kRational, &d), "");
  EXPECT_EQ(d.model, LensModel::kRational);
  return d;
}

Distortion RandomFisheye(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Distortion d;
  EXPECT_EQ(
      DistortionFromVector({0.05 * u(rng), 0.01 * u(rng), 0.005 * u(rng), 0.001 * u(rng)}, LensModel::kFisheye, &d),
      "");
  return d;
}

std::vector<Distortion> TestLenses() {
  std::mt19937 rng(49);
  std::vector<Distortion> lenses;
  for (int i = 0; i < 4; ++i) {
    lenses.push_back(RandomRational(rng, 8));
    lenses.push_back(RandomRational(rng, 12));
    lenses.push_back(RandomRational(rng, 14));
    lenses.push_back(RandomFisheye(rng));
  }
  return lenses;
}

// Points in front of the camera: up to ~31° off axis for the rational model (|x'| < 0.6), up to
// ~75° for the fisheye model.
std::vector<cv::Point3d> RandomPoints(std::mt19937& rng, LensModel model, int n) {
  const double half = model == LensModel::kFisheye ? 2.5 : 0.6;
  std::uniform_real_distribution<double> xy(-half, half), z(300.0, 2000.0);
  std::vector<cv::Point3d> pts;
  for (int i = 0; i < n; ++i) {
    const double depth = z(rng);
    pts.emplace_back(xy(rng) * depth, xy(rng) * depth, depth);
  }
  return pts;
}

TEST(CameraLensModels, ProjectionMatchesOpenCvTo1e9Px) {
  std::mt19937 rng(5);
  for (const Distortion& d : TestLenses()) {
    const CameraIntrinsics cam = TestCamera(d);
    const std::vector<cv::Point3d> pts = RandomPoints(rng, d.model, 300);
    std::vector<cv::Point2d> cv_px;
    const cv::Mat k(CameraMatrix(cam));
    const std::vector<double> coefficients = DistortionVector(d);
    if (d.model == LensModel::kFisheye) {
      cv::fisheye::projectPoints(pts, cv_px, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, coefficients);
    } else {
      cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, coefficients, cv_px);
    }
    const std::vector<cv::Point2d> helper = ProjectPointsOpenCv(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2 px = ProjectPoint(cam, Vec3(pts[i].x, pts[i].y, pts[i].z));
      EXPECT_NEAR(px.x(), cv_px[i].x, 1e-9) << LensModelName(d.model) << " " << i;
      EXPECT_NEAR(px.y(), cv_px[i].y, 1e-9) << LensModelName(d.model) << " " << i;
      EXPECT_EQ(helper[i], cv_px[i]);
    }
  }
}

// Back-projection inverts projection: the ray of a point's pixel projects back onto the pixel
// (1e-9 px) and is the point's direction; the undistortion recovers distorted ideal points.
TEST(CameraLensModels, UndistortThenDistortIsTheIdentity) {
  std::mt19937 rng(17);
  for (const Distortion& d : TestLenses()) {
    const CameraIntrinsics cam = TestCamera(d);
    for (const cv::Point3d& p : RandomPoints(rng, d.model, 300)) {
      const Vec3 point(p.x, p.y, p.z);
      const Vec2 pixel = ProjectPoint(cam, point);
      const Vec3 ray = PixelRay(cam, pixel);
      EXPECT_NEAR(ray.norm(), 1.0, 1e-15);
      EXPECT_NEAR((ray - point.normalized()).norm(), 0.0, 1e-12) << LensModelName(d.model);
      const Vec2 back = ProjectPoint(cam, 800.0 * ray);
      EXPECT_NEAR(back.x(), pixel.x(), 1e-9) << LensModelName(d.model);
      EXPECT_NEAR(back.y(), pixel.y(), 1e-9) << LensModelName(d.model);
    }
    std::uniform_real_distribution<double> xy(-0.5, 0.5);
    for (int i = 0; i < 100; ++i) {
      const Vec2 ideal(xy(rng), xy(rng));
      const Vec2 again = UndistortNormalized(d, DistortNormalized(d, ideal));
      EXPECT_NEAR(again.x(), ideal.x(), 1e-13);
      EXPECT_NEAR(again.y(), ideal.y(), 1e-13);
    }
  }
}

// OpenCV's own inverses (run to convergence) as a second peer of the back-projection.
TEST(CameraLensModels, BackProjectionMatchesOpenCvUndistortPoints) {
  std::mt19937 rng(23);
  for (const Distortion& d : TestLenses()) {
    if (d.tilt_x_deg != 0.0) continue;  // cv::undistortPoints' fixed-point iteration stalls on some tilts
    const CameraIntrinsics cam = TestCamera(d);
    std::vector<cv::Point2d> px;
    for (const cv::Point3d& p : RandomPoints(rng, LensModel::kPinhole5, 100)) {
      const Vec2 pixel = ProjectPoint(cam, Vec3(p.x, p.y, p.z));
      px.emplace_back(pixel.x(), pixel.y());
    }
    std::vector<cv::Point2d> ideal;
    const cv::TermCriteria until(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-16);
    if (d.model == LensModel::kFisheye) {
      // cv::fisheye::undistortPoints marks a point it did not converge on as -1e6: its Newton
      // step on θ must fall below eps, which 1e-16 never does for some points; 1e-14 leaves the
      // step after it at ~1e-28.
      const cv::TermCriteria newton(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-14);
      cv::fisheye::undistortPoints(px, ideal, cv::Mat(CameraMatrix(cam)), DistortionVector(d), cv::noArray(),
                                   cv::noArray(), newton);
    } else {
      cv::undistortPoints(px, ideal, cv::Mat(CameraMatrix(cam)), DistortionVector(d), cv::noArray(), cv::noArray(),
                          until);
    }
    for (std::size_t i = 0; i < px.size(); ++i) {
      const Vec3 ray = PixelRay(cam, Vec2(px[i].x, px[i].y));
      EXPECT_NEAR(ray.x() / ray.z(), ideal[i].x, 1e-9) << LensModelName(d.model);
      EXPECT_NEAR(ray.y() / ray.z(), ideal[i].y, 1e-9) << LensModelName(d.model);
    }
  }
}

// Analytic Jacobians vs central differences: step 1e-6, truncation ~1e-12, rounding ~1e-10.
TEST(CameraLensModels, JacobianMatchesFiniteDifferences) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> xy(-0.6, 0.6);
  std::vector<Distortion> lenses = TestLenses();
  lenses.push_back(Distortion{});
  lenses.back().model = LensModel::kFisheye;  // the fisheye's θ alone
  for (const Distortion& d : lenses) {
    for (int i = 0; i < 50; ++i) {
      const Vec2 p = i == 0 ? Vec2(1e-9, -2e-9) : Vec2(xy(rng), xy(rng));
      const Eigen::Matrix2d j = DistortNormalizedJacobian(d, p);
      const double h = 1e-6;
      for (int c = 0; c < 2; ++c) {
        Vec2 e = Vec2::Zero();
        e[c] = h;
        const Vec2 fd = (DistortNormalized(d, p + e) - DistortNormalized(d, p - e)) / (2 * h);
        EXPECT_NEAR(j(0, c), fd.x(), 1e-7) << LensModelName(d.model);
        EXPECT_NEAR(j(1, c), fd.y(), 1e-7) << LensModelName(d.model);
      }
    }
  }
}

// The 5-coefficient model named "rational" is the same lens: extra coefficients that are all zero
// read as the 5-coefficient model (the scan's fast path), and the rational formula agrees with it.
TEST(CameraLensModels, RationalWithZeroExtrasIsTheFiveCoefficientModel) {
  Distortion d;
  ASSERT_EQ(DistortionFromVector({-0.1, 0.05, 1e-3, -2e-3, 0.01, 0, 0, 0}, LensModel::kRational, &d), "");
  EXPECT_EQ(d.model, LensModel::kPinhole5);
  EXPECT_EQ(DistortionVector(d).size(), 5u);
  Distortion general = d;
  general.model = LensModel::kRational;
  for (double x : {-0.5, -0.1, 0.3}) {
    const Vec2 p(x, 0.7 * x + 0.05);
    EXPECT_NEAR((DistortNormalized(general, p) - DistortNormalized(d, p)).norm(), 0.0, 1e-15);
  }
  EXPECT_NE(DistortionFromVector({0.1, 0.2, 0.3}, LensModel::kFisheye, &d), "");
  EXPECT_NE(DistortionFromVector(std::vector<double>(9, 0.0), LensModel::kRational, &d), "");
  ASSERT_EQ(DistortionFromVector({0.01, -0.002, 0.0, 0.0}, LensModel::kFisheye, &d), "");
  EXPECT_THROW(DistortionCoefficients(TestCamera(d)), InputError);
}

}  // namespace
}  // namespace ramtk::camera
