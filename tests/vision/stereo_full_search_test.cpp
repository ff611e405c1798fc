// The whole-range search's pruning (tile bounds over dilated tiles, sub-stretches, segment
// bounding boxes, the row bounds) against the search that evaluates every sample along the curve
// (detail::StereoMatchTestHooks::exhaustive_search): the pruning only skips samples it has proven cannot
// bracket a crossing, so both find the same crossings. Checked with every pixel searched over the
// whole range (full_search), on a simulated set and on a band of rows of the real SLMaster capture
// (skipped if absent).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

// Both searches bracket each crossing between the same two samples (their positions differ by
// the rounding of the stepping, ~1e-13 relative) and refine it to a 1e-3 px bracket; the match is
// stored as float. 1e-3 px bounds the difference of one crossing reached twice.
void ExpectSameCrossings(const StereoCalibration& calib, const DecodedCamera& l, const DecodedCamera& r, double period,
                         StereoMatchOptions o) {
  detail::StereoMatchTestHooks hooks;
  hooks.full_search = true;
  hooks.exhaustive_search = false;
  const StereoMatch pruned = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  hooks.exhaustive_search = true;
  const StereoMatch every = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  long only_pruned = 0, only_every = 0, both = 0;
  double worst_px = 0;
  for (int y = 0; y < pruned.right_u.rows; ++y)
    for (int x = 0; x < pruned.right_u.cols; ++x) {
      const bool a = std::isfinite(pruned.right_u.at<float>(y, x)), b = std::isfinite(every.right_u.at<float>(y, x));
      only_pruned += a && !b;
      only_every += b && !a;
      if (!(a && b)) continue;
      ++both;
      worst_px = std::max(
          worst_px, static_cast<double>(std::hypot(pruned.right_u.at<float>(y, x) - every.right_u.at<float>(y, x),
                                                   pruned.right_v.at<float>(y, x) - every.right_v.at<float>(y, x))));
    }
  std::cout << "pruned " << pruned.summary.matched << ", every sample " << every.summary.matched << ", both " << both
            << ", largest difference " << worst_px << " px\n";
  EXPECT_GT(both, 1000);
  EXPECT_EQ(only_pruned, 0);
  EXPECT_EQ(only_every, 0);
  EXPECT_LT(worst_px, 1e-3);
  EXPECT_EQ(pruned.summary.rejected_lr, every.summary.rejected_lr);
  EXPECT_EQ(pruned.summary.rejected_no_match, every.summary.rejected_no_match);
}

TEST(StereoFullSearch, PruningFindsTheCrossingsOfEverySampleOnASimulatedSet) {
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 12;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  StereoMatchOptions o;
  o.search_step_px = 0.8;  // sub-stretches of 10 samples
  ExpectSameCrossings(WrittenCalibration(MakeFringePreset("small")), s.left, s.right, s.period, o);
}

TEST(StereoFullSearch, PruningFindsTheCrossingsOfEverySampleOnSlmaster) {
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  DecodedCamera l = DecodeCamera(m, "left", DecodeOptions{});
  const DecodedCamera r = DecodeCamera(m, "right", DecodeOptions{});
  // A band of 24 left rows through the object (every sample of a whole frame takes minutes); the
  // right camera whole. Without the left-right check only the left-to-right pass runs.
  const int y0 = l.mask.rows / 2 - 12, y1 = y0 + 24;
  l.mask.rowRange(0, y0).setTo(0);
  l.mask.rowRange(y1, l.mask.rows).setTo(0);
  StereoMatchOptions o;
  o.lr_tolerance_px = 0;
  // The whole default depth range (100 mm to 10 m): the longest curves, the most pruning.
  ExpectSameCrossings(ReadStereoCalibration(m.calibration), l, r, l.summary.period_px, o);
}

}  // namespace
}  // namespace ramtk::vision
