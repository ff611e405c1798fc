#pragma once
// Every crossing of the coordinate along the epipolar curve over the whole depth range (Matcher::FullSearch),
// pruned by the destination's tile bounds. Included by stereo_walk.cpp only
// (stereo_matcher.h).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {  // internal to stereo_walk.cpp, the one file that includes it

// Whether two sign bounds (TileSign's values) allow no pair of opposite sign between them.
inline bool CompatibleSigns(int s1, int s2) { return s1 == s2 || s1 == 2 || s2 == 2; }

// What a sample at destination pixel `pix` can be, from the tile bounds alone: +1 (if valid,
// f > 0), -1 (if valid, f < 0), 2 (never valid: outside the image or no valid corner), 0 (unknown).
inline int Matcher::TileSign(bool in_front, const Vec2& pix) const {
  if (!in_front) return 2;
  const double u = pix.x(), v = pix.y();
  const int u0 = FloorToInt(u), v0 = FloorToInt(v);
  if (u0 < 0 || v0 < 0 || u0 + 1 >= p.dst_coord.cols || v0 + 1 >= p.dst_coord.rows) return 2;
  const int tx = u0 / Pass::kTile, ty = v0 / Pass::kTile;
  const std::size_t t = static_cast<std::size_t>(ty) * p.tiles_x + tx;
  const float lo = p.tile_min[t], hi = p.tile_max[t];
  if (!(lo <= hi)) return 2;
  const double margin = 1e-3;  // projector px, far above the rounding of a bilinear sum
  if (c_src < lo - margin) return +1;
  if (c_src > hi + margin) return -1;
  return 0;
}

// TileSign over the dilated bounds: what every sample within kDilate * kTile pixels of `pix`
// can be. A pixel up to kDilate tiles outside the image takes the nearest tile's bounds
// (whose neighbourhood is a superset of the part inside the image).
inline int Matcher::NearSign(bool in_front, const Vec2& pix) const {
  return BoundSign(in_front, pix, Pass::kTile, p.tiles_x, p.tiles_y, Pass::kDilate, p.near_min, p.near_max);
}

// The same over the 3 x 3 tile bounds: what every sample within kTile pixels of `pix` can be.
inline int Matcher::MidSign(bool in_front, const Vec2& pix) const {
  return BoundSign(in_front, pix, Pass::kTile, p.tiles_x, p.tiles_y, 1, p.mid_min, p.mid_max);
}

// True if no two samples on the curve between pixels pa and pb can have opposite signs: the
// tile bounds over the chord's bounding box, widened by twice the curve's bend (the distance of
// its pixel pm between them from the chord) and a pixel, hold c_src outside or no valid cell.
inline bool Matcher::SegmentClear(const Vec2& pa, const Vec2& pb, const Vec2& pm) const {
  const Vec2 d = pb - pa, e = pm - pa;
  const double len = d.norm();
  const double bend = len > 0 ? std::abs(d.x() * e.y() - d.y() * e.x()) / len : e.norm();
  const double margin_px = 2.0 * bend + 1.0;
  const double x0 = std::min({pa.x(), pb.x(), pm.x()}) - margin_px, x1 = std::max({pa.x(), pb.x(), pm.x()}) + margin_px;
  const double y0 = std::min({pa.y(), pb.y(), pm.y()}) - margin_px, y1 = std::max({pa.y(), pb.y(), pm.y()}) + margin_px;
  if (!(std::abs(x0) < 1e7 && std::abs(x1) < 1e7 && std::abs(y0) < 1e7 && std::abs(y1) < 1e7)) return false;
  const int tx0 = std::max(0, FloorToInt(x0 / Pass::kTile));
  const int tx1 = std::min(p.tiles_x - 1, FloorToInt(x1 / Pass::kTile));
  const int ty0 = std::max(0, FloorToInt(y0 / Pass::kTile));
  const int ty1 = std::min(p.tiles_y - 1, FloorToInt(y1 / Pass::kTile));
  if (tx0 > tx1 || ty0 > ty1) return true;  // outside the image: no valid sample
  const int k = 31 - __builtin_clz(static_cast<unsigned>(tx1 - tx0 + 1));
  const std::size_t plane = static_cast<std::size_t>(p.tiles_y) * p.tiles_x;
  const float* lo_k = p.run_min.data() + k * plane;
  const float* hi_k = p.run_max.data() + k * plane;
  const int tx_b = tx1 - (1 << k) + 1;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int ty = ty0; ty <= ty1; ++ty) {
    const std::size_t row = static_cast<std::size_t>(ty) * p.tiles_x;
    lo = std::min({lo, lo_k[row + tx0], lo_k[row + tx_b]});
    hi = std::max({hi, hi_k[row + tx0], hi_k[row + tx_b]});
  }
  if (!(lo <= hi)) return true;
  const double margin = 1e-3;
  return c_src < lo - margin || c_src > hi + margin;
}

