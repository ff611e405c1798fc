// Projector gamma 2.2 on 3- and 4-step sets: phase error against truth before and after the
// self-calibrated correction.
#include "ramtk/vision/decode/nonlinearity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {
namespace {

using testing::SynthOptions;

// RMS error (projector px) of the decoded coordinate against truth.
// 3-step: an 8-bit camera with 0.5 DN noise. 4-step: gamma 2.2 leaves only weak 3rd/5th
// harmonics, so a 16-bit camera (noise 0.5/255 of full scale) keeps the noise below the effect.
double CoordinateRms(int steps, double gamma, bool correct, NonlinearityEstimate* estimate = nullptr) {
  SynthOptions o;
  o.gamma = gamma;
  o.blur_px = 0.3;      // in focus: defocus would attenuate the harmonics and lower the apparent gamma
  o.seed = 77 + steps;  // same noise with and without gamma
  const double scale = steps == 3 ? 1.0 : 257.0;
  o.full_scale = 255 * scale;
  o.noise_dn = 0.5;
  o.ambient = 15 * scale;
  o.gain = 220 * scale;
  const FringeManifest m = testing::GrayManifest(steps, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  DecodeOptions opt;
  opt.correct_nonlinearity = correct;
  const DecodedCamera d = DecodeFrames(m, testing::SynthesizeFrames(m, truth, o), o.full_scale, opt, "cam");
  if (estimate) *estimate = d.summary.nonlinearity;
  const auto c = testing::CompareToTruth(d.coordinate, d.mask, truth, m.Extent() / 32.0);
  EXPECT_EQ(c.order_errors, 0);
  EXPECT_GT(c.valid, 0.95 * truth.total());
  return c.rms_px;
}

class Gamma : public ::testing::TestWithParam<int> {};

TEST_P(Gamma, CorrectionRemovesAtLeast80PercentOfTheGammaError) {
  const int steps = GetParam();
  const double linear = CoordinateRms(steps, 1.0, false);  // noise-only error
  const double before = CoordinateRms(steps, 2.2, false);
  NonlinearityEstimate est;
  const double after = CoordinateRms(steps, 2.2, true, &est);
  // Error caused by the gamma: the part above the noise-only error (added in quadrature).
  const double caused_before = std::sqrt(std::max(0.0, before * before - linear * linear));
  const double caused_after = std::sqrt(std::max(0.0, after * after - linear * linear));
  const double removed = 1.0 - caused_after / caused_before;
  std::cout << "N=" << steps << " gamma 2.2: coordinate RMS vs truth " << before << " px -> " << after
            << " px (noise only " << linear << " px); gamma error removed " << 100 * removed << "%; "
            << est.BriefReport() << "\n";
  RecordProperty("removed_percent", std::to_string(100 * removed));
  EXPECT_GT(caused_before, 2 * linear);  // the gamma error is real
  EXPECT_GE(removed, 0.8);
  EXPECT_TRUE(est.applied);
  // The first-order ripple converts back to the projector's gamma (N = 4: the root above 1).
  EXPECT_NEAR(est.equivalent_gamma, 2.2, steps == 3 ? 0.1 : 0.2);
}

INSTANTIATE_TEST_SUITE_P(ThreeAndFourStep, Gamma, ::testing::Values(3, 4));

TEST(Gamma, LinearProjectorIsLeftAlone) {
  NonlinearityEstimate est;
  const double without = CoordinateRms(4, 1.0, false);
  const double with = CoordinateRms(4, 1.0, true, &est);
  EXPECT_LT(std::abs(est.sin_rad[0]), 2e-3);
  EXPECT_LE(with, without * 1.05 + 5e-4);  // 5e-4 px = 1e-4 rad
}

TEST(Gamma, RippleOfGammaMatchesFirstOrderHarmonics) {
  // Closed form for N = 3: (0.5 + 0.5 cos)^2 = 0.375 + 0.5 cos + 0.125 cos 2 -> r2 = B2/B1 = 0.25 and
  // phi' = phi - r2 sin(3 phi) to first order: s1 close to -0.25 (second-order terms are r2^2).
  EXPECT_NEAR(RippleOfGamma(2.0, 3), -0.25, 0.02);
  EXPECT_NEAR(RippleOfGamma(1.0, 3), 0.0, 1e-9);
  EXPECT_NEAR(RippleOfGamma(1.0, 4), 0.0, 1e-9);
  EXPECT_NEAR(EquivalentGamma(RippleOfGamma(2.2, 3), 3), 2.2, 1e-2);
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

TEST(Gamma, DirectHarmonicsOfAWideStepSet) {
  // 12 steps resolve harmonics 2..5 per pixel: gamma 2.2 must come back from B_2/B_1, and the
  // measured ratios must match the power law's Fourier series (computed independently here by
  // a direct sum over the profile).
  testing::SynthOptions o;
  o.gamma = 2.2;
  o.blur_px = 0.0;
  o.noise_dn = 1.0;
  o.ambient = 15;
  o.gain = 220;
  const FringeManifest m = testing::GrayManifest(12, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  DecodeOptions opt;
  const DecodedCamera d = DecodeFrames(m, testing::SynthesizeFrames(m, truth, o), 255.0, opt, "cam");
  const DecodeSummary& s = d.summary;
  ASSERT_EQ(s.harmonic_ratios.size(), 4u);
  for (int h = 2; h <= 5; ++h) {
    double ch = 0, c1 = 0;
    for (int i = 0; i < 3600; ++i) {
      const double t = 2 * M_PI * (i + 0.5) / 3600;
      const double v = std::pow(0.5 + 0.5 * std::cos(t), 2.2);
      ch += v * std::cos(h * t);
      c1 += v * std::cos(t);
    }
    EXPECT_NEAR(s.harmonic_ratios[h - 2], ch / c1, 0.01) << "h = " << h;  // 8-bit clipping/rounding
  }
  EXPECT_NEAR(s.gamma_from_harmonics, 2.2, 0.1);
}

// The closed form r_2 = (gamma - 1) / (gamma + 2) against a direct sum over the profile (fine
// enough that its own error is < 2e-7 at gamma = 0.3, where the profile's derivative is singular
// at its zero), and the inverse: exact round trip over [0.3, 5], NaN outside.
TEST(Gamma, SecondHarmonicClosedFormAndItsInverse) {
  for (const double gamma : {0.3, 0.5, 0.9, 1.0, 1.8, 2.2, 3.0, 5.0}) {
    double c2 = 0, c1 = 0;
    const int samples = 20000;
    for (int i = 0; i < samples; ++i) {
      const double t = 2 * M_PI * (i + 0.5) / samples;
      const double v = std::pow(0.5 + 0.5 * std::cos(t), gamma);
      c2 += v * std::cos(2 * t);
      c1 += v * std::cos(t);
    }
    EXPECT_NEAR(SecondHarmonicOfGamma(gamma), c2 / c1, 2e-7) << "gamma " << gamma;
    EXPECT_NEAR(GammaFromSecondHarmonic(SecondHarmonicOfGamma(gamma)), gamma, 1e-12) << "gamma " << gamma;
  }
  EXPECT_TRUE(std::isnan(GammaFromSecondHarmonic(SecondHarmonicOfGamma(0.29))));
  EXPECT_TRUE(std::isnan(GammaFromSecondHarmonic(SecondHarmonicOfGamma(5.01))));
  EXPECT_TRUE(std::isnan(GammaFromSecondHarmonic(std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace ramtk::vision
