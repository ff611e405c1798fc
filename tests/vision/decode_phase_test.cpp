// Wrapped phase, modulation and sigma_phi against analytic truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "test_hooks_scope.h"
#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/phase_shift.h"

namespace ramtk::vision {
namespace {

using testing::SynthOptions;

struct PhaseErrorStats {
  double rms_error = 0;  // RMS of the wrapped-phase error vs truth (rad)
  double rms_bound = 0;  // RMS of the per-pixel sigma_phi (rad)
  double sigma_est = 0;  // sigma_I the decoder estimated (DN)
  long valid = 0;
};

PhaseErrorStats RunCase(int steps, double noise_dn, double sigma_given) {
  SynthOptions o;
  o.noise_dn = noise_dn;
  o.seed = 1000 + steps;
  FringeManifest m = testing::GrayManifest(steps, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  DecodeOptions opt;
  opt.correct_nonlinearity = false;
  opt.intensity_sigma_dn = sigma_given;
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, opt, "cam");
  PhaseErrorStats s;
  double se = 0, sb = 0;
  const SequenceBlock& ps = m.sequence[0];
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      if (!d.mask.at<uchar>(y, x)) continue;
      const double phi = PatternPhase(truth.at<double>(y, x), ps.cycles[0], m.Extent(), ps.phase_at_origin_rad);
      const double e = std::remainder(d.wrapped.at<float>(y, x) - phi, 2 * M_PI);
      se += e * e;
      sb += std::pow(d.sigma_phase.at<float>(y, x), 2);
      ++s.valid;
    }
  s.rms_error = std::sqrt(se / s.valid);
  s.rms_bound = std::sqrt(sb / s.valid);
  s.sigma_est = d.summary.sigma_intensity_dn;
  return s;
}

// sigma_I of Gaussian noise plus 8-bit quantisation.
double EffectiveSigma(double noise_dn) { return std::sqrt(noise_dn * noise_dn + 1.0 / 12.0); }

class WrappedPhaseNoise : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(WrappedPhaseNoise, RmsErrorWithinTheSigmaPhiBound) {
  const auto [steps, noise] = GetParam();
  const PhaseErrorStats s = RunCase(steps, noise, EffectiveSigma(noise));
  RecordProperty("rms_error_rad", std::to_string(s.rms_error));
  RecordProperty("rms_bound_rad", std::to_string(s.rms_bound));
  std::cout << "N=" << steps << " noise " << noise << " DN: wrapped-phase RMS error " << s.rms_error
            << " rad, sigma_phi bound " << s.rms_bound << " rad, ratio " << s.rms_error / s.rms_bound << " (" << s.valid
            << " px)\n";
  EXPECT_GT(s.valid, 100000);
  EXPECT_LE(s.rms_error, 1.2 * s.rms_bound);
  // The bound is a prediction, not just a ceiling: the error is not far below it either.
  EXPECT_GE(s.rms_error, 0.8 * s.rms_bound);
}

INSTANTIATE_TEST_SUITE_P(TwoNoiseLevels, WrappedPhaseNoise,
                         ::testing::Combine(::testing::Values(3, 4, 12), ::testing::Values(1.0, 4.0)));

TEST(WrappedPhaseNoise, IntensitySigmaEstimatedFromTheFitResiduals) {
  // N > 3 leaves N - 3 residual degrees of freedom per pixel: the decoder's sigma_I estimate
  // must match the synthesised noise.
  for (double noise : {1.0, 4.0}) {
    const PhaseErrorStats s = RunCase(8, noise, 0.0);
    EXPECT_NEAR(s.sigma_est, EffectiveSigma(noise), 0.05 * EffectiveSigma(noise)) << "noise " << noise;
    EXPECT_LE(s.rms_error, 1.2 * s.rms_bound);
  }
}

// A projector with gamma 2.2 adds harmonics: a phase-dependent residual that is systematic,
// smooth across the image and not noise. The random part of sigma_I must still be the
// synthesised noise, on both decode paths, while the whole residual RMS is much larger.
// 8-step Gray frames of a gamma-2.2 projector with 1 DN of noise (the synthesiser's seed given).
std::vector<cv::Mat> GammaFrames(const FringeManifest& m, unsigned seed) {
  SynthOptions o;
  o.noise_dn = 1.0;
  o.gamma = 2.2;
  o.seed = seed;
  return testing::SynthesizeFrames(m, testing::TruthCoordinate(o, m.Extent()), o);
}

TEST(WrappedPhaseNoise, RandomIntensityNoiseSeparatedFromTheHarmonics) {
  for (bool reference : {false, true}) {
    const detail::ScopedDecodeTestHooks scope(testing::ReferenceDecodeHooks(reference));
    const FringeManifest m = testing::GrayManifest(8, 32, true);
    const std::vector<cv::Mat> frames = GammaFrames(m, 2024);
    DecodeOptions opt;
    const DecodedCamera d = DecodeFrames(m, frames, 255.0, opt, "cam");
    const DecodeSummary& s = d.summary;
    std::cout << (reference ? "reference" : "fast") << ": residual " << s.fit_residual_rms_dn << " DN, random "
              << s.sigma_intensity_random_dn << " DN, systematic " << s.sigma_intensity_systematic_dn << " DN\n";
    // ~30 000 pairs x 5 degrees of freedom: the estimate's own relative error is ~0.3 %; 5 %
    // covers the quantisation's correlation with the signal (as the test above).
    EXPECT_NEAR(s.sigma_intensity_random_dn, EffectiveSigma(1.0), 0.05 * EffectiveSigma(1.0)) << reference;
    EXPECT_DOUBLE_EQ(s.sigma_intensity_dn, s.sigma_intensity_random_dn);
    EXPECT_GT(s.fit_residual_rms_dn, 2 * s.sigma_intensity_random_dn) << "the harmonics must show in the residual";
    // The old estimate on request: the whole residual.
    opt.noise_from_neighbours = false;
    const DecodedCamera old = DecodeFrames(m, frames, 255.0, opt, "cam");
    EXPECT_DOUBLE_EQ(old.summary.sigma_intensity_dn, old.summary.fit_residual_rms_dn);
  }
}

// The intensity-noise estimate's pixel triples, four at a time on AVX2 lanes, against the one-by-
// one loop: the same sums to the bit (the random and total sigmas compared exactly), on 8-bit and
// 16-bit frames, with a mask whose holes leave pixels with only one neighbour pair or none, at
// strides 1 and 3.
TEST(WrappedPhaseNoise, TriplesOnLanesGiveTheBitsOfTheScalarLoop) {
  const FringeManifest m = testing::GrayManifest(8, 32, true);
  const std::vector<cv::Mat> frames = GammaFrames(m, 2026);
  cv::Mat mask(frames[0].size(), CV_8U, cv::Scalar(255));
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> pick(0, 9);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (pick(rng) == 0 || (x / 37 + y / 23) % 7 == 3) mask.at<uchar>(y, x) = 0;
  for (const int depth : {CV_8U, CV_16U}) {
    std::vector<cv::Mat> converted(8);
    std::vector<const cv::Mat*> finest;
    for (int k = 0; k < 8; ++k) {
      frames[k].convertTo(converted[k], depth, depth == CV_16U ? 16.0 : 1.0);
      finest.push_back(&converted[k]);
    }
    for (const int stride : {1, 3}) {
      detail::SetAvx2Kernels(false);
      const detail::IntensityNoise scalar = detail::EstimateIntensityNoise(finest, mask, stride);
      detail::SetAvx2Kernels(true);
      const detail::IntensityNoise lanes = detail::EstimateIntensityNoise(finest, mask, stride);
      EXPECT_GT(scalar.pairs, 1000);
      EXPECT_EQ(lanes.pairs, scalar.pairs);
      EXPECT_EQ(std::memcmp(&lanes.random_dn, &scalar.random_dn, sizeof(double)), 0) << lanes.random_dn;
      EXPECT_EQ(std::memcmp(&lanes.total_dn, &scalar.total_dn, sizeof(double)), 0) << lanes.total_dn;
    }
  }
}

// The per-pixel estimates' stride follows the valid pixel count (DecodeOptions::
// estimate_max_samples): closed-form cases, then a frame sampled at every 8th pixel instead of
// every 4th still finds the synthesised noise, and agrees with the denser sampling within their
// statistical scatter.
TEST(WrappedPhaseNoise, SparserSamplingOfLargeFramesStillFindsTheNoise) {
  EXPECT_EQ(detail::EstimateStride(4, 6650600, 200000), 6);  // a thesis frame: 33 x the samples
  EXPECT_EQ(detail::EstimateStride(4, 410613, 200000), 4);   // SLMaster: the stride
  EXPECT_EQ(detail::EstimateStride(4, 1883935, 200000), 4);  // a 2048x1536 set
  EXPECT_EQ(detail::EstimateStride(4, 6650600, 0), 4);       // off
  EXPECT_EQ(detail::EstimateStride(0, 0, 200000), 1);
  const FringeManifest m = testing::GrayManifest(8, 32, true);
  const std::vector<cv::Mat> frames = GammaFrames(m, 2025);
  DecodeOptions dense, sparse;
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, dense, "cam");
  const long valid = d.summary.valid_pixels;
  sparse.estimate_max_samples = valid / 64;  // every 8th pixel in x and y
  ASSERT_EQ(detail::EstimateStride(sparse.noise_stride, valid, sparse.estimate_max_samples), 8);
  const DecodedCamera e = DecodeFrames(m, frames, 255.0, sparse, "cam");
  const double a = d.summary.sigma_intensity_random_dn, b = e.summary.sigma_intensity_random_dn;
  std::cout << "sigma_I random: every 4th pixel " << a << " DN, every 8th " << b << " DN (" << valid << " valid)\n";
  EXPECT_NEAR(b, EffectiveSigma(1.0), 0.05 * EffectiveSigma(1.0));
  // Relative error of each ~1 / sqrt(2 pixels (N - 3)); the sparse set is a subset of the dense.
  const double rel = 1.0 / std::sqrt(2.0 * (valid / 64.0) * (8 - 3));
  EXPECT_NEAR(b / a, 1.0, 4 * rel);
  EXPECT_EQ(e.summary.valid_pixels, valid);
  EXPECT_EQ(cv::norm(d.coordinate, e.coordinate, cv::NORM_INF, d.mask), 0.0);  // the phase itself is untouched
}

