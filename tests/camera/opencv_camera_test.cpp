// The camera model in OpenCV's types: K and the coefficients round-trip, and a point projected
// with cv::projectPoints from the converted K and coefficients lands where ProjectPoint puts it.
#include "ramtk/camera/opencv_camera.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include "ramtk/core/error.h"

namespace ramtk::camera {
namespace {

TEST(OpenCvCamera, ConversionsRoundTripAndProjectLikeOpenCv) {
  const cv::Matx33d k(1510.5, 0, 655.25, 0, 1508.75, 498.5, 0, 0, 1);
  const std::vector<double> d = {-0.11, 0.07, 4e-4, -3e-4, 0.01};
  const CameraIntrinsics c = IntrinsicsFromOpenCv(k, d, cv::Size(1280, 1024));
  EXPECT_EQ(CameraMatrix(c), k);
  const cv::Vec<double, 5> back = DistortionCoefficients(c);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(back[i], d[i]);
  EXPECT_EQ(ImageSize(c), cv::Size(1280, 1024));
  const Vec3 x_in_camera(35.0, -22.0, 480.0);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(std::vector<cv::Point3d>{{x_in_camera.x(), x_in_camera.y(), x_in_camera.z()}}, cv::Vec3d(0, 0, 0),
                    cv::Vec3d(0, 0, 0), CameraMatrix(c), back, projected);
  const Vec2 ours = ProjectPoint(c, x_in_camera);
  // OpenCV projects in double precision: agreement to rounding of a ~1000 px coordinate.
  EXPECT_NEAR(projected[0].x, ours.x(), 1e-9);
  EXPECT_NEAR(projected[0].y, ours.y(), 1e-9);
}

TEST(OpenCvCamera, FewerCoefficientsAreZeroAndExtraTermsAreTheRationalModel) {
  const cv::Matx33d k(1000, 0, 320, 0, 1000, 240, 0, 0, 1);
  const CameraIntrinsics four = IntrinsicsFromOpenCv(k, {0.1, 0.2, 0.3, 0.4}, cv::Size(640, 480));
  EXPECT_EQ(four.distortion.k3, 0.0);
  EXPECT_EQ(four.distortion.p2, 0.4);
  EXPECT_NO_THROW(IntrinsicsFromOpenCv(k, {0.1, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, cv::Size(640, 480)));
  EXPECT_EQ(IntrinsicsFromOpenCv(k, {0.1, 0.2, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0}, cv::Size(640, 480)).distortion.model,
            LensModel::kRational);
  EXPECT_THROW(IntrinsicsFromOpenCv(k, {0.1, 0.2, 0.0, 0.0, 0.0, 0.5, 0.0}, cv::Size(640, 480)), InputError);
}

}  // namespace
}  // namespace ramtk::camera
