// The match's walks on four AVX2 lanes (vision/stereo/include/ramtk/vision/stereo/detail/stereo_walk_lanes.h: along the curves and along
// the rectified rows) against the scalar walks:
// every root the lanes settle is the scalar walk's to the bit (RunPass recomputes each one the
// scalar way and compares all its fields), and the match's outputs with the lanes on are those
// with the lanes off, bit for bit. On a simulated set, on the real SLMaster capture (skipped if
// absent) and with the options that change what the walk reads (no left-right check, the curve
// back pass, no sigma-widened tolerance).
#include "ramtk/vision/stereo/detail/stereo_walk_lanes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <iostream>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

::testing::AssertionResult SameMap(const char* name, const cv::Mat& a, const cv::Mat& b) {
  if (a.size != b.size || a.type() != b.type()) return ::testing::AssertionFailure() << name << ": sizes differ";
  for (int y = 0; y < a.rows; ++y)
    if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0)
      return ::testing::AssertionFailure() << name << ": row " << y << " differs";
  return ::testing::AssertionSuccess();
}

// The match with the lanes off, then on with the check; returns how many roots the lanes settled.
long ExpectLanesAreTheScalarWalk(const StereoCalibration& calib, const DecodedCamera& l, const DecodedCamera& r,
                                 double period, const StereoMatchOptions& o,
                                 detail::StereoMatchTestHooks hooks = {}) {
  hooks.keep_back_matches = true;
  const detail::ScopedStereoMatchTestHooks scope(hooks);
  detail::SetAvx2Kernels(false);
  const StereoMatch scalar = MatchStereo(calib, l, r, period, o);
  detail::SetAvx2Kernels(true);
  detail::SetWalkLaneCheck(true);
  const StereoMatch lanes = MatchStereo(calib, l, r, period, o);
  const long checked = detail::WalkLanesChecked(), mismatched = detail::WalkLaneMismatches();
  detail::SetWalkLaneCheck(false);
  std::cout << lanes.summary.BriefReport() << "\nlanes settled " << checked << " roots, " << mismatched
            << " differ from the scalar walk's\n";
  EXPECT_EQ(mismatched, 0);
  EXPECT_TRUE(SameMap("right_u", scalar.right_u, lanes.right_u));
  EXPECT_TRUE(SameMap("right_v", scalar.right_v, lanes.right_v));
  EXPECT_TRUE(SameMap("sigma_px", scalar.sigma_px, lanes.sigma_px));
  EXPECT_TRUE(SameMap("depth_mm", scalar.depth_mm, lanes.depth_mm));
  EXPECT_TRUE(SameMap("point_sigma_mm", scalar.point_sigma_mm, lanes.point_sigma_mm));
  EXPECT_TRUE(SameMap("x_mm", scalar.x_mm, lanes.x_mm));
  EXPECT_TRUE(SameMap("y_mm", scalar.y_mm, lanes.y_mm));
  EXPECT_TRUE(SameMap("back_u", scalar.back_u, lanes.back_u));
  EXPECT_TRUE(SameMap("back_sigma_px", scalar.back_sigma_px, lanes.back_sigma_px));
  EXPECT_EQ(scalar.summary.matched, lanes.summary.matched);
  EXPECT_EQ(scalar.summary.rejected_lr, lanes.summary.rejected_lr);
  EXPECT_EQ(scalar.summary.rejected_no_match, lanes.summary.rejected_no_match);
  EXPECT_EQ(scalar.summary.full_searches, lanes.summary.full_searches);
  // The reach map (BackReach's boxes, eight cells at a time on the lanes) and the row lists.
  EXPECT_EQ(scalar.summary.rejected_no_back_match, lanes.summary.rejected_no_back_match);
  EXPECT_EQ(scalar.summary.rejected_noisy, lanes.summary.rejected_noisy);
  EXPECT_EQ(scalar.summary.left_valid, lanes.summary.left_valid);
  return checked;
}

TEST(StereoWalkLanes, SettleTheScalarWalksRootsOnASimulatedSet) {
  detail::SetAvx2Kernels(true);
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 43;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  const StereoCalibration calib = WrittenCalibration(MakeFringePreset("small"));
  StereoMatchOptions o;
  // Both passes on the lanes: the back pass along rectified rows, the points' pass along the
  // curves with the left-right check. They take the common case: most matches of each pass (a
  // regression that leaves them all to the scalar walk would pass the comparisons above).
  const long settled = ExpectLanesAreTheScalarWalk(calib, s.left, s.right, s.period, o);
  const StereoMatch m = MatchStereo(calib, s.left, s.right, s.period, o);
  EXPECT_GT(settled, 1.6 * m.summary.matched);
  // What the walk reads changes with these: the check off (one pass), the back pass along the
  // curves (the curve walk without a check), the tolerance not widened by the back sigma.
  o.lr_tolerance_px = 0;
  EXPECT_GT(ExpectLanesAreTheScalarWalk(calib, s.left, s.right, s.period, o), 0.8 * m.summary.matched);
  detail::StereoMatchTestHooks curve;
  curve.rectified_back_pass = false;
  EXPECT_GT(ExpectLanesAreTheScalarWalk(calib, s.left, s.right, s.period, StereoMatchOptions{}, curve),
            1.6 * m.summary.matched);
  o = StereoMatchOptions{};
  o.lr_sigma_factor = 0;
  ExpectLanesAreTheScalarWalk(calib, s.left, s.right, s.period, o);
}

// With both cameras' sampling kernel stated the settled roots move by the kernel terms
// (stereo_kernel_terms.h) on the scalar side of EmitSettled: the outputs stay those with the
// lanes off, bit for bit, and differ from the unstated match's.
TEST(StereoWalkLanes, KernelTermsGiveTheScalarWalksOutputs) {
  detail::SetAvx2Kernels(true);
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 44;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  StereoCalibration calib = WrittenCalibration(cfg);
  const StereoMatch unstated = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  calib.left.sampling_kernel = calib.right.sampling_kernel = camera::SamplingKernel{1.0, 0.0};
  const StereoMatch stated = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  EXPECT_FALSE(SameMap("depth_mm", unstated.depth_mm, stated.depth_mm));
  EXPECT_GT(ExpectLanesAreTheScalarWalk(calib, s.left, s.right, s.period, StereoMatchOptions{}),
            1.6 * stated.summary.matched);
}

TEST(StereoWalkLanes, SettleTheScalarWalksRootsOnTheRealCapture) {
  detail::SetAvx2Kernels(true);
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const DecodedCamera l = DecodeCamera(m, "left", DecodeOptions{});
  const DecodedCamera r = DecodeCamera(m, "right", DecodeOptions{});
  const long settled = ExpectLanesAreTheScalarWalk(ReadStereoCalibration(m.calibration), l, r, l.summary.period_px,
                                                   StereoMatchOptions{});
  EXPECT_GT(settled, 2 * 300000);  // of 375 412 matches and about as many back matches
}

}  // namespace
}  // namespace ramtk::vision