// The sign test of NearSign and MidSign on bounds over cells of cell_px pixels (nx x ny of
// them), each holding every cell within reach of any point of it; a pixel up to `outside`
// cells outside the image takes the nearest cell's bounds, one farther out reaches no cell.
inline int Matcher::BoundSign(bool in_front, const Vec2& pix, int cell_px, int nx, int ny, int outside,
                              const std::vector<float>& lo_of, const std::vector<float>& hi_of) const {
  if (!in_front) return 0;  // unknown: the fine search decides
  const double u = pix.x(), v = pix.y();
  if (!(std::abs(u) < 1e7 && std::abs(v) < 1e7)) return 0;
  const int tx = FloorDiv(FloorToInt(u), cell_px);
  const int ty = FloorDiv(FloorToInt(v), cell_px);
  if (tx < -outside || ty < -outside || tx >= nx + outside || ty >= ny + outside) return 2;
  const std::size_t t = static_cast<std::size_t>(std::clamp(ty, 0, ny - 1)) * nx + std::clamp(tx, 0, nx - 1);
  const float lo = lo_of[t], hi = hi_of[t];
  if (!(lo <= hi)) return 2;
  const double margin = 1e-3;
  if (c_src < lo - margin) return +1;
  if (c_src > hi + margin) return -1;
  return 0;
}

// FullSearch without any pruning: every sample from w_lo on, one step at a time.
inline void Matcher::ExhaustiveSearch(std::vector<Root>* roots) const {
  if (!(std::min(Speed(w_lo), Speed(w_hi)) > 1e-9)) return;
  Sample prev;
  double w_prev = w_lo;
  for (double w = w_lo; w <= w_hi; w = Step(w)) NextSample(w, Eval(w), &prev, &w_prev, roots);
}

// Quick rejection: false if c_src lies outside every coordinate on the rows the curve crosses.
inline bool Matcher::RowsMayCross() const {
  Vec2 pa, pb;
  if (Pixel(w_lo, &pa) && Pixel(w_hi, &pb)) {
    const int rows = static_cast<int>(p.row_min.size());
    const double mid_w = 0.5 * (w_lo + w_hi);
    Vec2 pm;
    double y0 = std::min(pa.y(), pb.y()), y1 = std::max(pa.y(), pb.y());
    if (Pixel(mid_w, &pm)) y0 = std::min(y0, pm.y()), y1 = std::max(y1, pm.y());
    const int r0 = std::max(0, FloorToInt(y0) - 2);
    const int r1 = std::min(rows - 1, static_cast<int>(std::ceil(y1)) + 2);
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int r = r0; r <= r1; ++r) lo = std::min(lo, p.row_min[r]), hi = std::max(hi, p.row_max[r]);
    if (!(c_src >= lo && c_src <= hi)) return false;
  }
  return true;
}

// One stretch of FullSearch that its end samples could not prove clear (the sample positions
// `ws`, its first and last pixel): taken in sub-stretches. `prev_fine`: the sample at ws[0] was
// evaluated (it is `prev`); on return, the same for the stretch's last sample.
inline void Matcher::SampleStretch(const std::vector<double>& ws, const Vec2& pix_a, bool front_a, const Vec2& pix_b,
                                   bool front_b, bool* prev_fine_io, Sample* prev_io, double* w_prev_io,
                                   std::vector<Root>* roots) const {
  constexpr double kMaxSubChordPx = 2.0 * Pass::kTile - 4.0;  // ends within reach of each sample (MidSign)
  bool& prev_fine = *prev_fine_io;
  Sample& prev = *prev_io;
  double& w_prev = *w_prev_io;
  // The stretch in sub-stretches: those the 3 x 3 tile bounds prove clear (MidSign, the
  // same argument over a shorter chord) are stepped over, the others evaluated sample by
  // sample. Near a crossing this evaluates ~1/3 of the stretch's samples.
  const std::size_t n = ws.size() - 1;
  std::size_t j = 0;
  Vec2 pix_j = pix_a;
  int mid_j = MidSign(front_a, pix_j);
  while (j < n) {
    const std::size_t e = std::min(n, j + static_cast<std::size_t>(p.sub_stretch));
    Vec2 pix_e = pix_b;
    const bool front_e = e == n ? front_b : Pixel(ws[e], &pix_e);
    const int mid_e = MidSign(front_e, pix_e);
    const bool sub_clear =
        mid_j != 0 && mid_e != 0 && CompatibleSigns(mid_j, mid_e) && (pix_e - pix_j).norm() <= kMaxSubChordPx;
    if (!sub_clear) {
      std::size_t k0 = j + 1;
      if (!prev_fine) {
        prev = Sample{};
        k0 = j;
      }
      for (std::size_t k = k0; k <= e; ++k) {
        Vec2 pix;
        const bool front = Pixel(ws[k], &pix);
        NextSample(ws[k], TileSign(front, pix) == 2 ? Sample{} : EvalAt(pix), &prev, &w_prev, roots);
      }
    }
    prev_fine = !sub_clear;
    j = e;
    pix_j = pix_e;
    mid_j = mid_e;
  }
}

