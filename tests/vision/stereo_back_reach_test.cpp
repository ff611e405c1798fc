// The left-right check's shortcut (StereoMatchOptions::skip_without_back_match): a left pixel that
// no right pixel's own match can accept is not searched. The check would reject any crossing of
// it, so the match must be the same, bit for bit, as when every pixel is searched and the check
// itself rejects them; only the counts move from rejected_lr / rejected_no_match to
// rejected_no_back_match. Checked on the real SLMaster capture (its bust throws occlusion
// shadows: skipped if the data is absent) and on a simulated set.
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode.h"
#include "ramtk/vision/manifest.h"
#include "ramtk/vision/stereo_match.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

// Same bytes (NaN where unmatched in both), not merely close values.
bool SameBits(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int y = 0; y < a.rows; ++y)
    if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
  return true;
}

// Returns the number of pixels the shortcut skipped.
long ExpectSameMatchWithTheShortcut(const StereoCalibration& calib, const DecodedCamera& l, const DecodedCamera& r,
                                    double period) {
  StereoMatchOptions o;
  o.skip_without_back_match = false;
  const StereoMatch every = MatchStereo(calib, l, r, period, o);
  o.skip_without_back_match = true;
  const StereoMatch skip = MatchStereo(calib, l, r, period, o);
  const StereoMatchSummary &a = every.summary, &b = skip.summary;
  std::cout << "every pixel searched: " << a.BriefReport() << "\nshortcut: " << b.BriefReport() << "\n";
  EXPECT_EQ(a.rejected_no_back_match, 0);
  EXPECT_EQ(b.matched, a.matched);
  EXPECT_EQ(b.left_valid, a.left_valid);
  EXPECT_EQ(b.rejected_noisy, a.rejected_noisy);
  // The skipped pixels are exactly the ones that had been rejected by the search or the check.
  EXPECT_EQ(b.rejected_no_back_match + b.rejected_lr + b.rejected_no_match, a.rejected_lr + a.rejected_no_match);
  EXPECT_LE(b.rejected_lr, a.rejected_lr);
  EXPECT_LE(b.rejected_no_match, a.rejected_no_match);
  EXPECT_TRUE(SameBits(skip.right_u, every.right_u));
  EXPECT_TRUE(SameBits(skip.right_v, every.right_v));
  EXPECT_TRUE(SameBits(skip.depth_mm, every.depth_mm));
  EXPECT_TRUE(SameBits(skip.sigma_px, every.sigma_px));
  EXPECT_TRUE(SameBits(skip.point_sigma_mm, every.point_sigma_mm));
  EXPECT_EQ(skip.summary.median_sigma_px, every.summary.median_sigma_px);
  return b.rejected_no_back_match;
}

TEST(StereoBackReach, SkippingPixelsNoBackMatchAcceptsLeavesTheRealMatchUnchanged) {
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const DecodedCamera l = DecodeCamera(m, "left", DecodeOptions{});
  const DecodedCamera r = DecodeCamera(m, "right", DecodeOptions{});
  const long skipped = ExpectSameMatchWithTheShortcut(ReadStereoCalibration(m.calibration), l, r, l.summary.period_px);
  // The bust's occlusion shadows: 24 264 of the 34 535 rejected left pixels (2026-11-26). A map
  // that marked nothing would skip every pixel and fail above; one that marked everything, none.
  EXPECT_GT(skipped, 10000);
}

TEST(StereoBackReach, SkippingPixelsNoBackMatchAcceptsLeavesTheSimulatedMatchUnchanged) {
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 31;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  const long skipped =
      ExpectSameMatchWithTheShortcut(WrittenCalibration(MakeFringePreset("small")), s.left, s.right, s.period);
  EXPECT_GT(skipped, 0);
}

}  // namespace
}  // namespace ramtk::vision
