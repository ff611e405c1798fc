// The decode's AVX2 row kernels (decode_avx2.h) against its 128-bit kernels: every map and every
// summary figure bit for bit. The 128-bit path is itself checked against the reference path and
// analytic truth (decode_fast_test.cpp, decode_phase_test.cpp); the frames come from the analytic
// synthesiser, with dark and saturated patches and a width that leaves tails for every kernel, as
// 8-bit samples and as 12-bit ones in 16-bit words.
#include "ramtk/vision/decode/detail/decode_avx2.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"

namespace ramtk::vision {
namespace {

// Same type, size and bytes (NaN payloads included).
::testing::AssertionResult SameBits(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() && b.empty()) return ::testing::AssertionSuccess();
  if (a.type() != b.type() || a.size() != b.size()) return ::testing::AssertionFailure() << "type or size differs";
  const std::size_t row = a.cols * a.elemSize();
  for (int y = 0; y < a.rows; ++y)
    if (std::memcmp(a.ptr(y), b.ptr(y), row) != 0) return ::testing::AssertionFailure() << "row " << y << " differs";
  return ::testing::AssertionSuccess();
}

// A set of 8-bit frames 403 px wide (tails of 3 px after 16- and 8-pixel steps) with a dark
// patch (below the dark level) and a saturated one.
std::vector<cv::Mat> EightBitFrames(const FringeManifest& m, double gamma) {
  testing::SynthOptions o;
  o.width = 403;
  o.height = 61;
  o.gamma = gamma;
  o.noise_dn = 1.5;
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, testing::TruthCoordinate(o, m.Extent()), o);
  std::vector<cv::Mat> out(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames[i].convertTo(out[i], CV_8U);
    out[i](cv::Rect(30, 10, 40, 20)).setTo(2);    // dark in every frame
    out[i](cv::Rect(200, 25, 17, 9)).setTo(255);  // saturated
  }
  return out;
}

TEST(DecodeAvx2, KernelsGiveTheBitsOfThe128BitKernels) {
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  const std::vector<FringeManifest> sets = {testing::GrayManifest(12, 64, true), testing::GrayManifest(4, 32, false),
                                            testing::HeterodyneManifest(5, {64, 59, 55})};
  for (const FringeManifest& m : sets) {
    const std::string what = std::to_string(m.sequence[0].steps) + "-step " +
                             (m.sequence[0].type == BlockType::kHeterodyne ? "heterodyne" : "gray");
    SCOPED_TRACE(what);
    const std::vector<cv::Mat> frames8 = EightBitFrames(m, 1.8);
    // 8-bit samples, and the same scaled to 12 bits in 16-bit words (a 12-bit camera's frames:
    // the double-sum kernels).
    for (const int bits : {8, 12}) {
      SCOPED_TRACE(std::to_string(bits) + "-bit");
      std::vector<cv::Mat> frames = frames8;
      if (bits == 12)
        for (cv::Mat& f : frames) f.convertTo(f, CV_16U, 4095.0 / 255.0);  // 255 -> 4095: saturated
      const double full_scale = bits == 8 ? 255.0 : 4095.0;
      DecodeOptions o;
      o.keep_diagnostic_maps = true;
      detail::SetAvx2Kernels(false);
      const DecodedCamera narrow = DecodeFrames(m, frames, full_scale, o, "cam");
      detail::SetAvx2Kernels(true);
      const DecodedCamera wide = DecodeFrames(m, frames, full_scale, o, "cam");
      const DecodeSummary &a = narrow.summary, &b = wide.summary;
      ASSERT_GT(a.valid_pixels, 10000) << a.BriefReport();
      EXPECT_GT(a.dark, 0);
      EXPECT_GT(a.saturated, 0);
      EXPECT_TRUE(SameBits(wide.mask, narrow.mask));
      EXPECT_TRUE(SameBits(wide.wrapped, narrow.wrapped));
      EXPECT_TRUE(SameBits(wide.background, narrow.background));
      EXPECT_TRUE(SameBits(wide.modulation, narrow.modulation));
      EXPECT_TRUE(SameBits(wide.fit_residual, narrow.fit_residual));
      EXPECT_TRUE(SameBits(wide.coordinate, narrow.coordinate));
      EXPECT_TRUE(SameBits(wide.sigma_phase, narrow.sigma_phase));
      EXPECT_TRUE(SameBits(wide.sigma_coordinate, narrow.sigma_coordinate));
      EXPECT_EQ(b.valid_pixels, a.valid_pixels);
      EXPECT_EQ(b.dark, a.dark);
      EXPECT_EQ(b.saturated, a.saturated);
      EXPECT_EQ(b.low_modulation, a.low_modulation);
      EXPECT_EQ(b.edge_corrections, a.edge_corrections);
      EXPECT_EQ(b.fit_residual_rms_dn, a.fit_residual_rms_dn);
      EXPECT_EQ(b.phase_residual_rms_rad, a.phase_residual_rms_rad);
      EXPECT_EQ(b.worst_residual_dn, a.worst_residual_dn);
      EXPECT_EQ(b.sigma_intensity_dn, a.sigma_intensity_dn);
      EXPECT_EQ(b.median_modulation_dn, a.median_modulation_dn);
      EXPECT_EQ(b.phase_ripple_rad, a.phase_ripple_rad);
      EXPECT_EQ(b.harmonic_ratios, a.harmonic_ratios);
      EXPECT_EQ(b.nonlinearity.sin_rad, a.nonlinearity.sin_rad);
      EXPECT_EQ(b.nonlinearity.cos_rad, a.nonlinearity.cos_rad);
    }
  }
  detail::SetAvx2Kernels(true);
}

}  // namespace
}  // namespace ramtk::vision
