#pragma once
// Comparison switches of the stereo match. Each selects the reference a production path is
// tested against, or keeps a map only a comparison needs; none is part of StereoMatchOptions.
// They are process-wide and read at the start of each MatchStereo: tests and benchmarks set them
// with ScopedStereoMatchTestHooks, the command line from RAMTK_TEST_HOOKS (tools/test_hooks.cpp).
// Production code never sets them.

namespace ramtk::vision::detail {

struct StereoMatchTestHooks {
  // Every pixel is searched over the whole depth range. false (production): a pixel whose left
  // neighbour matched walks from that neighbour's depth to the equal-coordinate crossing (the
  // coordinate is monotone along the curve, so a few samples); a run start walks from the match
  // of the pixel above (rows run in fixed blocks of 16, each in order); it falls back to the
  // whole-range search only if the walk finds no crossing or its crossing is rejected by the
  // modulation or left-right check. Both give the same matches (ctest StereoWalk.*).
  bool full_search = false;
  // The whole-range search itself without pruning: every sample along the curve is evaluated,
  // with none of the tile bounds that prove stretches free of crossings. Far slower (minutes on
  // a whole frame); it finds the same crossings as the pruned search (ctest StereoFullSearch.*).
  bool exhaustive_search = false;
  // With the left-right check: a left pixel that no right pixel's own match can accept (none
  // lands within the check's tolerance of it, BackReach in stereo_back_reach.cpp) is not searched and
  // is counted in rejected_no_back_match: any crossing would fail the check. The matches are the
  // same either way (ctest StereoBackReach.*). false: search them.
  bool skip_without_back_match = true;
  // The right-to-left pass, whose matches only feed the left-right check, searches rectified
  // rows: both cameras are turned about their centres to one orientation whose x axis is the
  // baseline, so every epipolar curve becomes a row; the left camera's coordinate map is
  // resampled once onto integer rectified pixels (bilinear reads of the cells the curve search
  // interpolates), and each right pixel's crossing is found along one row pair, in closed form
  // per cell. Its distorted pixel, variance and modulation are then read as in the curve search.
  // The crossing itself is the grid's (the coordinate interpolated twice): ~0.01 px from the curve
  // search's inside a surface, against the check's 0.5 px tolerance. The left-to-right pass, which
  // gives the points, always searches along the curves: only which pixels the check accepts can
  // differ, at edges (ctest StereoRectified.*). false: both passes along the curves.
  bool rectified_back_pass = true;
  // Keep the right-to-left pass's matches (StereoMatch::back_u, back_v, back_sigma_px).
  bool keep_back_matches = false;
};

StereoMatchTestHooks CurrentStereoMatchTestHooks();
void SetStereoMatchTestHooks(const StereoMatchTestHooks& hooks);

// Sets the hooks for its lifetime and restores the previous ones after.
class ScopedStereoMatchTestHooks {
 public:
  explicit ScopedStereoMatchTestHooks(const StereoMatchTestHooks& hooks) : saved_(CurrentStereoMatchTestHooks()) {
    SetStereoMatchTestHooks(hooks);
  }
  ~ScopedStereoMatchTestHooks() { SetStereoMatchTestHooks(saved_); }
  ScopedStereoMatchTestHooks(const ScopedStereoMatchTestHooks&) = delete;
  ScopedStereoMatchTestHooks& operator=(const ScopedStereoMatchTestHooks&) = delete;

 private:
  StereoMatchTestHooks saved_;
};

}  // namespace ramtk::vision::detail
