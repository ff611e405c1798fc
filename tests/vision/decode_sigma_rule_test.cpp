// ModulationRule::kSigma against truth the decoder does not see: the analytic synthesis's
// projector coordinate (decode_synth.h) and the closed-form rate at which noise alone passes the
// noise floor. Fixed seeds; tolerances from the binomial counts.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

using testing::SynthOptions;

// sigma_I of Gaussian noise plus 8-bit quantisation.
double EffectiveSigma(double noise_dn) { return std::sqrt(noise_dn * noise_dn + 1.0 / 12.0); }

// Both decode paths (the fast one, and the reference under its test hook).
template <typename F>
void OnBothPaths(F body) {
  for (const bool reference : {false, true}) {
    SCOPED_TRACE(reference ? "reference path" : "fast path");
    testing::WithReferenceDecode(reference, [&] { body(reference); });
  }
}

// Every pixel decoded (no weak-fringe rejection) at one modulation B: the wrong period orders
// against the synthesis's truth follow OrderErrorProbability for a complementary Gray code.
TEST(DecodeSigmaRule, WrongOrderRateFollowsTheModel) {
  SynthOptions o;
  o.noise_dn = 2.0;
  o.gain = 12;  // B = gain / 2 x the blur's attenuation ~ 5.7 DN: B / sigma_I ~ 2.9
  o.seed = 21;
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  DecodeOptions opt;
  opt.modulation_rule = ModulationRule::kFixed;
  opt.min_modulation_fraction = 0;
  opt.dark_fraction = 0;
  opt.correct_nonlinearity = false;
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, opt, "cam");
  const testing::TruthComparison c = testing::CompareToTruth(d.coordinate, d.mask, truth, 32.0);
  const double b = o.gain / 2 * std::exp(-0.5 * std::pow(2 * M_PI * o.blur_px / 32.0, 2));
  detail::OrderDecision decision = detail::OrderDecisionOf(m);
  std::vector<const cv::Mat*> ps, gray;
  for (int k = 0; k < 4; ++k) ps.push_back(&frames[k]);
  for (std::size_t k = 4; k < frames.size(); ++k) gray.push_back(&frames[k]);
  decision.gray_contrast = detail::GrayContrastRatio(ps, gray, d.mask, 2);
  EXPECT_NEAR(decision.gray_contrast, o.gain / 2 / b, 0.1);  // the synthesis's binary over sinusoid contrast
  const double model = detail::OrderErrorProbability(decision, 4, b / EffectiveSigma(o.noise_dn));
  const double measured = static_cast<double>(c.order_errors) / c.valid;
  std::cout << "wrong orders " << c.order_errors << " of " << c.valid << " (" << measured << "), model " << model
            << "\n";
  ASSERT_GT(c.order_errors, 300);  // a rate measured to < 6 %
  // The model counts every Gray bit at the measured contrast and the phase's quarter-period
  // margin: an upper bound, within ~1/12 of the rate (the half-period bit of 6 is half corrected).
  EXPECT_LT(measured, 1.05 * model);
  EXPECT_GT(measured, 0.8 * model);
}

// Noise alone (no projector light): B is Rayleigh with scale sqrt(2/N) sigma_I, so a share
// exp(-c^2/2) passes the noise floor c (the order test switched off by epsilon near 1).
TEST(DecodeSigmaRule, NoiseOnlyPixelsPassTheFloorAtTheRayleighRate) {
  SynthOptions o;
  o.noise_dn = 4.0;
  o.gain = 0;
  o.ambient = 60;
  o.seed = 5;
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  DecodeOptions opt;
  opt.intensity_sigma_dn = EffectiveSigma(o.noise_dn);
  opt.max_order_error_probability = 0.999;
  opt.noise_floor_factor = 2.0;
  opt.correct_nonlinearity = false;
  OnBothPaths([&](bool) {
    const DecodedCamera d = DecodeFrames(m, frames, 255.0, opt, "cam");
    // Pixels whose random Gray code put the order outside the projector are rejected before the
    // rule applies (independently of B): the share is of the others.
    const double total = static_cast<double>(frames[0].total() - d.summary.unwrap_rejected);
    const double passed = 1.0 - d.summary.dark / total;
    const double expected = std::exp(-0.5 * 2.0 * 2.0);
    EXPECT_NEAR(passed, expected, 4 * std::sqrt(expected * (1 - expected) / total));
    EXPECT_NEAR(d.summary.noise_floor_dn, 2.0 * std::sqrt(2.0 / 4) * EffectiveSigma(o.noise_dn), 1e-9);
  });
}

// Weak fringes well above the noise (B ~ 4 DN, sigma_I ~ 0.6 DN): the fixed 2 % rule (5.1 DN)
// rejects them all, the sigma rule keeps them with no wrong order, and the fast and reference
// paths give the same mask and counts.
TEST(DecodeSigmaRule, WeakButCleanFringesAreKeptWithoutWrongOrders) {
  SynthOptions o;
  o.noise_dn = 0.5;
  o.gain = 8.4;
  o.ambient = 10;
  o.seed = 9;
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  DecodeOptions sigma;
  sigma.correct_nonlinearity = false;
  DecodeOptions fixed = sigma;
  fixed.modulation_rule = ModulationRule::kFixed;
  const DecodedCamera f = DecodeFrames(m, frames, 255.0, fixed, "cam");
  EXPECT_LT(f.summary.valid_fraction, 0.05) << f.summary.BriefReport();
  cv::Mat fast_mask;
  DecodeSummary fast;
  OnBothPaths([&](bool reference) {
    const DecodedCamera d = DecodeFrames(m, frames, 255.0, sigma, "cam");
    std::cout << d.summary.BriefReport() << "\n";
    const testing::TruthComparison c = testing::CompareToTruth(d.coordinate, d.mask, truth, 32.0);
    EXPECT_GT(d.summary.valid_fraction, 0.95);
    EXPECT_EQ(c.order_errors, 0);
    EXPECT_LT(d.summary.modulation_threshold_dn, 0.8 * d.summary.median_modulation_dn);
    if (!reference) {
      fast_mask = d.mask.clone();
      fast = d.summary;
      return;
    }
    EXPECT_EQ(cv::countNonZero(d.mask != fast_mask), 0);
    EXPECT_EQ(d.summary.dark, fast.dark);
    EXPECT_EQ(d.summary.low_modulation, fast.low_modulation);
    EXPECT_EQ(d.summary.valid_pixels, fast.valid_pixels);
    EXPECT_NEAR(d.summary.sigma_intensity_dn, fast.sigma_intensity_dn, 1e-3 * fast.sigma_intensity_dn);
    EXPECT_NEAR(d.summary.modulation_threshold_dn, fast.modulation_threshold_dn, 1e-3 * fast.modulation_threshold_dn);
  });
}

}  // namespace
}  // namespace ramtk::vision
