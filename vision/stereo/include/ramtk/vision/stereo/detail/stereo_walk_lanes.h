#pragma once
// The match's walk (stereo_walk.cpp, RunPass: a search from the left neighbour's inverse depth,
// then Matcher::Accept) for four source pixels at once, one per lane, on CPUs with AVX2. Both
// searches: along the epipolar curves (Matcher::LocalSearch, the left-to-right pass) and along
// the rectified rows (Matcher::RectLocalSearch and RectRoot, the back pass).
//
// Each lane takes the scalar code's operations in its order (no fused multiply-add), so a root
// the lanes settle is the scalar walk's bit for bit. The lanes settle only the common case: the
// crossing within the first three cells of the tangent line (four of the rectified row), the
// curve's pixel there within 1e-4 px of the line's (no second round), and a root the left-right
// check, if any, accepts through the interpolated back match. Every other pixel (about 3 % of
// the left-to-right pass on the SLMaster capture) is left to the scalar walk, which then starts
// from scratch; a lane never settles a root the scalar walk would not. RunPass checks the two
// against each other when SetWalkLaneCheck is on (tests/vision/stereo_walk_lanes_test.cpp).
#include <cstddef>

#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision::detail {

// What the walk reads of a pass (fixed for the pass): the destination camera, its maps, the
// depth range and the left-right check's back matches (Pass in stereo_pass.h).
struct WalkMaps {
  double t[3] = {0, 0, 0};  // dst_from_src translation, mm
  double fx = 1, fy = 1, cx = 0, cy = 0;
  Distortion distortion;
  int cols = 0, rows = 0;  // the destination image
  const float* coord = nullptr;
  const float* sigma = nullptr;
  const float* modulation = nullptr;
  int stride = 0;                          // of the three maps above (one layout), floats
  const unsigned char* cell_ok = nullptr;  // Pass::cell_ok, cols per row
  double step_px = 0, max_span = 0;
  double w_lo = 0, w_hi = 0;                              // the pass's inverse-depth range
  double box_x0 = 0, box_x1 = 0, box_y0 = 0, box_y1 = 0;  // Pass::box_*
  double max_modulation_ratio = 1e300;
  bool lr_check = false, lr_sigma = false;
  double lr_tolerance = 0, lr_sigma_factor = 0;
  const float *back_u = nullptr, *back_v = nullptr, *back_sigma = nullptr;
  int back_stride = 0;  // of the three back maps (one layout), floats
  int back_cols = 0, back_rows = 0;
  // The rectified search (Pass::rect): the destination's coordinate map on the rectified grid,
  // its origin, and the rectified frame's sign and f times the baseline.
  bool rect = false;
  const float* grid = nullptr;
  int grid_stride = 0, grid_cols = 0, grid_rows = 0;
  double grid_u0 = 0, grid_v0 = 0;
  double rect_sign = 1, rect_fb = 0;
  bool points = false;  // also the points' depth, x, y and sigma (Pass::points)
};

// Four source pixels: in, their rays, coordinates and seeds; out, the roots the lanes settled.
struct WalkLanes {
  int active = 0;                 // bit i: lane i holds a pixel
  double a_x[4], a_y[4], a_z[4];  // R (ideal, 1) of the source pixel
  double rs_u[4], rs_v[4], rs_z[4];  // its rectified ray (the rectified search)
  double c_src[4];                // its coordinate, projector px
  double w0[4];                   // the seed (the left neighbour's inverse depth)
  double b_src[4];                // its modulation, DN
  double su[4], sv[4];            // its column and row
  double sigma_src[4];            // its coordinate's sigma, projector px
  double ideal_x[4], ideal_y[4];  // its ideal normalised coordinates (WalkMaps::points)
  int found = 0;                  // bit i: lane i's root is settled below
  double w[4], slope[4], pix_x[4], pix_y[4], var[4], modulation[4], vel_x[4], vel_y[4];
  int u0[4], v0[4];  // the root's cell
  // The settled pixels' outputs as RunPass writes them: the right pixel, the match sigma (px)
  // and, with WalkMaps::points, the depth, x, y and point sigma (mm).
  float out_u[4], out_v[4], out_sigma[4], out_depth[4], out_x[4], out_y[4], out_point_sigma[4];
  // The same before rounding to float (the tests compare them with stereo_walk.cpp's Outputs).
  double out_sigma_d[4], out_x_d[4], out_y_d[4], out_point_sigma_d[4];
};

// Settles what it can of the active lanes (call only where Avx2Kernels() holds).
void WalkFourLanes(const WalkMaps& maps, WalkLanes* lanes);

// Tests: RunPass also walks every pixel the lanes settled the scalar way and counts the roots
// that differ in any bit (or that the scalar walk does not accept).
void SetWalkLaneCheck(bool on);
bool WalkLaneCheck();
void CountWalkLaneCheck(bool same);
void CountWalkLaneMismatch();  // a mismatch found beside a root already counted (its outputs)
long WalkLanesChecked();
long WalkLaneMismatches();

}  // namespace ramtk::vision::detail
