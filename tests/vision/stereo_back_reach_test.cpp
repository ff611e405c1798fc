// The left-right check's shortcut (detail::StereoMatchTestHooks::skip_without_back_match): a left pixel that
// no right pixel's own match can accept is not searched. The check would reject any crossing of
// it, so the match must be the same, bit for bit, as when every pixel is searched and the check
// itself rejects them; only the counts move from rejected_lr / rejected_no_match to
// rejected_no_back_match. Checked on the real SLMaster capture (its bust throws occlusion
// shadows: skipped if the data is absent) and on a simulated set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/stereo/detail/back_reach_lanes.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

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
  detail::StereoMatchTestHooks hooks;
  hooks.skip_without_back_match = false;
  const StereoMatch every = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, {}); });
  hooks.skip_without_back_match = true;
  const StereoMatch skip = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, {}); });
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

// The eight-cell kernel against the rule written out cell by cell: four finite corners whose box
// diagonal is under 4 px (Sq(du) + Sq(dv) < 15.9 in double), the tolerance widened by the finite
// sigmas, and the box [min - t, max + t] clamped to the image. Back maps with NaN holes, corners
// far apart, sigmas that widen the tolerance, boxes off the image on every side.
TEST(StereoBackReach, EightCellsAtOnceAsTheCellRule) {
  detail::SetAvx2Kernels(true);
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> jitter(-0.6f, 0.6f), sigma(0.0f, 0.4f);
  std::uniform_int_distribution<int> pick(0, 99);
  const int src_cols = 300, src_rows = 200, width = 64;
  const float tol = 0.5f, factor = 3.0f, slack = 1e-3f;
  long fast_cells = 0, boxes = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<float> bu0(width + 1), bu1(width + 1), bv0(width + 1), bv1(width + 1), s0(width + 1), s1(width + 1);
    const float base_u = -20.0f + 3.4f * (trial % 100), base_v = -10.0f + 2.3f * (trial % 97);
    for (int u = 0; u <= width; ++u) {
      for (auto [bu, bv, s] : {std::tuple{&bu0, &bv0, &s0}, std::tuple{&bu1, &bv1, &s1}}) {
        const int r = pick(rng);
        (*bu)[u] =
            r < 8 ? std::numeric_limits<float>::quiet_NaN() : base_u + u + (r < 15 ? 5 * jitter(rng) : jitter(rng));
        (*bv)[u] = std::isnan((*bu)[u]) ? (*bu)[u] : base_v + jitter(rng);
        (*s)[u] = pick(rng) < 10 ? std::numeric_limits<float>::quiet_NaN() : sigma(rng);
      }
    }
    for (const bool with_sigma : {false, true}) {
      for (int u = 0; u + 9 <= width + 1; u += 8) {
        detail::ReachBoxes got;
        detail::ReachBoxesOfEight(bu0.data(), bu1.data(), bv0.data(), bv1.data(), with_sigma ? s0.data() : nullptr,
                                  with_sigma ? s1.data() : nullptr, u, tol, factor, slack, src_cols, src_rows, &got);
        for (int i = 0; i < 8; ++i) {
          const int c = u + i;
          const float bu[4] = {bu0[c], bu0[c + 1], bu1[c], bu1[c + 1]},
                      bv[4] = {bv0[c], bv0[c + 1], bv1[c], bv1[c + 1]};
          bool fast = true;
          for (int k = 0; k < 4; ++k) fast = fast && std::isfinite(bu[k]) && std::isfinite(bv[k]);
          float umin = 0, umax = 0, vmin = 0, vmax = 0;
          if (fast) {
            umin = std::min(std::min(bu[0], bu[1]), std::min(bu[2], bu[3]));
            umax = std::max(std::max(bu[0], bu[1]), std::max(bu[2], bu[3]));
            vmin = std::min(std::min(bv[0], bv[1]), std::min(bv[2], bv[3]));
            vmax = std::max(std::max(bv[0], bv[1]), std::max(bv[2], bv[3]));
            const double du = umax - umin, dv = vmax - vmin;
            fast = du * du + dv * dv < 15.9;
          }
          ASSERT_EQ(got.fast >> i & 1, fast ? 1 : 0) << "trial " << trial << ", cell " << c;
          if (!fast) continue;
          ++fast_cells;
          float t = tol;
          if (with_sigma)
            for (const float sk : {s0[c], s0[c + 1], s1[c], s1[c + 1]})
              if (std::isfinite(sk)) t = std::max(t, factor * sk);
          t += slack;
          const float lo_u = umin - t, hi_u = umax + t, lo_v = vmin - t, hi_v = vmax + t;
          bool has = hi_u >= 0 && hi_v >= 0 && lo_u <= src_cols - 1 && lo_v <= src_rows - 1;
          const int x0 = static_cast<int>(std::ceil(std::max(lo_u, 0.0f)));
          const int x1 = static_cast<int>(std::floor(std::min(hi_u, src_cols - 1.0f)));
          const int y0 = static_cast<int>(std::ceil(std::max(lo_v, 0.0f)));
          const int y1 = static_cast<int>(std::floor(std::min(hi_v, src_rows - 1.0f)));
          has = has && x0 <= x1 && y0 <= y1;
          ASSERT_EQ(got.has >> i & 1, has ? 1 : 0) << "trial " << trial << ", cell " << c;
          if (!has) continue;
          ++boxes;
          EXPECT_EQ(got.x0[i], x0);
          EXPECT_EQ(got.x1[i], x1);
          EXPECT_EQ(got.y0[i], y0);
          EXPECT_EQ(got.y1[i], y1);
        }
      }
    }
  }
  EXPECT_GT(fast_cells, 20000);
  EXPECT_GT(boxes, 10000);
}

}  // namespace
}  // namespace ramtk::vision
