// The tables of the curve search (stereo_pass.h): the ideal box, row, tile and run bounds, the stepping.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stereo_pass.h"

namespace ramtk::vision::detail {

// Pass::box_*: the destination image's bounding box in ideal normalised coordinates, from its
// border pixels, 2 px margin.
void SetIdealBox(Pass* pass) {
  Pass& p = *pass;
  const CameraIntrinsics& dc = *p.dst;
  p.box_x0 = p.box_y0 = 1e300;
  p.box_x1 = p.box_y1 = -1e300;
  auto add = [&](double u, double v) {
    const Vec2 q = UndistortNormalized(dc.distortion, Vec2((u - dc.cx) / dc.fx, (v - dc.cy) / dc.fy));
    p.box_x0 = std::min(p.box_x0, q.x());
    p.box_x1 = std::max(p.box_x1, q.x());
    p.box_y0 = std::min(p.box_y0, q.y());
    p.box_y1 = std::max(p.box_y1, q.y());
  };
  for (int i = 0; i <= 64; ++i) {
    const double fu = (dc.width - 1.0) * i / 64, fv = (dc.height - 1.0) * i / 64;
    add(fu, 0);
    add(fu, dc.height - 1.0);
    add(0, fv);
    add(dc.width - 1.0, fv);
  }
  p.box_x0 -= 2 / dc.fx;
  p.box_x1 += 2 / dc.fx;
  p.box_y0 -= 2 / dc.fy;
  p.box_y1 += 2 / dc.fy;
}

// The tables of the search along the distorted epipolar curve (everything it needs beyond
// Pass::cell_ok): row and tile bounds of the destination coordinates, the destination image's
// ideal bounding box, and the full search's stepping.
void BuildCurveTables(const StereoMatchOptions& options, const cv::Mat& dst_coord, Pass* pass) {
  Pass& p = *pass;
  p.row_min.assign(static_cast<std::size_t>(dst_coord.rows), std::numeric_limits<float>::infinity());
  p.row_max.assign(static_cast<std::size_t>(dst_coord.rows), -std::numeric_limits<float>::infinity());
  tbb::parallel_for(tbb::blocked_range<int>(0, dst_coord.rows, 32), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      // A coordinate is finite or NaN (unmatched), and std::min(lo, NaN) / std::max(hi, NaN) keep
      // lo / hi (the comparison with NaN is false): the NaNs drop out without a branch.
      const float* row = dst_coord.ptr<float>(y);
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (int x = 0; x < dst_coord.cols; ++x) lo = std::min(lo, row[x]), hi = std::max(hi, row[x]);
      p.row_min[y] = lo;
      p.row_max[y] = hi;
    }
  });
  p.tiles_x = (dst_coord.cols + Pass::kTile - 1) / Pass::kTile;
  p.tiles_y = (dst_coord.rows + Pass::kTile - 1) / Pass::kTile;
  p.tile_min.assign(static_cast<std::size_t>(p.tiles_x) * p.tiles_y, std::numeric_limits<float>::infinity());
  p.tile_max.assign(p.tile_min.size(), -std::numeric_limits<float>::infinity());
  tbb::parallel_for(0, p.tiles_y, [&](int ty) {
    for (int y = ty * Pass::kTile; y <= std::min(dst_coord.rows - 1, (ty + 1) * Pass::kTile); ++y) {
      const float* row = dst_coord.ptr<float>(y);
      for (int tx = 0; tx < p.tiles_x; ++tx) {
        float lo = p.tile_min[ty * p.tiles_x + tx], hi = p.tile_max[ty * p.tiles_x + tx];
        for (int x = tx * Pass::kTile; x <= std::min(dst_coord.cols - 1, (tx + 1) * Pass::kTile); ++x)
          lo = std::min(lo, row[x]), hi = std::max(hi, row[x]);  // NaNs drop out (as for the rows)
        p.tile_min[ty * p.tiles_x + tx] = lo;
        p.tile_max[ty * p.tiles_x + tx] = hi;
      }
    }
  });
  // The tile bounds over the (2 r + 1)^2 tiles around each tile.
  auto dilate = [&](int r, std::vector<float>* lo_of, std::vector<float>* hi_of) {
    lo_of->assign(p.tile_min.size(), std::numeric_limits<float>::infinity());
    hi_of->assign(p.tile_min.size(), -std::numeric_limits<float>::infinity());
    tbb::parallel_for(0, p.tiles_y, [&](int ty) {
      for (int tx = 0; tx < p.tiles_x; ++tx) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (int y = std::max(0, ty - r); y <= std::min(p.tiles_y - 1, ty + r); ++y)
          for (int x = std::max(0, tx - r); x <= std::min(p.tiles_x - 1, tx + r); ++x) {
            lo = std::min(lo, p.tile_min[y * p.tiles_x + x]);
            hi = std::max(hi, p.tile_max[y * p.tiles_x + x]);
          }
        (*lo_of)[ty * p.tiles_x + tx] = lo;
        (*hi_of)[ty * p.tiles_x + tx] = hi;
      }
    });
  };
  dilate(Pass::kDilate, &p.near_min, &p.near_max);
  dilate(1, &p.mid_min, &p.mid_max);
  p.levels = 1;
  while ((1 << p.levels) <= p.tiles_x) ++p.levels;
  {
    const std::size_t plane = p.tile_min.size();
    p.run_min.resize(plane * p.levels);
    p.run_max.resize(plane * p.levels);
    std::copy(p.tile_min.begin(), p.tile_min.end(), p.run_min.begin());
    std::copy(p.tile_max.begin(), p.tile_max.end(), p.run_max.begin());
    tbb::parallel_for(0, p.tiles_y, [&](int ty) {
      for (int k = 1; k < p.levels; ++k) {
        const float* lo_prev = p.run_min.data() + (k - 1) * plane + static_cast<std::size_t>(ty) * p.tiles_x;
        const float* hi_prev = p.run_max.data() + (k - 1) * plane + static_cast<std::size_t>(ty) * p.tiles_x;
        float* lo = p.run_min.data() + k * plane + static_cast<std::size_t>(ty) * p.tiles_x;
        float* hi = p.run_max.data() + k * plane + static_cast<std::size_t>(ty) * p.tiles_x;
        const int half = 1 << (k - 1);
        for (int tx = 0; tx < p.tiles_x; ++tx) {
          const bool both = tx + half < p.tiles_x;
          lo[tx] = both ? std::min(lo_prev[tx], lo_prev[tx + half]) : lo_prev[tx];
          hi[tx] = both ? std::max(hi_prev[tx], hi_prev[tx + half]) : hi_prev[tx];
        }
      }
    });
  }
  p.step_px = options.search_step_px;
  p.stretch = std::max(1, static_cast<int>(24.0 / p.step_px));
  p.sub_stretch = std::max(1, static_cast<int>(8.0 / p.step_px));
  // The coefficients c_2..c_8 of `steps` compositions of x -> x + x^2 (truncated at degree 8).
  auto composed = [](int steps) {
    constexpr int kDegree = 8;
    std::vector<double> g(kDegree + 1, 0.0);  // g = identity, then composed with x + x^2
    g[1] = 1;
    for (int k = 0; k < steps; ++k) {
      std::vector<double> sq(kDegree + 1, 0.0);
      for (int i = 0; i <= kDegree; ++i)
        for (int j = 0; i + j <= kDegree; ++j) sq[i + j] += g[i] * g[j];
      for (int i = 0; i <= kDegree; ++i) g[i] += sq[i];
    }
    return std::vector<double>(g.begin() + 2, g.end());
  };
  p.jump = composed(p.stretch);
  p.jump_far = composed(p.stretch * Pass::kFarStretches);
}

}  // namespace ramtk::vision::detail
