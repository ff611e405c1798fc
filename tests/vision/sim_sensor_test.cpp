// The camera sensor against its configured statistics: the variance of repeated exposures against
// shot noise (variance = signal in electrons) + read noise + quantisation, saturation, and the
// defocus blur's step response against the Gaussian error function.
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/vision/sim/fringe_renderer.h"

namespace ramtk::vision {
namespace {

TEST(SimSensor, NoiseVarianceMatchesShotPlusReadNoise) {
  SensorOptions o;
  o.bits = 16;
  o.full_well_electrons = 10000;
  o.read_noise_electrons = 12;
  const int repeats = 8;
  for (double radiance : {0.8, 0.05}) {
    const cv::Mat flat(300, 400, CV_32F, cv::Scalar(radiance));
    std::vector<cv::Mat> shots;
    for (int seed = 1; seed <= repeats; ++seed) {
      cv::Mat img;
      ApplySensor(flat, 1.0, o, seed, 7).convertTo(img, CV_64F);
      shots.push_back(img);
    }
    double var_sum = 0.0, mean_sum = 0.0;
    for (int v = 0; v < flat.rows; ++v) {
      for (int u = 0; u < flat.cols; ++u) {
        double m = 0.0, q = 0.0;
        for (const cv::Mat& s : shots) m += s.at<double>(v, u);
        m /= repeats;
        for (const cv::Mat& s : shots) q += std::pow(s.at<double>(v, u) - m, 2);
        var_sum += q / (repeats - 1);
        mean_sum += m;
      }
    }
    const double n = flat.total();
    const double max = 65535.0, dn_per_e = max / o.full_well_electrons;
    const double mean_dn = o.exposure * radiance * max;
    const double expected_var =
        mean_dn * dn_per_e + std::pow(o.read_noise_electrons * dn_per_e, 2) + 1.0 / 12.0;  // + rounding
    // The pooled variance of n pixels × 7 degrees of freedom has a relative std of sqrt(2/(7n))
    // ≈ 0.15 %; 1 % is > 6σ.
    EXPECT_NEAR(var_sum / n / expected_var, 1.0, 0.01) << "radiance " << radiance;
    // Unbiased: the mean of n·repeats samples is within 6σ of the expected DN.
    EXPECT_NEAR(mean_sum / n, mean_dn, 6.0 * std::sqrt(expected_var / (n * repeats)));
  }
}

TEST(SimSensor, NoiseIsUncorrelatedBetweenNeighbours) {
  SensorOptions o;
  o.bits = 16;
  const cv::Mat flat(256, 256, CV_32F, cv::Scalar(0.5));
  cv::Mat img;
  ApplySensor(flat, 1.0, o, 42, 0).convertTo(img, CV_64F);
  const double mean = cv::mean(img)[0];
  double c_row = 0, c_col = 0, var = 0;
  for (int v = 0; v + 1 < img.rows; ++v)
    for (int u = 0; u + 1 < img.cols; ++u) {
      const double a = img.at<double>(v, u) - mean;
      var += a * a;
      c_row += a * (img.at<double>(v, u + 1) - mean);
      c_col += a * (img.at<double>(v + 1, u) - mean);
    }
  // 65k pairs: the std of a zero correlation estimate is 1/sqrt(65k) ≈ 0.004.
  EXPECT_NEAR(c_row / var, 0.0, 0.025);
  EXPECT_NEAR(c_col / var, 0.0, 0.025);
}

TEST(SimSensor, SaturationClipsAtFullScaleAndDarkAtZero) {
  SensorOptions o;
  o.bits = 12;
  const cv::Mat bright(64, 64, CV_32F, cv::Scalar(2.0));  // 1.8× full scale
  const cv::Mat img = ApplySensor(bright, 1.0, o, 1, 0);
  ASSERT_EQ(img.type(), CV_16U);
  double lo, hi;
  cv::minMaxLoc(img, &lo, &hi);
  EXPECT_EQ(lo, 4095.0);  // the noise (σ ≈ 0.01 full scale) cannot pull 1.8× below full scale
  EXPECT_EQ(hi, 4095.0);
  const cv::Mat dark = ApplySensor(cv::Mat(64, 64, CV_32F, cv::Scalar(0.0)), 1.0, o, 1, 0);
  cv::minMaxLoc(dark, &lo, &hi);
  EXPECT_EQ(lo, 0.0);  // read noise is clipped at 0, never wraps
  // Read noise 10 e− at 4095/10000 DN/e−: σ = 4.1 DN; 4096 samples stay below 6σ.
  EXPECT_LT(hi, 6.0 * 10.0 * 4095.0 / 10000.0);
  EXPECT_GT(hi, 0.0);
}

TEST(SimSensor, DefocusBlurStepResponseIsTheGaussianErf) {
  SensorOptions o;
  o.bits = 16;
  o.noise = false;
  o.blur_sigma_px = 2.5;
  cv::Mat step(32, 200, CV_32F, cv::Scalar(0.0));
  step.colRange(100, 200).setTo(1.0);  // edge between columns 99 and 100, i.e. at x = 99.5
  const cv::Mat img = ApplySensor(step, 1.0, o, 1, 0);
  const double full = 0.9 * 65535.0;
  for (int u = 92; u <= 107; ++u) {
    const double x = u - 99.5;
    const double expected = full * 0.5 * std::erfc(-x / (std::sqrt(2.0) * o.blur_sigma_px));
    // The pixel-sampled Gaussian kernel vs the continuous erf: within 0.5 % of full scale.
    EXPECT_NEAR(img.at<std::uint16_t>(16, u), expected, 0.005 * full) << u;
  }
}

TEST(SimSensor, SoftKneeIsLinearBelowTheKneeAndTheAlgebraicClipAbove) {
  // Noise-free 16-bit ramp: below K = k·F the reading is the signal; above it the closed form
  // K + (F − K)·x/sqrt(1 + x²), x = (S − K)/(F − K), to the rounding (0.5 DN); monotone.
  SensorOptions o;
  o.bits = 16;
  o.exposure = 1.0;
  o.noise = false;
  o.soft_knee_fraction = 0.6;
  const double f = o.MaxValue(), k = 0.6 * f;
  cv::Mat ramp(1, 200, CV_32F);
  for (int u = 0; u < ramp.cols; ++u) ramp.at<float>(0, u) = static_cast<float>(1.3 * u / (ramp.cols - 1.0));
  const cv::Mat out = ApplySensor(ramp, 1.0, o, 1, 0);
  double previous = -1;
  for (int u = 0; u < ramp.cols; ++u) {
    const double s = ramp.at<float>(0, u) * f;
    const double x = (s - k) / (f - k);
    const double expected = s <= k ? s : k + (f - k) * x / std::sqrt(1 + x * x);
    const double got = out.at<std::uint16_t>(0, u);
    EXPECT_NEAR(got, std::min(std::round(s <= k ? s : expected), f), 0.5 + 1e-9) << "signal " << s;
    EXPECT_GE(got, previous);
    previous = got;
  }
  o.soft_knee_fraction = 1.0;
  EXPECT_NE(o.Validate(), "");
}

TEST(SimSensor, BadOptionsAreRejected) {
  SensorOptions o;
  o.bits = 9;
  EXPECT_NE(o.Validate(), "");
  o.bits = 8;
  o.full_well_electrons = 0;
  EXPECT_NE(o.Validate(), "");
}

}  // namespace
}  // namespace ramtk::vision
