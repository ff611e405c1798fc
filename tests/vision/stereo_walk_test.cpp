// The walking search (default: seeded from the left neighbour's match, whole-range search as the
// fallback) against the reference whole-range search of every pixel (detail::StereoMatchTestHooks::
// full_search): nearly the same pixels matched, at the same crossings, on a simulated set and on the real
// SLMaster capture (skipped if absent).
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

struct Comparison {
  long walk = 0, full = 0, both = 0, far = 0;
  double max_diff_px = 0;
};

// Crossings are refined until their bracket is < 1e-6 px long, so the same crossing reached from
// two brackets agrees to ~1e-6 px; stored as float (u, v ~ 1e3 px: rounding 6e-5 px).
Comparison Compare(const StereoCalibration& calib, const DecodedCamera& l, const DecodedCamera& r, double period,
                   StereoMatchOptions o) {
  // The searches' crossings are compared: the second-order terms that move the outputs after
  // the search (stereo_kernel_terms.h) are left out, and with them the kernel estimate (each
  // run's own back matches give a slightly different one).
  o.noise_bias_term = false;
  o.kernel_estimate = StereoMatchOptions::KernelEstimate::kOff;
  detail::StereoMatchTestHooks hooks;
  hooks.full_search = false;
  const StereoMatch walk = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  hooks.full_search = true;
  const StereoMatch full = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  Comparison c;
  c.walk = walk.summary.matched;
  c.full = full.summary.matched;
  for (int y = 0; y < walk.right_u.rows; ++y)
    for (int x = 0; x < walk.right_u.cols; ++x) {
      const float wu = walk.right_u.at<float>(y, x), fu = full.right_u.at<float>(y, x);
      if (!std::isfinite(wu) || !std::isfinite(fu)) continue;
      ++c.both;
      const double d = std::hypot(wu - fu, walk.right_v.at<float>(y, x) - full.right_v.at<float>(y, x));
      c.max_diff_px = std::max(c.max_diff_px, d);
      if (d > 1e-3) ++c.far;
    }
  std::cout << "walk " << c.walk << " matches (" << walk.summary.full_searches << " whole-range searches), full "
            << c.full << " (" << full.summary.full_searches << "), both " << c.both << ", " << c.far
            << " at another crossing, largest difference " << c.max_diff_px << " px\n";
  return c;
}

void ExpectSameMatches(const Comparison& c) {
  // NOT identical sets (open, docs/performance.md): the walk brackets a crossing with half-steps
  // from the neighbour's depth, the full search with 2-px samples from the range start, so near
  // mask and occlusion edges (a sample in an invalid cell) one finds crossings the other steps
  // over, and where a curve crosses the same coordinate twice the full search tries the crossing
  // of best modulation agreement first. Measured at the commit of this test: walk-only 0.52 %,
  // full-only 0.41 %, other crossing 0.09 % of the matches on the simulated set; 0.37 %, 0.003 %,
  // 1 pixel on SLMaster; with run starts seeded from the row above: 0.60 % / 0.56 % / 0.08 %
  // simulated, 0.45 % / 0.003 % / 1 pixel on SLMaster. Bounds: 1 % / 1 % / 0.2 % -- a regression in either search (a
  // lost crossing class, a wrong bracket) moves far more pixels than that.
  EXPECT_LE(c.walk - c.both, 0.01 * c.full);
  EXPECT_LE(c.full - c.both, 0.01 * c.full);
  EXPECT_LE(c.far, 0.002 * c.full);
  EXPECT_GT(c.both, 0.98 * c.full);
}

TEST(StereoWalk, SameMatchesAsFullSearchOnASimulatedSet) {
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 11;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  const Comparison c = Compare(WrittenCalibration(MakeFringePreset("small")), s.left, s.right, s.period, {});
  ExpectSameMatches(c);
}

TEST(StereoWalk, SameMatchesAsFullSearchOnSlmaster) {
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const DecodedCamera l = DecodeCamera(m, "left", DecodeOptions{});
  const DecodedCamera r = DecodeCamera(m, "right", DecodeOptions{});
  StereoMatchOptions o;
  o.min_depth_mm = 300;  // as ScanPipeline.SlmasterBinocularReconstructs and the bench
  o.max_depth_mm = 1500;
  const Comparison c = Compare(ReadStereoCalibration(m.calibration), l, r, l.summary.period_px, o);
  ExpectSameMatches(c);
}

}  // namespace
}  // namespace ramtk::vision