// Every crossing over the whole inverse-depth range, in order of w.
inline void Matcher::FullSearch(std::vector<Root>* roots) const {
  roots->clear();
  if (!(w_lo < w_hi)) return;
  if (p.exhaustive) {
    ExhaustiveSearch(roots);
    return;
  }
  if (!RowsMayCross()) return;
  // The samples lie every step_px along the curve (w_{n+1} = w_n + step_px / speed(w_n)); a
  // crossing lies between two consecutive valid samples of opposite sign. The samples are taken
  // in stretches of kStretch: a stretch whose two end samples fix, through the dilated tile
  // bounds (NearSign), the same sign (or no valid cell) for every sample within reach, holds
  // no pair of opposite sign, so its samples are not evaluated, only stepped over (Speed is a
  // few flops, Pixel and EvalAt the cost). The samples and crossings are exactly those of
  // evaluating every sample; the pixels with no crossing at all (rejected pixels) cost about
  // kStretch times less.
  const int kStretch = p.stretch;
  constexpr double kMaxChordPx = 2.0 * Pass::kDilate * Pass::kTile - 4.0;  // ends within reach of each sample
  thread_local std::vector<double> ws;                                     // one stretch of sample positions
  Sample prev;
  double w_prev = w_lo;
  // The speed is smallest at an end of the range (q_z is linear in w and positive there).
  if (!(std::min(Speed(w_lo), Speed(w_hi)) > 1e-9)) return;
  double w = w_lo;
  Vec2 pix_a = Vec2::Zero();
  bool front_a = Pixel(w, &pix_a);
  int sign_a = NearSign(front_a, pix_a);
  bool prev_fine = false;  // the sample at w was evaluated (it is prev)
  bool more = true;
  while (more) {
    // kFarStretches clear stretches, proven by the tile bounds over their bounding box
    // (SegmentClear), are stepped over at once (Pass::jump_far): far from the crossing most of
    // a long curve goes this way.
    if (sign_a != 0) {
      const double u = a.z() + p.T.z() * w;
      const double x = step_per_k * p.T.z() * u;
      if (std::abs(x) * kStretch * Pass::kFarStretches < 0.02) {
        double poly = 0;
        for (auto it = p.jump_far.rbegin(); it != p.jump_far.rend(); ++it) poly = poly * x + *it;
        const double w_end = w + step_per_k * u * u * poly;
        if (w_end <= w_hi) {
          Vec2 pix_b = Vec2::Zero(), pix_m = Vec2::Zero();
          const bool front_b = Pixel(w_end, &pix_b);
          const bool front_m = Pixel(0.5 * (w + w_end), &pix_m);
          if (front_a && front_b && front_m && (pix_b - pix_a).norm() <= Pass::kMaxFarChordPx &&
              SegmentClear(pix_a, pix_b, pix_m)) {
            w = w_end;
            sign_a = NearSign(front_b, pix_b);
            pix_a = pix_b;
            front_a = front_b;
            prev_fine = false;
            continue;
          }
        }
      }
    }
    // A clear stretch is only stepped over: its end in one jump (Pass::jump), no samples.
    {
      const double u = a.z() + p.T.z() * w;
      const double x = step_per_k * p.T.z() * u;
      if (std::abs(x) * kStretch < 0.02) {
        double poly = 0;
        for (auto it = p.jump.rbegin(); it != p.jump.rend(); ++it) poly = poly * x + *it;
        const double w_end = w + step_per_k * u * u * poly;
        if (w_end <= w_hi) {
          Vec2 pix_b = Vec2::Zero();
          const bool front_b = Pixel(w_end, &pix_b);
          const int sign_b = NearSign(front_b, pix_b);
          if (sign_a != 0 && sign_b != 0 && CompatibleSigns(sign_a, sign_b) && (pix_b - pix_a).norm() <= kMaxChordPx) {
            w = w_end;
            sign_a = sign_b;
            pix_a = pix_b;
            front_a = front_b;
            prev_fine = false;
            continue;
          }
        }
      }
    }
    ws.clear();
    ws.push_back(w);
    for (int k = 0; k < kStretch; ++k) {
      const double w_next = Step(w);
      if (!(w_next <= w_hi)) {
        more = false;
        break;
      }
      w = w_next;
      ws.push_back(w);
    }
    if (ws.size() < 2) break;
    Vec2 pix_b = Vec2::Zero();
    const bool front_b = Pixel(ws.back(), &pix_b);
    const int sign_b = NearSign(front_b, pix_b);
    const bool clear =
        sign_a != 0 && sign_b != 0 && CompatibleSigns(sign_a, sign_b) && (pix_b - pix_a).norm() <= kMaxChordPx;
    if (clear) {
      prev_fine = false;
    } else {
      SampleStretch(ws, pix_a, front_a, pix_b, front_b, &prev_fine, &prev, &w_prev, roots);
    }
    sign_a = sign_b;
    pix_a = pix_b;
    front_a = front_b;
  }
}

}  // namespace
}  // namespace ramtk::vision::detail
