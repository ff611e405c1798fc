// Pattern generation: layout (SLMaster convention) and decode round trips where the truth is the
// projector pixel index itself.
#include "ramtk/vision/fringe/patterns.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {
namespace {

FringeManifest Make(FringeDirection dir, std::vector<SequenceBlock> seq) {
  FringeManifest m;
  m.projector_width = 256;
  m.projector_height = 128;
  m.direction = dir;
  m.sequence = std::move(seq);
  m.cameras["projector"].resize(m.ImageCount());
  return m;
}

SequenceBlock Ps(int steps, double cycles) {
  SequenceBlock b;
  b.steps = steps;
  b.cycles = {cycles};
  return b;
}

SequenceBlock Gray(int bits, bool complementary) {
  SequenceBlock b;
  b.type = BlockType::kGrayCode;
  b.bits = bits;
  b.complementary = complementary;
  return b;
}

// Decodes the quantised patterns as if a camera saw the projector pixel for pixel.
void ExpectRoundTrip(const FringeManifest& m, int bits, double tolerance_px) {
  const auto q = QuantisePatterns(GeneratePatterns(m), bits);
  std::vector<cv::Mat> frames;
  for (const cv::Mat& p : q) {
    cv::Mat f;
    p.convertTo(f, CV_32F, 0.9);  // the camera sees 90% of the projector's range: nothing saturates
    frames.push_back(f);
  }
  DecodeOptions opt;
  opt.correct_nonlinearity = false;
  const DecodedCamera d = DecodeFrames(m, frames, bits == 8 ? 255.0 : 65535.0, opt, "projector");
  double worst = 0;
  long valid = 0;
  for (int y = 0; y < m.projector_height; ++y)
    for (int x = 0; x < m.projector_width; ++x) {
      if (!d.mask.at<uchar>(y, x)) continue;
      ++valid;
      const double truth = m.direction == FringeDirection::kVertical ? x : y;
      worst = std::max(worst, std::abs(d.coordinate.at<float>(y, x) - truth));
    }
  EXPECT_EQ(valid, static_cast<long>(m.projector_width) * m.projector_height);
  EXPECT_LT(worst, tolerance_px);
}

TEST(Patterns, SlmasterLayout) {
  // SLMaster (shared/data/slmaster-binocular): every period starts dark in step 0; step k adds
  // 2*pi*k/N; the first code image is dark on the left half, the second dark-bright-bright-dark.
  const FringeManifest m = Make(FringeDirection::kVertical, {Ps(12, 16), Gray(5, true)});
  const auto p = GeneratePatterns(m);
  ASSERT_EQ(p.size(), 17u);
  EXPECT_NEAR(p[0].at<float>(0, 0), 0.0, 1e-6);
  EXPECT_NEAR(p[0].at<float>(0, 8), 1.0, 1e-6);  // half a period (16 px) later: bright
  EXPECT_NEAR(p[3].at<float>(0, 4), 0.5 + 0.5 * std::cos(2 * M_PI * 4 / 16 - M_PI + 2 * M_PI * 3 / 12), 1e-6);
  EXPECT_EQ(p[12].at<float>(5, 127), 0.0f);
  EXPECT_EQ(p[12].at<float>(5, 128), 1.0f);
  EXPECT_EQ(p[13].at<float>(0, 63), 0.0f);
  EXPECT_EQ(p[13].at<float>(0, 64), 1.0f);
  EXPECT_EQ(p[13].at<float>(0, 191), 1.0f);
  EXPECT_EQ(p[13].at<float>(0, 192), 0.0f);
  // The last (complementary) image: stripes one period (16 px) wide, edges half a period off the
  // period edges (x = 8, 24, ...).
  int changes = 0;
  for (int x = 1; x < 256; ++x) {
    const bool edge = p[16].at<float>(0, x) != p[16].at<float>(0, x - 1);
    changes += edge;
    if (edge) {
      EXPECT_EQ(x % 16, 8) << x;
    }
  }
  EXPECT_EQ(changes, 16);
}

TEST(Patterns, ComplementaryGrayCodeRoundTrip8Bit) {
  ExpectRoundTrip(Make(FringeDirection::kVertical, {Ps(4, 16), Gray(5, true)}), 8, 0.05);
}

TEST(Patterns, HorizontalComplementaryGrayCodeRoundTrip16Bit) {
  ExpectRoundTrip(Make(FringeDirection::kHorizontal, {Ps(3, 8), Gray(4, true)}), 16, 0.01);
}

TEST(Patterns, HeterodyneRoundTrip) {
  SequenceBlock h;
  h.type = BlockType::kHeterodyne;
  h.steps = 4;
  h.cycles = {16, 13.5, 11.25};  // beats 2.5 and 2.25 -> 0.25 cycle: non-integer cycles allowed
  ExpectRoundTrip(Make(FringeDirection::kVertical, {h}), 16, 0.01);
}

TEST(Patterns, WritePatternSetWritesPngsAndManifest) {
  const std::string dir = std::string(RAMTK_TEST_OUTPUT_DIR) + "/pattern_set";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(RAMTK_TEST_OUTPUT_DIR);  // the parent, whichever test runs first
  WritePatternSet(dir, Make(FringeDirection::kVertical, {Ps(3, 32), Gray(6, true)}), 16);
  const FringeManifest m = ReadFringeManifest(dir + "/manifest.json");
  ASSERT_EQ(m.cameras.at("projector").size(), 9u);
  int bits = 0;
  const cv::Mat img = LoadImageDn(m.Resolve(m.cameras.at("projector")[3]), &bits);
  EXPECT_EQ(bits, 16);
  EXPECT_EQ(img.cols, 256);
  EXPECT_EQ(img.at<float>(0, 0), 0.0f);        // first code image: left half dark
  EXPECT_EQ(img.at<float>(0, 200), 65535.0f);  // right half bright
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

TEST(Patterns, GrayCodeBeforePhaseShiftRoundTrip) {
  ExpectRoundTrip(Make(FringeDirection::kVertical, {Gray(4, true), Ps(5, 8)}), 8, 0.05);
}

}  // namespace
}  // namespace ramtk::vision
