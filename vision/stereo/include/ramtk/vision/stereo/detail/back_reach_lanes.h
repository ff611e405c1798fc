#pragma once
// The back-match reach (stereo_back_reach.cpp, BackReach) of eight cells at once on CPUs with AVX2:
// the common cell (four finite back matches close together) and its box of source pixels, as
// the scalar loop computes them (tests/vision/stereo_back_reach_test.cpp compares the reach maps
// with the lanes on and off).

namespace ramtk::vision::detail {

// Cells u .. u + 7 of a pair of back-map rows (back_u rows bu0, bu1, back_v rows bv0, bv1, the
// back sigma rows s0, s1 or null): `fast` bit i when cell u + i has four finite corners whose
// box diagonal is below 4 px (the interpolated check), and then `has` bit i when its box
// [min - t, max + t] (t = the cell's tolerance + slack) holds a source pixel, pixels
// x0..x1 x y0..y1. The other cells are left to the scalar loop. Reads columns u .. u + 8.
struct ReachBoxes {
  int fast = 0, has = 0;
  int x0[8], x1[8], y0[8], y1[8];
};
void ReachBoxesOfEight(const float* bu0, const float* bu1, const float* bv0, const float* bv1, const float* s0,
                       const float* s1, int u, float lr_tolerance, float factor, float slack, int src_cols,
                       int src_rows, ReachBoxes* out);

}  // namespace ramtk::vision::detail
