#pragma once
// The search on the destination's rectified grid (Pass::rect): rows are epipolar lines. Included by stereo_walk.cpp
// only (stereo_matcher.h).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {  // internal to stereo_walk.cpp, the one file that includes it

// The source ray r = rect_from_src (ideal, 1) in the rectified frame, given as f r_x / r_z,
// f r_y / r_z and r_z (UndistortChains); false if it points behind the rectified cameras.
inline bool Matcher::SetRectRay(double u, double v, double z) {
  if (!(z > 1e-9)) return false;
  rs_z = z;
  rs_u = u;
  rs_v = v;
  return true;
}

// Grid column of the destination point at inverse depth w, and back.
inline double Matcher::RectColumn(double w) const { return rs_u + p.rect_sign * p.rect_fb * w / rs_z - p.grid.u0; }

inline double Matcher::RectW(double column) const {
  return (column + p.grid.u0 - rs_u) * p.rect_sign * rs_z / p.rect_fb;
}

// The grid row pair (j, j + 1) around the source's rectified v, and v's fraction between them.
inline bool Matcher::RectRows(int* j, double* fv) const {
  const double v = rs_v - p.grid.v0;
  if (!(v >= 0 && v < p.grid.coord.rows - 1)) return false;
  *j = FloorToInt(v);
  *fv = v - *j;
  return true;
}

// Cell i of the row pair (r0, r1) read at the source's v: the coordinate minus c_src at its two
// columns (linear between them along the row); false if a corner is invalid or the cell holds
// a jump (its four corners span more than max_span, as Pass::cell_ok).
inline bool Matcher::RectCell(const float* r0, const float* r1, int i, double fv, double* g0, double* g1) const {
  const float a0 = r0[i], a1 = r0[i + 1], b0 = r1[i], b1 = r1[i + 1];
  const float hi = std::max(std::max(a0, a1), std::max(b0, b1));
  const float lo = std::min(std::min(a0, a1), std::min(b0, b1));
  if (!(static_cast<double>(hi) - static_cast<double>(lo) <= p.max_span)) return false;  // NaN fails
  if (!(((a0 - a0) + (a1 - a1) + (b0 - b0) + (b1 - b1)) == 0.0f)) return false;
  *g0 = a0 + fv * (static_cast<double>(b0) - a0) - c_src;
  *g1 = a1 + fv * (static_cast<double>(b1) - a1) - c_src;
  return true;
}

// The root at grid column `column` (g rising by dg_du per column there): its inverse depth, its
// pixel on the distorted image with the pixel's velocity per unit w (PixelAndVelocity: the same
// epipolar curve, parametrised by the same w), the slope of the coordinate per unit w from the
// grid cell, and the destination's variance and modulation at the pixel (Complete). False
// outside the pass's range or if the pixel's own cell is not one the curve search interpolates.
// The crossing is the grid's (the coordinate interpolated twice): ~0.01 px from the distorted
// map's own crossing inside a surface, more at its edges, against the left-right check's 0.5 px.
inline bool Matcher::RectRoot(double column, double dg_du, Root* root) const {
  root->w = RectW(column);
  if (!InRange(root->w)) return false;
  Vec2 pix;
  if (!PixelAndVelocity(root->w, &pix, &root->vel)) return false;
  root->at = CellAt(pix);
  if (!root->at.ok) return false;
  root->slope = dg_du * p.rect_sign * p.rect_fb / rs_z;
  Complete(&root->at);
  return true;
}

// The crossing near a neighbour's inverse depth w0, walked cell by cell along the row pair in
// the direction in which |g| falls at the first cell (as LineCrossing), at most 32 cells.
inline bool Matcher::RectLocalSearch(double w0, Root* root) const {
  int j;
  double fv;
  if (!RectRows(&j, &fv)) return false;
  const double c0 = RectColumn(w0);
  const int cols = p.grid.coord.cols;
  if (!(c0 >= 0 && c0 < cols - 1)) return false;
  const float* r0 = p.grid_rows.Row(j);
  const float* r1 = p.grid_rows.Row(j + 1);
  int i = FloorToInt(c0), dir = 0;
  for (int n = 0; n < 32 && i >= 0 && i + 1 < cols; ++n, i += dir) {
    double g0, g1;
    if (!RectCell(r0, r1, i, fv, &g0, &g1)) return false;
    if ((g0 > 0) != (g1 > 0) || g0 == 0) {
      if (g0 == g1) return false;
      return RectRoot(i + g0 / (g0 - g1), g1 - g0, root);
    }
    if (dir == 0) dir = ((g0 > 0) == (g1 > g0)) ? -1 : +1;
  }
  return false;
}

// Every crossing over the pass's depth range along the row pair, in order of column.
inline void Matcher::RectFullSearch(std::vector<Root>* roots) const {
  roots->clear();
  int j;
  double fv;
  if (!RectRows(&j, &fv)) return;
  const float lo = std::min(p.grid.row_min[j], p.grid.row_min[j + 1]);
  const float hi = std::max(p.grid.row_max[j], p.grid.row_max[j + 1]);
  if (!(c_src >= lo && c_src <= hi)) return;
  double ca = RectColumn(p.w_lo), cb = RectColumn(p.w_hi);
  if (ca > cb) std::swap(ca, cb);
  const int cols = p.grid.coord.cols;
  if (!(cb >= 0 && ca <= cols - 2)) return;
  const int i0 = std::max(0, FloorToInt(ca)), i1 = std::min(cols - 2, FloorToInt(cb));
  const float* r0 = p.grid_rows.Row(j);
  const float* r1 = p.grid_rows.Row(j + 1);
  // Blocks of cells whose corners' bounds (both rows) leave out c_src hold no crossing: a
  // cell's g lies between its corners' smallest and largest value.
  constexpr int kBlock = detail::RectifiedGrid::kBlock;
  const int blocks = p.grid.blocks;
  const float* lo0 = p.grid.block_min.data() + static_cast<std::size_t>(j) * blocks;
  const float* lo1 = lo0 + blocks;
  const float* hi0 = p.grid.block_max.data() + static_cast<std::size_t>(j) * blocks;
  const float* hi1 = hi0 + blocks;
  for (int b = i0 / kBlock; b <= i1 / kBlock; ++b) {
    if (!(c_src >= std::min(lo0[b], lo1[b]) && c_src <= std::max(hi0[b], hi1[b]))) continue;
    for (int i = std::max(i0, b * kBlock); i <= std::min(i1, b * kBlock + kBlock - 1); ++i) {
      double g0, g1;
      if (!RectCell(r0, r1, i, fv, &g0, &g1)) continue;
      if ((g0 > 0) == (g1 > 0) && g0 != 0) continue;
      if (g0 == g1) continue;
      Root r;
      if (RectRoot(i + g0 / (g0 - g1), g1 - g0, &r)) roots->push_back(r);
    }
  }
}

}  // namespace
}  // namespace ramtk::vision::detail
