// Pass::reach: the source pixels the left-right check can accept (stereo_pass.h).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/stereo/detail/back_reach_lanes.h"
#include "stereo_pass.h"

namespace ramtk::vision::detail {

// Pass::reach: the source pixels (integer positions) that Consistent can accept for some
// destination cell. Consistent takes the cell under the crossing; with its four back matches
// finite and within 4 px of the first, it accepts a source pixel within the tolerance of their
// bilinear mean, which lies in their bounding box; otherwise one within tolerance + 1 px of the
// back match of the nearest finite corner. The tolerance is the cell's (its corners' largest
// sigma times lr_sigma_factor, at least lr_tolerance). Every such pixel is marked: a superset.
// Only cells the pass interpolates (Pass::cell_ok) mark: a crossing's sample comes from
// ValidCell, so no crossing lies in another cell, and Consistent takes the crossing's own cell.
cv::Mat BackReach(const Pass& p, int src_cols, int src_rows) {
  cv::Mat reach(src_rows, src_cols, CV_8U, cv::Scalar(0));
  const int cols = p.back_u.cols, rows = p.back_u.rows;
  // Boxes are widened by kSlack px: the float bounds here against Consistent's double sums.
  constexpr float kSlack = 1e-3f;
  const float lr_tolerance = static_cast<float>(p.lr_tolerance), factor = static_cast<float>(p.lr_sigma_factor);
  // The source pixels (integer positions) in [u0, u1] x [v0, v1]: false if none.
  auto pixels = [&](float u0, float u1, float v0, float v1, int* x0, int* x1, int* y0, int* y1) {
    if (!(u1 >= 0 && v1 >= 0 && u0 <= src_cols - 1 && v0 <= src_rows - 1)) return false;
    // Clamped to the image first: a huge tolerance (a back sigma from a nearly flat slope)
    // must not overflow the integer bounds.
    *x0 = -FloorToInt(-std::max(u0, 0.0f)), *x1 = FloorToInt(std::min(u1, src_cols - 1.0f));
    *y0 = -FloorToInt(-std::max(v0, 0.0f)), *y1 = FloorToInt(std::min(v1, src_rows - 1.0f));
    return *x0 <= *x1 && *y0 <= *y1;
  };
  // Marks pixels x0..x1 of rows y0..y1. Cells of several rows mark the same pixels at once:
  // relaxed atomic stores of the same value (plain byte stores on x86).
  auto mark = [&](int x0, int x1, int y0, int y1) {
    for (int y = y0; y <= y1; ++y) {
      uchar* r = reach.ptr<uchar>(y);
      for (int x = x0; x <= x1; ++x) __atomic_store_n(r + x, uchar{1}, __ATOMIC_RELAXED);
    }
  };
  const bool lanes = detail::Avx2Kernels();
  tbb::parallel_for(tbb::blocked_range<int>(0, rows - 1, 16), [&](const tbb::blocked_range<int>& range) {
    for (int v = range.begin(); v < range.end(); ++v) {
      // back_u and back_v are written together: NaN in both (unmatched) or finite in both.
      const float *u0 = p.back_u.ptr<float>(v), *u1 = p.back_u.ptr<float>(v + 1);
      const float *v0 = p.back_v.ptr<float>(v), *v1 = p.back_v.ptr<float>(v + 1);
      const float* s0 = p.lr_sigma ? p.back_sigma.ptr<float>(v) : nullptr;
      const float* s1 = p.lr_sigma ? p.back_sigma.ptr<float>(v + 1) : nullptr;
      // Neighbouring cells of a surface mark overlapping boxes of the same rows: they are
      // joined into one run (rows ry0..ry1, pixels rx0..rx1) and marked when the next box does
      // not join it. The marked pixels are the same; the loops run once per run, not per cell.
      int rx0 = 0, rx1 = -1, ry0 = 0, ry1 = -1;
      auto add = [&](int x0, int x1, int y0, int y1) {
        if (y0 == ry0 && y1 == ry1 && x0 <= rx1 + 1 && x1 >= rx0 - 1) {
          rx0 = std::min(rx0, x0), rx1 = std::max(rx1, x1);
          return;
        }
        if (rx0 <= rx1) mark(rx0, rx1, ry0, ry1);
        rx0 = x0, rx1 = x1, ry0 = y0, ry1 = y1;
      };
      // One cell (the scalar loop; with AVX2 only the cells the lanes leave).
      const uchar* ok_row = p.cell_ok.data() + static_cast<std::size_t>(v) * cols;  // the right image's cells
      auto cell = [&](int u) {
        if (!ok_row[u]) return;
        if (std::isnan(u0[u]) && std::isnan(u1[u]) && std::isnan(u0[u + 1]) && std::isnan(u1[u + 1])) return;
        const float bu[4] = {u0[u], u0[u + 1], u1[u], u1[u + 1]};
        const bool fin[4] = {bu[0] == bu[0], bu[1] == bu[1], bu[2] == bu[2], bu[3] == bu[3]};
        const float bv[4] = {v0[u], v0[u + 1], v1[u], v1[u + 1]};
        // The cell's tolerance, from its finite sigmas only (as Consistent).
        float tolerance = lr_tolerance;
        if (s0) {
          for (const float sk : {s0[u], s0[u + 1], s1[u], s1[u + 1]})
            if (std::isfinite(sk)) tolerance = std::max(tolerance, factor * sk);
        }
        int x0, x1, y0, y1;
        if (fin[0] & fin[1] & fin[2] & fin[3]) {
          const float umin = std::min(std::min(bu[0], bu[1]), std::min(bu[2], bu[3]));
          const float umax = std::max(std::max(bu[0], bu[1]), std::max(bu[2], bu[3]));
          const float vmin = std::min(std::min(bv[0], bv[1]), std::min(bv[2], bv[3]));
          const float vmax = std::max(std::max(bv[0], bv[1]), std::max(bv[2], bv[3]));
          // Consistent's spread (largest squared distance from the first corner) < 16: certain
          // when the box's diagonal is shorter, else computed as Consistent does.
          bool bilinear = Sq(umax - umin) + Sq(vmax - vmin) < 15.9;
          if (!bilinear) {
            double spread = 0;
            for (int k = 0; k < 4; ++k)
              spread =
                  std::max(spread, Sq(static_cast<double>(bu[k]) - bu[0]) + Sq(static_cast<double>(bv[k]) - bv[0]));
            bilinear = spread < 16.0;
          }
          if (bilinear) {
            const float t = tolerance + kSlack;
            if (pixels(umin - t, umax + t, vmin - t, vmax + t, &x0, &x1, &y0, &y1)) add(x0, x1, y0, y1);
            return;
          }
        }
        const float t = tolerance + 1 + kSlack;
        for (int k = 0; k < 4; ++k)
          if (fin[k] && pixels(bu[k] - t, bu[k] + t, bv[k] - t, bv[k] + t, &x0, &x1, &y0, &y1)) add(x0, x1, y0, y1);
      };
      int u = 0;
      if (lanes) {
        // Eight cells at a time (columns u .. u + 8 read); the cells in order, as one by one.
        detail::ReachBoxes boxes;
        for (; u + 9 <= cols; u += 8) {
          detail::ReachBoxesOfEight(u0, u1, v0, v1, s0, s1, u, lr_tolerance, factor, kSlack, src_cols, src_rows,
                                    &boxes);
          if (!boxes.fast) {
            for (int i = 0; i < 8; ++i) cell(u + i);
            continue;
          }
          for (int i = 0; i < 8; ++i) {
            if (!ok_row[u + i]) continue;
            if (!(boxes.fast >> i & 1))
              cell(u + i);
            else if (boxes.has >> i & 1)
              add(boxes.x0[i], boxes.x1[i], boxes.y0[i], boxes.y1[i]);
          }
        }
      }
      for (; u + 1 < cols; ++u) cell(u);
      if (rx0 <= rx1) mark(rx0, rx1, ry0, ry1);
    }
  });
  return reach;
}

}  // namespace ramtk::vision::detail
