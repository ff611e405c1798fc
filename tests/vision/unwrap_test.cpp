// Temporal unwrapping against analytic truth: period-order errors for heterodyne, plain and
// complementary Gray code under projector blur and noise.
#include "ramtk/vision/fringe/unwrap.h"

#include <gtest/gtest.h>

#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {
namespace {

using testing::SynthOptions;

DecodeOptions Plain() {
  DecodeOptions o;
  o.correct_nonlinearity = false;
  return o;
}

TEST(Unwrap, ComplementaryGrayCodeHasNoOrderErrorsAtNominalNoise) {
  SynthOptions o;  // 1 DN noise, 1.5 px projector blur
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const auto frames = testing::SynthesizeFrames(m, truth, o);
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, Plain(), "cam");
  const auto c = testing::CompareToTruth(d.coordinate, d.mask, truth, m.Extent() / 32.0);
  std::cout << "complementary Gray code: " << c.order_errors << " order errors in " << c.valid << " valid px, "
            << d.summary.edge_corrections << " edge orders corrected, RMS " << c.rms_px << " px\n";
  EXPECT_GT(c.valid, 0.95 * truth.total());
  EXPECT_EQ(c.order_errors, 0);
  EXPECT_GT(d.summary.edge_corrections, 0);  // the blur did put codes off by one cell
}

TEST(Unwrap, PlainVersusComplementaryEdgeErrors) {
  SynthOptions o;
  o.noise_dn = 2.0;
  o.blur_px = 2.5;
  // The same 4-step images; the plain decoder uses the first 5 code images only.
  const FringeManifest comp = testing::GrayManifest(4, 32, true);
  const FringeManifest plain = testing::GrayManifest(4, 32, false);
  const cv::Mat truth = testing::TruthCoordinate(o, comp.Extent());
  const auto frames = testing::SynthesizeFrames(comp, truth, o);
  const std::vector<cv::Mat> plain_frames(frames.begin(), frames.end() - 1);
  const DecodedCamera dc = DecodeFrames(comp, frames, 255.0, Plain(), "cam");
  const DecodedCamera dp = DecodeFrames(plain, plain_frames, 255.0, Plain(), "cam");
  const double period = comp.Extent() / 32.0;
  const auto cc = testing::CompareToTruth(dc.coordinate, dc.mask, truth, period);
  const auto cp = testing::CompareToTruth(dp.coordinate, dp.mask, truth, period);
  std::cout << "edge errors, plain Gray code: " << cp.order_errors << " / " << cp.valid
            << " px; complementary: " << cc.order_errors << " / " << cc.valid << " px\n";
  RecordProperty("plain_order_errors", std::to_string(cp.order_errors));
  RecordProperty("complementary_order_errors", std::to_string(cc.order_errors));
  EXPECT_GT(cp.order_errors, 100);  // plain Gray code jumps a period at blurred edges
  EXPECT_EQ(cc.order_errors, 0);
}

TEST(Unwrap, ThreeFrequencyHeterodyneHasNoOrderErrorsAtNominalNoise) {
  SynthOptions o;
  // 1024 px projector: 64, 60, 57 cycles -> beats 4 and 3 -> 1 cycle across the projector.
  const FringeManifest m = testing::HeterodyneManifest(4, {64, 60, 57});
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const auto frames = testing::SynthesizeFrames(m, truth, o);
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, Plain(), "cam");
  const auto c = testing::CompareToTruth(d.coordinate, d.mask, truth, m.Extent() / 64.0);
  std::cout << "heterodyne 64/60/57: " << c.order_errors << " order errors in " << c.valid << " valid px, RMS "
            << c.rms_px << " px, rejected " << d.summary.unwrap_rejected << "\n";
  EXPECT_GT(c.valid, 0.99 * truth.total());
  EXPECT_EQ(c.order_errors, 0);
}

TEST(Unwrap, TwoFrequencyHeterodyne) {
  SynthOptions o;
  const FringeManifest m = testing::HeterodyneManifest(6, {16, 15});
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const DecodedCamera d = DecodeFrames(m, testing::SynthesizeFrames(m, truth, o), 255.0, Plain(), "cam");
  const auto c = testing::CompareToTruth(d.coordinate, d.mask, truth, m.Extent() / 16.0);
  EXPECT_GT(c.valid, 0.99 * truth.total());
  EXPECT_EQ(c.order_errors, 0);
}

TEST(Unwrap, GrayCodeDecodingIsTheInverseOfTheCode) {
  // Every cell of a 6-bit code read back from its ideal images.
  const int bits = 6, extent = 640;
  std::vector<cv::Mat> frames;
  for (int j = 0; j < bits; ++j) {
    cv::Mat f(1, extent, CV_32F);
    for (int u = 0; u < extent; ++u) {
      const int cell = u * (1 << bits) / extent;
      f.at<float>(0, u) = static_cast<float>(((cell ^ (cell >> 1)) >> (bits - 1 - j)) & 1);
    }
    frames.push_back(f);
  }
  const cv::Mat cells = DecodeGrayCode(frames, cv::Mat(1, extent, CV_32F, cv::Scalar(0.5)));
  for (int u = 0; u < extent; ++u) ASSERT_EQ(cells.at<int>(0, u), u * (1 << bits) / extent) << u;
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

TEST(QualityMask, SaturatedAndLowModulationPixelsAreMaskedByCause) {
  // Over-exposed: ambient 100 + gain 180 clips the bright fringe crests; a dark band with little
  // modulation on the left. Truth decides which pixels should go.
  testing::SynthOptions o;
  o.ambient = 100;
  o.gain = 180;
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  // Columns 0..39: replace by a flat grey that alternates by 2 DN from step to step: no
  // modulation at the fringe frequency (B = 0), so no fringes above the noise.
  for (std::size_t k = 0; k < 4; ++k)
    for (int y = 0; y < truth.rows; ++y)
      for (int x = 0; x < 40; ++x) frames[k].at<float>(y, x) = static_cast<float>(120 + (k % 2 ? 2 : -2));
  for (const ModulationRule rule : {ModulationRule::kSigma, ModulationRule::kFixed}) {
  SCOPED_TRACE(rule == ModulationRule::kSigma ? "sigma rule" : "fixed rule");
  DecodeOptions opt;
  opt.correct_nonlinearity = false;
  opt.modulation_rule = rule;
  const DecodedCamera d = DecodeFrames(m, frames, 255.0, opt, "cam");
  long expect_saturated = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 40; x < truth.cols; ++x) {
      bool sat = false;
      for (int k = 0; k < 4; ++k) sat |= frames[k].at<float>(y, x) >= 255.0f * 0.998f;
      expect_saturated += sat;
      EXPECT_EQ(d.mask.at<uchar>(y, x) == 0, sat) << x << "," << y;
      if (HasFailure()) return;
    }
  EXPECT_GT(expect_saturated, 1000);
  EXPECT_EQ(d.summary.saturated, expect_saturated);
  // The fixed rule calls them low modulation (B below 2 % of full scale), the sigma rule dark (B
  // below its noise floor).
  EXPECT_EQ(rule == ModulationRule::kFixed ? d.summary.low_modulation : d.summary.dark, 40L * truth.rows);
  const auto c = testing::CompareToTruth(d.coordinate, d.mask, truth, m.Extent() / 32.0);
  EXPECT_EQ(c.order_errors, 0);
  }
}

}  // namespace
}  // namespace ramtk::vision
