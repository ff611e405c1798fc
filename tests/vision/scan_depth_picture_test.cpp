// The depth picture (depth.png of `ramtk scan`): its palette indices against the closed form of a
// depth ramp, its colours against OpenCV's turbo map, its PNG against OpenCV's decoder.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// 17 x 16 pixels; pixel i holds z = 600 - (100 / 254) j with j = i mod 255 (so the range is
// 500 .. 600 mm and pixel i's index is 1 + j), NaN where i mod 13 == 5.
cv::Mat Ramp() {
  cv::Mat z(17, 16, CV_32F);
  for (int i = 0; i < static_cast<int>(z.total()); ++i)
    z.at<float>(i / z.cols, i % z.cols) = i % 13 == 5 ? kNaN : static_cast<float>(600.0 - 100.0 / 254 * (i % 255));
  return z;
}

cv::Vec3b Turbo(int level) {
  cv::Mat grey(1, 1, CV_8U, cv::Scalar(level)), colour;
  cv::applyColorMap(grey, colour, cv::COLORMAP_TURBO);
  return colour.at<cv::Vec3b>(0, 0);
}

TEST(DepthPicture, NearIsTheRedEndFarTheBlueEndNoPointBlack) {
  const cv::Mat z = Ramp();
  const DepthPicture p = DepthPictureOf(z);
  ASSERT_EQ(p.index.type(), CV_8UC1);
  ASSERT_EQ(p.index.size(), z.size());
  ASSERT_EQ(p.palette_bgr.size(), 256u);
  for (int i = 0; i < static_cast<int>(z.total()); ++i) {
    const int expected = i % 13 == 5 ? 0 : 1 + i % 255;
    ASSERT_EQ(p.index.at<uchar>(i / z.cols, i % z.cols), expected) << "pixel " << i;
  }
  EXPECT_EQ(p.palette_bgr[0], cv::Vec3b(0, 0, 0));
  EXPECT_EQ(p.palette_bgr[255], Turbo(255));  // 500 mm, the nearest: the red end
  EXPECT_EQ(p.palette_bgr[1], Turbo(0));      // 600 mm, the farthest: the blue end
  for (int k = 1; k <= 255; ++k)
    EXPECT_EQ(p.palette_bgr[k], Turbo(static_cast<int>(std::lround(255.0 * (k - 1) / 254)))) << "index " << k;
  // Red end: more red than blue.
  EXPECT_GT(Turbo(255)[2], Turbo(255)[0]);
  EXPECT_GT(Turbo(0)[0], Turbo(0)[2]);
}

TEST(DepthPicture, OneDepthOrNoneAtAllStillGiveAPicture) {
  cv::Mat z(3, 4, CV_32F, cv::Scalar(kNaN));
  EXPECT_EQ(cv::countNonZero(DepthPictureOf(z).index), 0);
  z.at<float>(1, 2) = 700;
  z.at<float>(2, 0) = 700;
  const DepthPicture p = DepthPictureOf(z);
  EXPECT_EQ(cv::countNonZero(p.index), 2);
  EXPECT_GE(p.index.at<uchar>(1, 2), 1);
  EXPECT_EQ(p.index.at<uchar>(1, 2), p.index.at<uchar>(2, 0));
}

TEST(DepthPicture, PreviewAndItsPngShowThePalettesColours) {
  const cv::Mat z = Ramp();
  const DepthPicture p = DepthPictureOf(z);
  const cv::Mat bgr = DepthPreview(z);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  const cv::Mat decoded = cv::imdecode(DepthPreviewPng(z), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(decoded.type(), CV_8UC3);
  ASSERT_EQ(decoded.size(), z.size());
  for (int y = 0; y < z.rows; ++y)
    for (int x = 0; x < z.cols; ++x) {
      const cv::Vec3b truth = p.palette_bgr[p.index.at<uchar>(y, x)];
      ASSERT_EQ(bgr.at<cv::Vec3b>(y, x), truth) << x << ", " << y;
      ASSERT_EQ(decoded.at<cv::Vec3b>(y, x), truth) << x << ", " << y;
    }
}

}  // namespace
}  // namespace ramtk::vision