// The sigma maps' row (detail::SigmaRow, eight pixels at a time on two double lanes) against
// its formula evaluated one pixel at a time: the same bits, for a row with masked pixels, a
// modulation of 0, negative, NaN or tiny, and a width that leaves a one-by-one tail.
TEST(WrappedPhaseNoise, SigmaRowIsTheFormulaBitForBit) {
  const int width = 203;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> modulation(0.5f, 200.0f);
  std::vector<uchar> mask(width);
  std::vector<float> b(width), c(width);
  for (int x = 0; x < width; ++x) {
    mask[x] = (x % 7 == 3) ? 0 : 255;
    b[x] = modulation(rng);
    c[x] = static_cast<float>(x) * 0.37f;
  }
  b[5] = 0.0f;
  b[6] = -3.0f;
  b[9] = std::numeric_limits<float>::quiet_NaN();
  b[12] = 1e-30f;
  b[201] = 0.0f;  // in the tail
  for (const double ripple : {0.0, 0.003}) {
    std::vector<float> c_out = c, sp(width, -1.0f), sc(width, -1.0f);
    const double k = 0.41, to_px = 20.0 / (2 * M_PI);
    detail::SigmaRow(mask.data(), b.data(), width, k, ripple, to_px, c_out.data(), sp.data(), sc.data());
    std::vector<float> sc_only(width, -1.0f), c_only = c;
    detail::SigmaRow(mask.data(), b.data(), width, k, ripple, to_px, c_only.data(), nullptr, sc_only.data());
    auto same = [](float u, float v) { return std::memcmp(&u, &v, sizeof u) == 0; };
    for (int x = 0; x < width; ++x) {
      SCOPED_TRACE("x " + std::to_string(x) + ", ripple " + std::to_string(ripple));
      if (!mask[x]) {
        EXPECT_TRUE(std::isnan(c_out[x]) && std::isnan(sp[x]) && std::isnan(sc[x]));
        continue;
      }
      const float s = b[x] > 0 ? static_cast<float>(std::sqrt(k * k / (double(b[x]) * b[x]) + ripple * ripple))
                               : std::numeric_limits<float>::infinity();
      EXPECT_TRUE(same(c_out[x], c[x]));
      EXPECT_TRUE(same(sp[x], s)) << sp[x] << " vs " << s;
      EXPECT_TRUE(same(sc[x], static_cast<float>(s * to_px)));
      EXPECT_TRUE(same(sc_only[x], sc[x]));
    }
  }
}

TEST(PhaseShift, ExactSinusoidClosedForm) {
  // Noise-free float samples: the LS solution is exact for any N.
  for (int n : {3, 4, 5, 7, 12}) {
    std::vector<cv::Mat> frames;
    const double a = 100, b = 37, phi = -2.3;
    for (int k = 0; k < n; ++k) frames.emplace_back(1, 1, CV_32F, cv::Scalar(a + b * std::cos(phi + 2 * M_PI * k / n)));
    const PhaseShiftResult r = ComputePhaseShift(frames);
    EXPECT_NEAR(r.wrapped.at<float>(0, 0), phi, 1e-5) << n;
    EXPECT_NEAR(r.background.at<float>(0, 0), a, 1e-4) << n;
    EXPECT_NEAR(r.modulation.at<float>(0, 0), b, 1e-4) << n;
    EXPECT_NEAR(r.residual_ss.at<float>(0, 0), 0.0, 1e-2) << n;
  }
}

}  // namespace
}  // namespace ramtk::vision
