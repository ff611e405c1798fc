// Stereo matching of equal absolute projector coordinate along epipolar curves (stereo_match.h).
#include "ramtk/vision/stereo/stereo_match.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <sstream>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/stereo/detail/back_reach_lanes.h"
#include "ramtk/vision/kernels/fast_round.h"
#include "ramtk/core/error.h"
#include "ramtk/vision/kernels/rank_select.h"
#include "ramtk/vision/stereo/detail/stereo_rectified_grid.h"
#include "ramtk/vision/stereo/detail/stereo_search_list.h"
#include "ramtk/vision/stereo/detail/stereo_walk_lanes.h"
#include "ramtk/vision/stereo/detail/test_hooks.h"
#include "ramtk/vision/stereo/detail/undistort_chains.h"

namespace ramtk::vision {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline double Sq(double x) { return x * x; }
using detail::FloorDiv;
using detail::FloorToInt;

// A CV_32F map's rows as a raw pointer and a row stride in floats: the per-crossing reads use
// it instead of cv::Mat::ptr, whose step lookup costs loads of its own (~3 % of the match's
// instructions).
struct RowView {
  const float* data = nullptr;
  std::size_t stride = 0;
  explicit RowView(const cv::Mat& m = cv::Mat())
      : data(m.empty() ? nullptr : m.ptr<float>()), stride(m.empty() ? 0 : m.step1()) {
    CV_Assert(m.empty() || m.type() == CV_32F);
  }
  const float* Row(int y) const { return data + static_cast<std::size_t>(y) * stride; }
};

// One direction of matching: every valid pixel of camera `src` is searched for in camera `dst`.
struct Pass {
  const CameraIntrinsics* src = nullptr;
  const CameraIntrinsics* dst = nullptr;
  Mat3 R;  // dst_from_src rotation
  Vec3 T;  // dst_from_src translation, mm
  cv::Mat src_coord, src_sigma, src_mask;
  cv::Mat dst_coord, dst_sigma;
  cv::Mat src_modulation, dst_modulation;
  RowView dst_coord_rows, dst_sigma_rows, dst_modulation_rows;  // of the maps above (MatchStereo)
  // Bounding box of the destination image in ideal normalised coordinates (plus a margin).
  double box_x0 = 0, box_x1 = 0, box_y0 = 0, box_y1 = 0;
  // Per destination row: the smallest and largest valid coordinate (a crossing needs c_src in between).
  std::vector<float> row_min, row_max;
  // Per destination cell (index v0 * cols + u0, the cell's top-left pixel): 1 if its four corners
  // are valid and span at most max_span, the cells EvalAt and LineCrossing interpolate.
  std::vector<uchar> cell_ok;
  // Per kTile x kTile tile of destination cells: the smallest and largest valid coordinate of
  // the cells' corners (pixels tile..tile+kTile inclusive); +inf/-inf if none. The full search
  // skips the samples of tiles that cannot hold a crossing (TileSign).
  static constexpr int kTile = 8;
  int tiles_x = 0, tiles_y = 0;
  std::vector<float> tile_min, tile_max;
  // The same bounds over the (2 kDilate + 1)^2 tiles around each tile: they hold every cell
  // within kDilate * kTile pixels of any point of the centre tile. The full search's coarse pass
  // (FullSearch) uses them to prove that a stretch of the curve holds no crossing.
  static constexpr int kDilate = 2;
  std::vector<float> near_min, near_max;
  // The same over the 3 x 3 tiles around each tile (every cell within kTile pixels of any point
  // of the centre tile). A stretch that the dilated bounds cannot prove clear is taken in
  // sub-stretches of `sub_stretch` samples (~8 px), and only those that these bounds cannot prove
  // clear are evaluated (MidSign).
  std::vector<float> mid_min, mid_max;
  int sub_stretch = 1;
  // Per row of tiles, sparse tables of the tile bounds over runs of 2^k tiles (levels x tiles_y x
  // tiles_x): the bounds over any run of tiles in two reads. The full search steps over
  // kFarStretches stretches at once where these bounds over the segment's bounding box prove
  // that it holds no crossing (SegmentClear).
  int levels = 0;
  std::vector<float> run_min, run_max;
  static constexpr int kFarStretches = 4;
  static constexpr double kMaxFarChordPx = 128;  // longer chords are not tried (the bend estimate)
  double period = 1;
  double w_lo = 0, w_hi = 1;  // inverse depth range (1/mm)
  double max_sigma = 0;       // projector px
  double max_span = 0;        // projector px
  double step_px = 0.8;
  // The full search's stretches: `stretch` samples (~24 px), and the end of a stretch in one
  // jump. With u = q_z and x = (step_px / speed_k) T_z u, one step maps x to x + x^2; `stretch`
  // steps map it to x + sum_j c_j x^j, and w moves by (step_px / speed_k) u^2 sum_j c_j x^(j-2)
  // (j = 2..8; truncation below 1e-15 relative for |x| stretch < 0.02). jump[i] = c_(i+2).
  int stretch = 1;
  std::vector<double> jump;
  std::vector<double> jump_far;  // the same for kFarStretches * stretch steps
  // Optional validator: for each dst pixel, its match back in src (the other pass's output).
  cv::Mat back_u, back_v, back_sigma;
  RowView back_u_rows, back_v_rows, back_sigma_rows;  // of the maps above (Consistent reads them)
  // With the check: per source pixel, 1 if some destination cell's back matches can pass Consistent
  // for it (BackReach), else no crossing of it can be accepted and it is not searched.
  cv::Mat reach;
  double lr_tolerance = 0;
  double lr_sigma_factor = 0;
  // Set with the maps above (MatchStereo): whether Consistent checks at all, and whether it widens
  // the tolerance by the back match's sigma (cv::Mat::empty is not inlined).
  bool lr_check = false, lr_sigma = false;
  double max_modulation_ratio = 1e300;  // B_dst / B_src (or its inverse) above this: not the same surface point
  bool points = false;                  // also write each match's depth and point sigma (the left-to-right pass)
  bool pixels = true;                   // write the matched pixels u, v (the back pass must: the check reads them)
  bool sigma_map = true;                // keep the sigma map (the back pass must); false: its values per block only
  bool full_search = false;             // StereoMatchTestHooks::full_search
  bool exhaustive = false;              // StereoMatchTestHooks::exhaustive_search
  // StereoMatchTestHooks::rectified_back_pass: the search runs on the destination coordinate map resampled
  // onto the rectified grid (RectifiedGrid), whose rows are epipolar lines. A point X in the
  // rectified frame of a camera (its rotation, rect_from_src for the source, the camera centre at
  // the origin) lies at rectified pixel f (X_x, X_y) / X_z; the two frames differ by the baseline
  // along x, so a point at inverse depth w on the source ray r = rect_from_src (ideal, 1) lies on
  // the destination's row v = f r_y / r_z at u = f r_x / r_z + rect_sign f B w / r_z.
  bool rect = false;
  Mat3 rect_from_src = Mat3::Identity();
  double rect_f = 1, rect_fb = 0, rect_sign = -1;  // f (px), f times the baseline (px mm), -1 or +1
  detail::RectifiedGrid grid;                      // the destination's coordinate map on the grid
  RowView grid_rows;                               // grid.coord's rows
};

// A sample of the destination coordinate map on the epipolar curve.
struct Sample {
  bool ok = false;
  double f = 0;           // c_dst - c_src, projector px
  double var = 0;         // variance of the interpolated c_dst, projector px^2 (Complete)
  double modulation = 0;  // interpolated destination modulation B, DN (Complete)
  Vec2 pix = Vec2::Zero();
  int u0 = 0, v0 = 0;  // the cell under pix (its top-left pixel) when ok
};

struct Matcher {
  const Pass& p;
  Vec3 a = Vec3::Zero();  // R * ideal ray of the source pixel (z = 1 in the source frame)
  double c_src = 0;
  double w_lo = 0, w_hi = 0;           // the full search's range: the pass's, clipped to the image (SetRange)
  double speed_k = 0, step_per_k = 0;  // Speed(w) = speed_k / q_z(w)^2; step_px / speed_k (SetRange)
  // Pass::rect: the source ray r = rect_from_src (ideal, 1): its rectified pixel f r_x / r_z,
  // f r_y / r_z (the destination row) and r_z (SetRectRay).
  double rs_u = 0, rs_v = 0, rs_z = 1;

  // Narrows [lo, hi] to where g(w) = (ac + tc w) / (az + tz w) lies in [b0, b1]; g is monotonic
  // (a Moebius function) while az + tz w > 0.
  static void Clip(double ac, double tc, double az, double tz, double b0, double b1, double* lo, double* hi) {
    if (*lo > *hi) return;
    auto g = [&](double w) { return (ac + tc * w) / (az + tz * w); };
    const double glo = g(*lo), ghi = g(*hi);
    auto solve = [&](double b) { return (b * az - ac) / (tc - b * tz); };
    if (ghi >= glo) {
      if (glo < b0) *lo = std::max(*lo, solve(b0));
      if (ghi > b1) *hi = std::min(*hi, solve(b1));
    } else {
      if (glo > b1) *lo = std::max(*lo, solve(b1));
      if (ghi < b0) *hi = std::min(*hi, solve(b0));
    }
  }
  // The inverse-depth range whose points project inside the destination image.
  void SetRange() {
    const double sx = p.dst->fx * (p.T.x() * a.z() - a.x() * p.T.z());
    const double sy = p.dst->fy * (p.T.y() * a.z() - a.y() * p.T.z());
    speed_k = std::sqrt(sx * sx + sy * sy);
    step_per_k = speed_k > 0 ? p.step_px / speed_k : 0;
    w_lo = p.w_lo;
    w_hi = p.w_hi;
    // In front of the destination camera: az + tz w > 1e-9.
    if (p.T.z() < 0) w_hi = std::min(w_hi, (a.z() - 1e-9) / -p.T.z());
    if (p.T.z() > 0) w_lo = std::max(w_lo, (1e-9 - a.z()) / p.T.z());
    if (!(a.z() + p.T.z() * w_lo > 0) || !(a.z() + p.T.z() * w_hi > 0)) {
      w_hi = w_lo - 1;
      return;
    }
    Clip(a.x(), p.T.x(), a.z(), p.T.z(), p.box_x0, p.box_x1, &w_lo, &w_hi);
    Clip(a.y(), p.T.y(), a.z(), p.T.z(), p.box_y0, p.box_y1, &w_lo, &w_hi);
  }

  // Whether w lies in the range SetRange gives, tested on w itself: the pass's range, in front of
  // the destination camera, and the ideal point inside the destination image's box. A walked
  // crossing needs only this (SetRange's clipping, two divisions per bound and a square root,
  // is for the full search's stepping).
  bool InRange(double w) const {
    if (!(w >= p.w_lo && w <= p.w_hi)) return false;
    const double qz = a.z() + p.T.z() * w;
    if (!(qz > 1e-9)) return false;
    const double qx = a.x() + p.T.x() * w, qy = a.y() + p.T.y() * w;
    return qx >= p.box_x0 * qz && qx <= p.box_x1 * qz && qy >= p.box_y0 * qz && qy <= p.box_y1 * qz;
  }

  // Destination pixel of the point at inverse depth w on the source ray; false behind the camera.
  bool Pixel(double w, Vec2* pix) const {
    const Vec3 q = a + p.T * w;
    if (q.z() <= 1e-12) return false;
    const Vec2 d = DistortNormalized(p.dst->distortion, Vec2(q.x() / q.z(), q.y() / q.z()));
    *pix = Vec2(p.dst->fx * d.x() + p.dst->cx, p.dst->fy * d.y() + p.dst->cy);
    return true;
  }
  // Speed of the (undistorted) destination image point per unit w, pixels.
  // The undistorted image point x(w) = (a_x + T_x w) / (a_z + T_z w) moves with
  // dx/dw = (T_x a_z - a_x T_z) / q_z^2 (the numerator does not depend on w), so the speed is
  // speed_k / q_z(w)^2 with speed_k fixed per source pixel (SetRange): no division chain or
  // square root in the full search's stepping loop, whose steps depend on each other.
  double Speed(double w) const {
    const double qz = a.z() + p.T.z() * w;
    return speed_k / (qz * qz);
  }
  // w + step_px / Speed(w), without the division.
  double Step(double w) const {
    const double qz = a.z() + p.T.z() * w;
    return w + step_per_k * qz * qz;
  }
  Sample Eval(double w) const {
    Sample s;
    if (!Pixel(w, &s.pix)) return s;
    return EvalAt(s.pix);
  }
  // What a sample at destination pixel `pix` can be, from the tile bounds alone: +1 (if valid,
  // f > 0), -1 (if valid, f < 0), 2 (never valid: outside the image or no valid corner), 0 (unknown).
  int TileSign(bool in_front, const Vec2& pix) const {
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
  int NearSign(bool in_front, const Vec2& pix) const {
    return BoundSign(in_front, pix, Pass::kTile, p.tiles_x, p.tiles_y, Pass::kDilate, p.near_min, p.near_max);
  }
  // The same over the 3 x 3 tile bounds: what every sample within kTile pixels of `pix` can be.
  int MidSign(bool in_front, const Vec2& pix) const {
    return BoundSign(in_front, pix, Pass::kTile, p.tiles_x, p.tiles_y, 1, p.mid_min, p.mid_max);
  }
  // True if no two samples on the curve between pixels pa and pb can have opposite signs: the
  // tile bounds over the chord's bounding box, widened by twice the curve's bend (the distance of
  // its pixel pm between them from the chord) and a pixel, hold c_src outside or no valid cell.
  bool SegmentClear(const Vec2& pa, const Vec2& pb, const Vec2& pm) const {
    const Vec2 d = pb - pa, e = pm - pa;
    const double len = d.norm();
    const double bend = len > 0 ? std::abs(d.x() * e.y() - d.y() * e.x()) / len : e.norm();
    const double margin_px = 2.0 * bend + 1.0;
    const double x0 = std::min({pa.x(), pb.x(), pm.x()}) - margin_px,
                 x1 = std::max({pa.x(), pb.x(), pm.x()}) + margin_px;
    const double y0 = std::min({pa.y(), pb.y(), pm.y()}) - margin_px,
                 y1 = std::max({pa.y(), pb.y(), pm.y()}) + margin_px;
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
  int BoundSign(bool in_front, const Vec2& pix, int cell_px, int nx, int ny, int outside,
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
  // The cell under `pix` (its top-left pixel u0, v0): true if it lies in the image and is one of
  // the cells EvalAt and LineCrossing interpolate (Pass::cell_ok).
  bool ValidCell(const Vec2& pix, int* u0, int* v0) const {
    *u0 = FloorToInt(pix.x());
    *v0 = FloorToInt(pix.y());
    if (*u0 < 0 || *v0 < 0 || *u0 + 1 >= p.dst_coord.cols || *v0 + 1 >= p.dst_coord.rows) return false;
    return p.cell_ok[static_cast<std::size_t>(*v0) * p.dst_coord.cols + *u0] != 0;
  }
  Sample EvalAt(const Vec2& pix) const {
    Sample s;
    s.pix = pix;
    const double u = s.pix.x(), v = s.pix.y();
    int u0, v0;
    if (!ValidCell(pix, &u0, &v0)) return s;
    s.u0 = u0, s.v0 = v0;
    const float* r0 = p.dst_coord_rows.Row(v0);
    const float* r1 = p.dst_coord_rows.Row(v0 + 1);
    const double c00 = r0[u0], c10 = r0[u0 + 1], c01 = r1[u0], c11 = r1[u0 + 1];
    const double fu = u - u0, fv = v - v0;
    const double w00 = (1 - fu) * (1 - fv), w10 = fu * (1 - fv), w01 = (1 - fu) * fv, w11 = fu * fv;
    s.f = w00 * c00 + w10 * c10 + w01 * c01 + w11 * c11 - c_src;
    s.ok = true;
    return s;
  }
  // EvalAt without the interpolated value: whether the cell under `pix` is one EvalAt reads.
  Sample CellAt(const Vec2& pix) const {
    Sample s;
    s.pix = pix;
    s.ok = ValidCell(pix, &s.u0, &s.v0);
    return s;
  }
  // Fills the variance and modulation of a valid sample (EvalAt leaves them out: only the
  // crossing's own sample needs them).
  void Complete(Sample* sample) const {
    Sample& s = *sample;
    if (!s.ok) return;
    const double u = s.pix.x(), v = s.pix.y();
    const int u0 = s.u0, v0 = s.v0;  // the cell EvalAt / CellAt found
    const double fu = u - u0, fv = v - v0;
    const double w00 = (1 - fu) * (1 - fv), w10 = fu * (1 - fv), w01 = (1 - fu) * fv, w11 = fu * fv;
    const float* s0 = p.dst_sigma_rows.Row(v0);
    const float* s1 = p.dst_sigma_rows.Row(v0 + 1);
    const double q00 = s0[u0], q10 = s0[u0 + 1], q01 = s1[u0], q11 = s1[u0 + 1];
    s.var = w00 * w00 * q00 * q00 + w10 * w10 * q10 * q10 + w01 * w01 * q01 * q01 + w11 * w11 * q11 * q11;
    if (!std::isfinite(s.var)) s.var = 0;
    const float* b0 = p.dst_modulation_rows.Row(v0);
    const float* b1 = p.dst_modulation_rows.Row(v0 + 1);
    s.modulation = w00 * b0[u0] + w10 * b0[u0 + 1] + w01 * b1[u0] + w11 * b1[u0 + 1];
  }

  struct Root {
    double w = 0, slope = 0;
    Sample at;
    // Velocity of the destination pixel per unit w near the root (LocalSearch: at its start, a
    // pixel or so away, which changes the speed by < 1e-4 relative); NaN: not known.
    Vec2 vel = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  };
  // Regula falsi (Illinois) on the bilinear surface between two samples of opposite sign. It stops
  // at 1e-6 of a period in coordinate or a 1e-3 px bracket: the match sigma is ~0.05 px, and a
  // tighter stop (1e-9 period / 1e-6 px) moves points by < 0.4 um for 5-7 % more match time
  // (docs/performance.md).
  bool Refine(double wa, Sample sa, double wb, Sample sb, Root* root) const {
    if (std::abs(sb.f - sa.f) > p.max_span) return false;
    const double slope = (sb.f - sa.f) / (wb - wa);
    double fa = sa.f, fb = sb.f;
    int side = 0;
    Sample s = std::abs(fa) < std::abs(fb) ? sa : sb;
    double w = std::abs(fa) < std::abs(fb) ? wa : wb;
    for (int it = 0; it < 40 && fa != 0 && fb != 0; ++it) {
      w = (wa * fb - wb * fa) / (fb - fa);
      s = Eval(w);
      if (!s.ok) return false;
      if (std::abs(s.f) < 1e-6 * p.period || std::abs(wb - wa) * Speed(w) < 1e-3) break;
      if (s.f * fb > 0) {
        wb = w;
        fb = s.f;
        if (side == -1) fa *= 0.5;
        side = -1;
      } else {
        wa = w;
        fa = s.f;
        if (side == +1) fb *= 0.5;
        side = +1;
      }
    }
    root->w = w;
    root->slope = slope;
    root->at = s;
    Complete(&root->at);
    return true;
  }

  // Destination pixel at w (as Pixel) and its velocity per unit w (distorted image), in closed
  // form: the ideal point moves with d x / dw = (T_xy a_z - a_xy T_z) / q_z^2, the lens maps it
  // through its Jacobian. False behind the camera.
  bool PixelAndVelocity(double w, Vec2* pix, Vec2* vel) const {
    const Vec3 q = a + p.T * w;
    if (q.z() <= 1e-12) return false;
    const double iz = 1.0 / q.z();
    const Vec2 ideal(q.x() * iz, q.y() * iz);
    const Vec2 d = DistortNormalized(p.dst->distortion, ideal);
    *pix = Vec2(p.dst->fx * d.x() + p.dst->cx, p.dst->fy * d.y() + p.dst->cy);
    const Vec2 dideal((p.T.x() * a.z() - a.x() * p.T.z()) * iz * iz, (p.T.y() * a.z() - a.y() * p.T.z()) * iz * iz);
    const Vec2 dd = DistortNormalizedJacobian(p.dst->distortion, ideal) * dideal;
    *vel = Vec2(p.dst->fx * dd.x(), p.dst->fy * dd.y());
    return true;
  }

  // The crossing of the bilinear surface along the line pix + vel * s (s in units of w) nearest
  // to s = 0 on the side where |f| falls, at most max_px pixels away. Within one cell the
  // bilinear interpolant is quadratic in s, so each cell's crossing is solved in closed form and
  // the cells are walked in order. False if the line leaves the image, meets a cell with an
  // invalid corner or a wrap (span > max_span), or no crossing lies within reach.
  bool LineCrossing(const Vec2& pix, const Vec2& vel, double max_px, double* s_root, double* dfds) const {
    const int cols = p.dst_coord.cols, rows = p.dst_coord.rows;
    int u0 = FloorToInt(pix.x()), v0 = FloorToInt(pix.y());
    const double speed = vel.norm();
    if (!(speed > 0)) return false;
    const double s_max = max_px / speed;
    double dir = 0;  // +1 or -1: the direction of s in which |f| falls (from the first cell)
    double s_in = 0;
    for (int cells = 0; cells < 64; ++cells) {
      if (u0 < 0 || v0 < 0 || u0 + 1 >= cols || v0 + 1 >= rows) return false;
      if (!p.cell_ok[static_cast<std::size_t>(v0) * cols + u0]) return false;
      const float* r0 = p.dst_coord_rows.Row(v0);
      const float* r1 = p.dst_coord_rows.Row(v0 + 1);
      const double c00 = r0[u0], c10 = r0[u0 + 1], c01 = r1[u0], c11 = r1[u0 + 1];
      // f(s) = A + B s + C s^2 on this cell (fu = au + vel.x s, fv = av + vel.y s).
      const double au = pix.x() - u0, av = pix.y() - v0;
      const double ka = c10 - c00, kb = c01 - c00, kc = c11 - c10 - c01 + c00;
      const double A = c00 - c_src + ka * au + kb * av + kc * au * av;
      const double B = ka * vel.x() + kb * vel.y() + kc * (au * vel.y() + av * vel.x());
      const double C = kc * vel.x() * vel.y();
      if (dir == 0) {
        const double f0 = A + B * s_in + C * s_in * s_in, g0 = B + 2 * C * s_in;
        if (f0 == 0) {
          *s_root = s_in;
          *dfds = g0;
          return g0 != 0;
        }
        if (g0 == 0 || !std::isfinite(g0)) return false;
        dir = (f0 * g0 > 0) ? -1.0 : 1.0;
      }
      // Where the line leaves the cell, going in direction dir.
      const double dx = dir * vel.x(), dy = dir * vel.y();
      const double tx = dx > 0 ? (u0 + 1 - pix.x()) / dx : dx < 0 ? (u0 - pix.x()) / dx : 1e300;
      const double ty = dy > 0 ? (v0 + 1 - pix.y()) / dy : dy < 0 ? (v0 - pix.y()) / dy : 1e300;
      const double t_out = std::min({tx, ty, s_max});  // |s| at the exit
      const double lo = std::min(dir * s_in, dir * t_out), hi = std::max(dir * s_in, dir * t_out);
      // Roots of A + B s + C s^2 (stable form), the first one met going in direction dir.
      double best = std::numeric_limits<double>::quiet_NaN();
      const double disc = B * B - 4 * A * C;
      if (disc >= 0) {
        const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
        for (const double r : {q != 0 ? A / q : std::numeric_limits<double>::quiet_NaN(),
                               C != 0 ? q / C : std::numeric_limits<double>::quiet_NaN()}) {
          if (r >= lo - 1e-12 * (std::abs(lo) + 1e-300) && r <= hi + 1e-12 * (std::abs(hi) + 1e-300) &&
              (std::isnan(best) || dir * r < dir * best))
            best = r;
        }
      }
      if (!std::isnan(best)) {
        *s_root = best;
        *dfds = B + 2 * C * best;
        return *dfds != 0;
      }
      if (t_out >= s_max) return false;
      s_in = dir * t_out;
      if (tx <= ty) u0 += dx > 0 ? 1 : -1;
      if (ty <= tx) v0 += dy > 0 ? 1 : -1;
    }
    return false;
  }

  // The crossing near a neighbour's inverse depth w0: the curve is replaced by its tangent line
  // at w0 in the destination image and the crossing on the line is solved (LineCrossing). The
  // curve's own pixel there is then computed; if it is within 1e-4 px of the line's point (as a
  // rule: the curve bends by far less over the few pixels between neighbours) that is the
  // crossing, otherwise the line through the curve's pixel is solved again. The slope for the
  // match sigma is the secant of the surface over step_px / 4 on each side of the crossing along
  // the tangent (the bracket of a walk with step step_px / 2 spans as much), or the derivative
  // where those samples are not valid or the secant is flat or reversed (noise).
  bool LocalSearch(double w0, Root* root) const {
    Vec2 pix, vel;
    if (!PixelAndVelocity(w0, &pix, &vel)) return false;
    double w = w0, s = 0, dfds = 0;
    if (!LineCrossing(pix, vel, 16.0 * p.step_px, &s, &dfds)) return false;
    const double speed = vel.norm();
    bool done = false;
    for (int round = 0; round < 4 && !done; ++round) {
      w += s;
      Vec2 on_curve;
      if (!Pixel(w, &on_curve)) return false;
      const Vec2 on_line = pix + vel * s;
      pix = on_curve;
      s = 0;
      if ((on_curve - on_line).squaredNorm() < 1e-8) {
        done = true;
        break;
      }
      if (!LineCrossing(pix, vel, 4.0, &s, &dfds)) return false;
      done = std::abs(s) * speed < 1e-4;
      if (done) w += s;
    }
    if (!done || !InRange(w)) return false;
    const Vec2 at = pix + vel * s;
    root->w = w;
    root->at = CellAt(at);  // no one reads a crossing's f (it is ~0): only its cell's validity
    if (!root->at.ok) return false;
    const double hs = 0.25 * p.step_px / speed;
    const Sample sa = EvalAt(at - vel * hs), sb = EvalAt(at + vel * hs);
    const double secant = (sa.ok && sb.ok && std::abs(sb.f - sa.f) <= p.max_span) ? (sb.f - sa.f) / (2 * hs) : 0.0;
    root->slope = secant * dfds > 0 ? secant : dfds;  // a flat or reversed secant (noise): the derivative
    root->vel = vel;
    Complete(&root->at);
    return true;
  }

  // ---- The rectified search (Pass::rect) ----

  // The source ray r = rect_from_src (ideal, 1) in the rectified frame, given as f r_x / r_z,
  // f r_y / r_z and r_z (UndistortChains); false if it points behind the rectified cameras.
  bool SetRectRay(double u, double v, double z) {
    if (!(z > 1e-9)) return false;
    rs_z = z;
    rs_u = u;
    rs_v = v;
    return true;
  }
  // Grid column of the destination point at inverse depth w, and back.
  double RectColumn(double w) const { return rs_u + p.rect_sign * p.rect_fb * w / rs_z - p.grid.u0; }
  double RectW(double column) const { return (column + p.grid.u0 - rs_u) * p.rect_sign * rs_z / p.rect_fb; }
  // The grid row pair (j, j + 1) around the source's rectified v, and v's fraction between them.
  bool RectRows(int* j, double* fv) const {
    const double v = rs_v - p.grid.v0;
    if (!(v >= 0 && v < p.grid.coord.rows - 1)) return false;
    *j = FloorToInt(v);
    *fv = v - *j;
    return true;
  }
  // Cell i of the row pair (r0, r1) read at the source's v: the coordinate minus c_src at its two
  // columns (linear between them along the row); false if a corner is invalid or the cell holds
  // a jump (its four corners span more than max_span, as Pass::cell_ok).
  bool RectCell(const float* r0, const float* r1, int i, double fv, double* g0, double* g1) const {
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
  bool RectRoot(double column, double dg_du, Root* root) const {
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
  bool RectLocalSearch(double w0, Root* root) const {
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
  void RectFullSearch(std::vector<Root>* roots) const {
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

  // The search's rule between consecutive samples: a crossing lies between two valid samples of
  // opposite sign (or at a zero); it is refined and kept. Then `sk` at w becomes the previous.
  void NextSample(double w, const Sample& sk, Sample* prev, double* w_prev, std::vector<Root>* roots) const {
    if (sk.ok && prev->ok && ((sk.f > 0) != (prev->f > 0) || sk.f == 0)) {
      Root r;
      if (Refine(*w_prev, *prev, w, sk, &r)) roots->push_back(r);
    }
    *prev = sk;
    *w_prev = w;
  }

  // FullSearch without any pruning: every sample from w_lo on, one step at a time.
  void ExhaustiveSearch(std::vector<Root>* roots) const {
    if (!(std::min(Speed(w_lo), Speed(w_hi)) > 1e-9)) return;
    Sample prev;
    double w_prev = w_lo;
    for (double w = w_lo; w <= w_hi; w = Step(w)) NextSample(w, Eval(w), &prev, &w_prev, roots);
  }

  // Every crossing over the whole inverse-depth range, in order of w.
  void FullSearch(std::vector<Root>* roots) const {
    roots->clear();
    if (!(w_lo < w_hi)) return;
    if (p.exhaustive) {
      ExhaustiveSearch(roots);
      return;
    }
    // Quick rejection: c_src outside every coordinate on the rows the curve crosses.
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
      if (!(c_src >= lo && c_src <= hi)) return;
    }
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
    constexpr double kMaxSubChordPx = 2.0 * Pass::kTile - 4.0;               // the same for MidSign
    auto compatible = [](int s1, int s2) { return s1 == s2 || s1 == 2 || s2 == 2; };
    thread_local std::vector<double> ws;  // one stretch of sample positions
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
            if (sign_a != 0 && sign_b != 0 && compatible(sign_a, sign_b) && (pix_b - pix_a).norm() <= kMaxChordPx) {
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
          sign_a != 0 && sign_b != 0 && compatible(sign_a, sign_b) && (pix_b - pix_a).norm() <= kMaxChordPx;
      if (clear) {
        prev_fine = false;
      } else {
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
              mid_j != 0 && mid_e != 0 && compatible(mid_j, mid_e) && (pix_e - pix_j).norm() <= kMaxSubChordPx;
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
      sign_a = sign_b;
      pix_a = pix_b;
      front_a = front_b;
    }
  }

  // Same surface point: the modulations agree (a matte surface sends the same radiance to both
  // cameras), and the destination position's own match back in the source image lands on the
  // source pixel (left-right consistency).
  bool Accept(const Root& r, double b_src, double su, double sv) const {
    const double ratio = std::max(1e-6, r.at.modulation) / std::max(1e-6, b_src);
    if (ratio > p.max_modulation_ratio || ratio * p.max_modulation_ratio < 1.0) return false;
    return Consistent(r.at.pix, su, sv);
  }
  bool Consistent(const Vec2& dst_pix, double su, double sv) const {
    if (!p.lr_check) return true;
    const double u = dst_pix.x(), v = dst_pix.y();
    const int u0 = FloorToInt(u), v0 = FloorToInt(v);
    if (u0 < 0 || v0 < 0 || u0 + 1 >= p.back_u.cols || v0 + 1 >= p.back_u.rows) return false;
    // The four corners' back matches and sigmas (Pass::back_u_rows ...).
    // The three maps share one layout (the back pass's outputs; MatchStereo checks): one offset.
    const std::size_t at0 = static_cast<std::size_t>(v0) * p.back_u_rows.stride + static_cast<std::size_t>(u0);
    const std::size_t at1 = at0 + p.back_u_rows.stride;
    const float *bu_f = p.back_u_rows.data, *bv_f = p.back_v_rows.data;
    const float fu4[4] = {bu_f[at0], bu_f[at0 + 1], bu_f[at1], bu_f[at1 + 1]};
    const float fv4[4] = {bv_f[at0], bv_f[at0 + 1], bv_f[at1], bv_f[at1 + 1]};
    // All eight finite: x - x is 0 for a finite x and NaN otherwise, and so is the sum.
    const bool all = ((fu4[0] - fu4[0]) + (fu4[1] - fu4[1]) + (fu4[2] - fu4[2]) + (fu4[3] - fu4[3]) +
                      (fv4[0] - fv4[0]) + (fv4[1] - fv4[1]) + (fv4[2] - fv4[2]) + (fv4[3] - fv4[3])) == 0.0f;
    const double bu[4] = {fu4[0], fu4[1], fu4[2], fu4[3]}, bv[4] = {fv4[0], fv4[1], fv4[2], fv4[3]};
    double tolerance = p.lr_tolerance;
    if (p.lr_sigma) {
      const float* bs_f = p.back_sigma_rows.data;
      const float s4[4] = {bs_f[at0], bs_f[at0 + 1], bs_f[at1], bs_f[at1 + 1]};
      for (const float sk : s4)
        if (sk - sk == 0.0f) tolerance = std::max(tolerance, p.lr_sigma_factor * static_cast<double>(sk));  // finite
    }
    const double fu = u - u0, fv = v - v0;
    if (all) {
      const double wts[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
      double mu = 0, mv = 0, spread = 0;
      for (int k = 0; k < 4; ++k) {
        mu += wts[k] * bu[k];
        mv += wts[k] * bv[k];
        spread = std::max(spread, Sq(bu[k] - bu[0]) + Sq(bv[k] - bv[0]));  // squared
      }
      if (spread < 16.0) return Sq(mu - su) + Sq(mv - sv) <= tolerance * tolerance;
    }
    const int k = (fu < 0.5 ? 0 : 1) + (fv < 0.5 ? 0 : 2);
    if (!std::isfinite(bu[k])) return false;
    return Sq(bu[k] - su) + Sq(bv[k] - sv) <= Sq(tolerance + 1.0);
  }
};

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

struct PassResult {
  cv::Mat u, v, sigma;               // sigma: Pass::sigma_map only
  cv::Mat depth, point_sigma, x, y;  // Pass::points only
  std::atomic<long> noisy{0}, no_match{0}, lr{0}, unreachable{0}, full{0}, matched{0}, valid{0};
  // Without Pass::sigma_map: the matched pixels' sigmas, one part per block (for their median).
  std::mutex sigma_mutex;
  std::vector<std::vector<float>> sigma_parts;
};

// One source row's walk in RunPass: its cursor, seeds, counts and output rows.
struct RowWalk {
  int y = 0;
  int x = 0;         // the cursor: every pixel left of it is done
  int next_ray = 0;  // the chain's entry of the next pixel searched
  int last_x = -2;   // the column of the last pixel searched
  double w_prev = std::numeric_limits<double>::quiet_NaN();
  double w_last = std::numeric_limits<double>::quiet_NaN();  // the row's last match, past gaps
  bool lane_tried = false;  // the lanes walked the pixel at the cursor and did not settle it
  const detail::UndistortChain* chain = nullptr;
  const float *crow = nullptr, *srow = nullptr, *mod_row = nullptr;
  // The output rows (the pass writes u, v only with `pixels`, depth to point_sigma only with `points`).
  float *u_row = nullptr, *v_row = nullptr, *sigma_row = nullptr, *depth_row = nullptr, *x_row = nullptr,
        *y_row = nullptr, *point_sigma_row = nullptr;
  const double* w_up = nullptr;  // the row above's inverse depths (NaN: not matched)
  double* w_row = nullptr;       // this row's
  long noisy = 0, no_match = 0, lr = 0, unreachable = 0, full = 0, matched = 0, valid = 0;

  void Start(const Pass& p, PassResult* out, int row, const detail::UndistortChain* c,
             const detail::SearchCounts& counts, const double* up, double* own, float* sigma_scratch) {
    const int W = p.src_coord.cols;
    y = row;
    chain = c;
    valid = counts.valid;
    noisy = counts.noisy;
    unreachable = counts.unreachable;
    w_up = up;
    w_row = own;
    detail::FillNaN(w_row, W);
    crow = p.src_coord.ptr<float>(y);
    srow = p.src_sigma.ptr<float>(y);
    mod_row = p.src_modulation.ptr<float>(y);
    u_row = p.pixels ? out->u.ptr<float>(y) : nullptr;
    v_row = p.pixels ? out->v.ptr<float>(y) : nullptr;
    sigma_row = p.sigma_map ? out->sigma.ptr<float>(y) : sigma_scratch;
    depth_row = p.points ? out->depth.ptr<float>(y) : nullptr;
    x_row = p.points ? out->x.ptr<float>(y) : nullptr;
    y_row = p.points ? out->y.ptr<float>(y) : nullptr;
    point_sigma_row = p.points ? out->point_sigma.ptr<float>(y) : nullptr;
    for (float* r : {u_row, v_row, sigma_row, depth_row, x_row, y_row, point_sigma_row})
      if (r) detail::FillNaN(r, W);
  }
  void Flush(PassResult* out) const {
    out->noisy += noisy;
    out->no_match += no_match;
    out->lr += lr;
    out->unreachable += unreachable;
    out->full += full;
    out->matched += matched;
    out->valid += valid;
  }
};

// Whether two roots are the same to the bit (the lanes' check, detail::SetWalkLaneCheck).
bool SameBits(const Matcher::Root& a, const Matcher::Root& b) {
  const double va[] = {a.w, a.slope, a.at.pix.x(), a.at.pix.y(), a.at.var, a.at.modulation, a.vel.x(), a.vel.y()};
  const double vb[] = {b.w, b.slope, b.at.pix.x(), b.at.pix.y(), b.at.var, b.at.modulation, b.vel.x(), b.vel.y()};
  return std::memcmp(va, vb, sizeof va) == 0 && a.at.ok == b.at.ok && a.at.u0 == b.at.u0 && a.at.v0 == b.at.v0;
}

// Moves the row's cursor to its next pixel to search (true) or to the row's end (false). The
// left neighbour's match seeds the walk only if the neighbour was searched (and matched).
bool NextSearched(const Pass& p, RowWalk* r) {
  if (r->next_ray >= r->chain->count) {
    r->x = p.src_coord.cols;
    return false;
  }
  r->x = r->chain->xs[r->next_ray];
  if (r->x != r->last_x + 1) r->w_prev = std::numeric_limits<double>::quiet_NaN();
  return true;
}

// A matched pixel's outputs before they are stored as float: the match sigma along the curve
// (px), the depth as stored, the point's x and y from it, and the point's sigma along its ray (mm).
struct PixelOutputs {
  double sigma_px = 0;
  float depth = 0;
  double x = 0, y = 0, point_sigma = 0;
};
// Match sigma: c_dst(w) = c_src; var(w) = (sigma_src^2 + var(c_dst)) / slope^2, times the
// pixel's speed. X(w) = (ideal, 1) / w on the source ray: z = 1 / w, |dX/dw| = |(ideal, 1)| / w^2;
// x and y from the depth as stored (StereoMatch::x_mm), the point TriangulateMatches formed from
// the depth map when it undistorted the pixel again. (WalkFourLanes computes the same.)
PixelOutputs Outputs(float sigma_src, double var, double slope, const Vec2& vel, double w, const Vec2& ideal) {
  PixelOutputs o;
  const double sigma_w = std::sqrt(static_cast<double>(sigma_src) * sigma_src + var) / std::abs(slope);
  o.sigma_px = vel.norm() * sigma_w;
  const double z = 1.0 / w;
  o.depth = static_cast<float>(z);
  o.x = ideal.x() * static_cast<double>(o.depth);
  o.y = ideal.y() * static_cast<double>(o.depth);
  const double ray = std::sqrt(ideal.x() * ideal.x() + ideal.y() * ideal.y() + 1.0);
  o.point_sigma = ray * z * z * sigma_w;
  return o;
}

// Searches the pixel at the row's cursor and writes its outputs (NextSearched then moves the
// cursor on).
// `settled` (CheckSettled only, in tests): the root the lanes settled from the left neighbour's
// seed, taken as found and compared with the scalar walk's first try from that seed.
void SearchPixel(const Pass& p, Matcher& m, std::vector<Matcher::Root>& roots, RowWalk* r,
                 const Matcher::Root* settled) {
  const int x = r->x, y = r->y;
  r->last_x = x;
  // The source ray (undistorted before the row's walk, in the order of the row).
  const detail::UndistortChain& chain = *r->chain;
  assert(r->next_ray < chain.count && chain.xs[r->next_ray] == x);
  const int entry = r->next_ray++;
  const Vec2 ideal(chain.ideal_x[entry], chain.ideal_y[entry]);
  m.a = Vec3(chain.a_x[entry], chain.a_y[entry], chain.a_z[entry]);
  m.c_src = r->crow[x];
  if (p.rect && !m.SetRectRay(chain.rs_u[entry], chain.rs_v[entry], chain.rs_z[entry])) {
    ++r->no_match;
    r->w_prev = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  Matcher::Root root;
  bool found = false, any = false;
  if (settled) {
    root = *settled;
    found = any = true;
    Matcher::Root scalar;  // the scalar walk's first try, from the same seed
    const bool same = (p.rect ? m.RectLocalSearch(r->w_prev, &scalar) : m.LocalSearch(r->w_prev, &scalar)) &&
                      m.Accept(scalar, r->mod_row[x], x, y) && SameBits(scalar, root);
    detail::CountWalkLaneCheck(same);
  } else if (!p.full_search) {
    // Start from the left neighbour's match; then (a run start, or no acceptable crossing
    // near it: the neighbour may lie on another surface) from the pixel above's, then
    // from the row's last match before a gap. A walk costs ~0.1 us, a full search ~3 us.
    const double seeds[3] = {r->w_prev, r->w_up[x], r->w_last};
    for (int k = 0; k < 3 && !found; ++k) {
      const double w_seed = seeds[k];
      if (!std::isfinite(w_seed) || (k >= 1 && w_seed == seeds[0]) || (k == 2 && w_seed == seeds[1])) continue;
      if (p.rect ? m.RectLocalSearch(w_seed, &root) : m.LocalSearch(w_seed, &root)) {
        any = true;
        found = m.Accept(root, r->mod_row[x], x, y);
      }
    }
  }
  if (!found) {
    ++r->full;
    if (p.rect) {
      m.RectFullSearch(&roots);
    } else {
      m.SetRange();
      m.FullSearch(&roots);
    }
    any = any || !roots.empty();
    // Several crossings (another surface lit by the same projector column on the same
    // epipolar curve): try first the one whose modulation agrees best with the source's.
    const double b_src = std::max(1e-6, static_cast<double>(r->mod_row[x]));
    std::stable_sort(roots.begin(), roots.end(), [&](const Matcher::Root& ra, const Matcher::Root& rb) {
      return std::abs(std::log(std::max(1e-6, ra.at.modulation) / b_src)) <
             std::abs(std::log(std::max(1e-6, rb.at.modulation) / b_src));
    });
    for (const auto& cand : roots) {
      if (m.Accept(cand, b_src, x, y)) {
        root = cand;
        found = true;
        break;
      }
    }
  }
  if (!found) {
    (any ? r->lr : r->no_match) += 1;
    r->w_prev = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  ++r->matched;
  r->w_prev = root.w;
  r->w_last = root.w;
  r->w_row[x] = root.w;
  Vec2 d = root.vel, unused;
  if (!std::isfinite(d.x())) m.PixelAndVelocity(root.w, &unused, &d);
  const PixelOutputs o = Outputs(r->srow[x], root.at.var, root.slope, d, root.w, ideal);
  if (p.pixels) {
    r->u_row[x] = static_cast<float>(root.at.pix.x());
    r->v_row[x] = static_cast<float>(root.at.pix.y());
  }
  r->sigma_row[x] = static_cast<float>(o.sigma_px);
  if (p.points) {
    r->depth_row[x] = o.depth;
    r->x_row[x] = static_cast<float>(o.x);
    r->y_row[x] = static_cast<float>(o.y);
    r->point_sigma_row[x] = static_cast<float>(o.point_sigma);
  }
}

// What the lanes read of a pass (detail::WalkMaps).
detail::WalkMaps LaneMaps(const Pass& p) {
  detail::WalkMaps w;
  for (int i = 0; i < 3; ++i) w.t[i] = p.T(i);
  w.fx = p.dst->fx, w.fy = p.dst->fy, w.cx = p.dst->cx, w.cy = p.dst->cy;
  w.distortion = p.dst->distortion;
  w.cols = p.dst_coord.cols, w.rows = p.dst_coord.rows;
  w.coord = p.dst_coord_rows.data;
  w.sigma = p.dst_sigma_rows.data;
  w.modulation = p.dst_modulation_rows.data;
  w.stride = static_cast<int>(p.dst_coord_rows.stride);
  w.cell_ok = p.cell_ok.data();
  w.step_px = p.step_px, w.max_span = p.max_span;
  w.w_lo = p.w_lo, w.w_hi = p.w_hi;
  w.box_x0 = p.box_x0, w.box_x1 = p.box_x1, w.box_y0 = p.box_y0, w.box_y1 = p.box_y1;
  w.max_modulation_ratio = p.max_modulation_ratio;
  w.lr_check = p.lr_check, w.lr_sigma = p.lr_sigma;
  w.lr_tolerance = p.lr_tolerance, w.lr_sigma_factor = p.lr_sigma_factor;
  w.points = p.points;
  if (p.lr_check) {
    w.back_u = p.back_u_rows.data, w.back_v = p.back_v_rows.data, w.back_sigma = p.back_sigma_rows.data;
    w.back_stride = static_cast<int>(p.back_u_rows.stride);
    w.back_cols = p.back_u.cols, w.back_rows = p.back_u.rows;
  }
  if (p.rect) {
    w.rect = true;
    w.grid = p.grid_rows.data;
    w.grid_stride = static_cast<int>(p.grid_rows.stride);
    w.grid_cols = p.grid.coord.cols, w.grid_rows = p.grid.coord.rows;
    w.grid_u0 = p.grid.u0, w.grid_v0 = p.grid.v0;
    w.rect_sign = p.rect_sign, w.rect_fb = p.rect_fb;
  }
  return w;
}

// Whether the lanes can walk the pass: with the walk (not StereoMatchTestHooks::full_search), on a
// CPU with AVX2, into a camera of the 5-coefficient lens model (the lanes' model), with the three
// destination maps in one layout (MatchStereo makes them so) and every offset in an int.
bool LanesWalk(const Pass& p) {
  const double limit = 2e9;
  return !p.full_search && detail::Avx2Kernels() && p.dst->distortion.model == camera::LensModel::kPinhole5 &&
         p.dst_sigma_rows.stride == p.dst_coord_rows.stride &&
         p.dst_modulation_rows.stride == p.dst_coord_rows.stride &&
         static_cast<double>(p.dst_coord_rows.stride) * (p.dst_coord.rows + 1) < limit &&
         static_cast<double>(p.dst_coord.cols) * (p.dst_coord.rows + 1) < limit &&
         (!p.lr_check || static_cast<double>(p.back_u_rows.stride) * (p.back_u.rows + 1) < limit) &&
         (!p.rect || static_cast<double>(p.grid_rows.stride) * (p.grid.coord.rows + 1) < limit);
}

// A pixel the lanes settled (lane k of `in`, the pixel at the row's cursor): its outputs as
// SearchPixel writes them for that root (the lanes computed them), and the row's seeds.
void EmitSettled(const Pass& p, RowWalk* r, const detail::WalkLanes& in, int k) {
  const int x = r->x;
  r->last_x = x;
  ++r->next_ray;
  ++r->matched;
  r->w_prev = in.w[k];
  r->w_last = in.w[k];
  r->w_row[x] = in.w[k];
  if (p.pixels) {
    r->u_row[x] = in.out_u[k];
    r->v_row[x] = in.out_v[k];
  }
  r->sigma_row[x] = in.out_sigma[k];
  if (p.points) {
    r->depth_row[x] = in.out_depth[k];
    r->x_row[x] = in.out_x[k];
    r->y_row[x] = in.out_y[k];
    r->point_sigma_row[x] = in.out_point_sigma[k];
  }
}

// Tests (detail::SetWalkLaneCheck): the settled root against the scalar walk from the same seed,
// bit for bit, and the lanes' outputs against SearchPixel's for that root.
void CheckSettled(const Pass& p, Matcher& m, const RowWalk& r, const detail::WalkLanes& in, int k) {
  Matcher::Root root;
  root.w = in.w[k];
  root.slope = in.slope[k];
  root.at.ok = true;
  root.at.pix = Vec2(in.pix_x[k], in.pix_y[k]);
  root.at.u0 = in.u0[k], root.at.v0 = in.v0[k];
  root.at.var = in.var[k];
  root.at.modulation = in.modulation[k];
  root.vel = Vec2(in.vel_x[k], in.vel_y[k]);
  // SearchPixel on a copy of the row (outputs into scratch rows) counts the root's comparison
  // with the scalar walk's; the outputs, before they become floats, are compared here.
  RowWalk copy = r;
  const std::size_t len = static_cast<std::size_t>(r.x) + 1;
  std::vector<float> scratch(7 * len, 0.0f);
  float** fields[7] = {&copy.u_row, &copy.v_row, &copy.sigma_row,      &copy.depth_row,
                       &copy.x_row, &copy.y_row, &copy.point_sigma_row};
  for (int i = 0; i < 7; ++i)
    if (*fields[i]) *fields[i] = scratch.data() + i * len;
  std::vector<double> w_row(len);
  copy.w_row = w_row.data();
  std::vector<Matcher::Root> roots;
  SearchPixel(p, m, roots, &copy, &root);
  const int e = r.next_ray;
  const PixelOutputs o =
      Outputs(r.srow[r.x], root.at.var, root.slope, root.vel, root.w, Vec2(r.chain->ideal_x[e], r.chain->ideal_y[e]));
  const double want[4] = {o.sigma_px, o.x, o.y, o.point_sigma};
  const double got[4] = {in.out_sigma_d[k], in.out_x_d[k], in.out_y_d[k], in.out_point_sigma_d[k]};
  bool same = std::memcmp(want, got, p.points ? sizeof want : sizeof(double)) == 0;
  const float lanes[7] = {in.out_u[k], in.out_v[k], in.out_sigma[k],      in.out_depth[k],
                          in.out_x[k], in.out_y[k], in.out_point_sigma[k]};
  for (int i = 0; i < 7; ++i)
    if (*fields[i]) same = same && std::memcmp(&scratch[i * len + r.x], &lanes[i], sizeof(float)) == 0;
  if (!same) detail::CountWalkLaneMismatch();
}

// Walks rows [yb, ye) of a block, `lanes` rows side by side (1: one after the other). A row's
// pixel is settled by the lanes when they can (the left neighbour's seed, the common case);
// otherwise the scalar search takes it, once the row above has passed it (it may seed from the
// row above's match). The results do not depend on `lanes`.
void WalkRows(const Pass& p, PassResult* out, int yb, int ye, int lanes, const detail::WalkMaps& maps,
              const detail::UndistortChain* chains, const detail::SearchCounts* counts, std::vector<double>* w_buf,
              std::vector<float>* sigma_buf) {
  Matcher m{p};
  std::vector<Matcher::Root> roots;
  const bool check = lanes > 1 && detail::WalkLaneCheck();  // tests: each settled pixel again
  const int W = p.src_coord.cols;
  std::vector<float> sigmas;  // without Pass::sigma_map: this block's matched sigmas
  for (int g = yb; g < ye; g += lanes) {
    const int n = std::min(lanes, ye - g);
    RowWalk rw[4];
    bool pending[4] = {false, false, false, false};
    for (int k = 0; k < n; ++k) {
      rw[k].Start(p, out, g + k, &chains[g + k - yb], counts[g + k - yb], w_buf[k].data(), w_buf[k + 1].data(),
                  p.sigma_map ? nullptr : sigma_buf[k].data());
      pending[k] = NextSearched(p, &rw[k]);
    }
    for (bool more = n > 0; more;) {
      int settled = 0;
      detail::WalkLanes in;
      if (lanes > 1) {
        in.active = 0;
        for (int k = 0; k < n; ++k) {
          RowWalk& r = rw[k];
          if (!pending[k] || r.lane_tried || !std::isfinite(r.w_prev)) continue;
          const int e = r.next_ray;
          in.a_x[k] = r.chain->a_x[e], in.a_y[k] = r.chain->a_y[e], in.a_z[k] = r.chain->a_z[e];
          if (p.rect) in.rs_u[k] = r.chain->rs_u[e], in.rs_v[k] = r.chain->rs_v[e], in.rs_z[k] = r.chain->rs_z[e];
          in.c_src[k] = r.crow[r.x];
          in.w0[k] = r.w_prev;
          in.b_src[k] = r.mod_row[r.x];
          in.su[k] = r.x, in.sv[k] = r.y;
          in.sigma_src[k] = r.srow[r.x];
          in.ideal_x[k] = r.chain->ideal_x[e], in.ideal_y[k] = r.chain->ideal_y[e];
          in.active |= 1 << k;
          r.lane_tried = true;
        }
        for (int k = 0; k < 4; ++k)
          if (!(in.active >> k & 1)) {  // an idle lane: finite values
            in.a_x[k] = in.a_y[k] = in.c_src[k] = in.w0[k] = in.b_src[k] = in.su[k] = in.sv[k] = 0.0;
            in.sigma_src[k] = in.ideal_x[k] = in.ideal_y[k] = 0.0;
            in.rs_u[k] = in.rs_v[k] = 0.0;
            in.a_z[k] = in.rs_z[k] = 1.0;
          }
        if (in.active) {
          detail::WalkFourLanes(maps, &in);
          settled = in.found;
        }
      }
      more = false;
      for (int k = 0; k < n; ++k) {
        RowWalk& r = rw[k];
        if (!pending[k]) continue;
        if (settled >> k & 1) {
          if (check) CheckSettled(p, m, r, in, k);
          EmitSettled(p, &r, in, k);
        } else if (k == 0 || !pending[k - 1] || rw[k - 1].x > r.x) {
          SearchPixel(p, m, roots, &r, nullptr);
        } else {
          more = true;  // waits for the row above
          continue;
        }
        r.lane_tried = false;
        pending[k] = NextSearched(p, &r);
        more = more || pending[k];
      }
    }
    for (int k = 0; k < n; ++k) rw[k].Flush(out);
    if (!p.sigma_map)  // the rows' sigmas before their scratch rows are reused
      for (int k = 0; k < n; ++k)
        for (int x = 0; x < W; ++x)
          if (rw[k].sigma_row[x] == rw[k].sigma_row[x]) sigmas.push_back(rw[k].sigma_row[x]);
    std::swap(w_buf[0], w_buf[n]);
  }
  if (!p.sigma_map && !sigmas.empty()) {
    std::lock_guard<std::mutex> lock(out->sigma_mutex);
    out->sigma_parts.push_back(std::move(sigmas));
  }
}

// Runs one pass over `rows`; returns false if cancelled.
bool RunPass(const Pass& p, PassResult* out, const StereoMatchOptions& options, const std::string& stage) {
  const int W = p.src_coord.cols, H = p.src_coord.rows;
  // The output maps (NaN where nothing matched: each row is filled as the pass reaches it, while
  // it stays in cache, not in a pass of its own).
  if (p.pixels) {
    out->u.create(H, W, CV_32F);
    out->v.create(H, W, CV_32F);
  }
  if (p.sigma_map) out->sigma.create(H, W, CV_32F);
  if (p.points) {
    out->depth.create(H, W, CV_32F);
    out->point_sigma.create(H, W, CV_32F);
    out->x.create(H, W, CV_32F);
    out->y.create(H, W, CV_32F);
  }
  // Rows run in fixed blocks of kBlock consecutive rows, one task per block, so a row can seed
  // its run starts from the row above (monotone phase: the pixel above's inverse depth is a
  // start as good as the left neighbour's). The blocks do not depend on the thread count, so
  // the result is deterministic. With a progress callback, progress is reported (and
  // cancellation checked) per chunk of 16 blocks: enough tasks per chunk that the threads finish
  // it together (with 4 blocks per chunk, 2 threads waited for the slowest block at every chunk:
  // 1.55x from 2 cores). Without one (the scan) the pass is one chunk and no thread waits at a
  // chunk's end; the gain was within noise, 2 threads already reaching 1.9x one thread.
  const int kBlock = 16, chunk = options.progress ? 16 * kBlock : std::max(H, 1);
  // The rotations the source rays are turned by (UndistortChains).
  detail::ChainRays turn;
  turn.rotation = p.R;
  turn.rectified = p.rect;
  turn.rect_from_camera = p.rect_from_src;
  turn.rect_f = p.rect_f;
  const int lanes = LanesWalk(p) ? 4 : 1;
  const detail::WalkMaps maps = lanes > 1 ? LaneMaps(p) : detail::WalkMaps{};
  for (int r0 = 0; r0 < H; r0 += chunk) {
    const int r1 = std::min(H, r0 + chunk);
    const int blocks = (r1 - r0 + kBlock - 1) / kBlock;
    tbb::parallel_for(0, blocks, [&](int b) {
      // The row above the rows walked (NaN above a block's first row), then one per lane.
      std::vector<double> w_buf[5];
      for (std::vector<double>& w : w_buf) w.resize(W);
      std::vector<float> sigma_buf[4];  // the rows' sigmas without a map (Pass::sigma_map)
      if (!p.sigma_map)
        for (std::vector<float>& b : sigma_buf) b.resize(W);
      detail::FillNaN(w_buf[0].data(), W);  // the row above the block's first (the others: RowWalk::Start)
      const int yb = r0 + b * kBlock, ye = std::min(r1, yb + kBlock);
      // The block's source rays first: the pixels each row will search (valid, not noisy,
      // reachable), undistorted row by row in order (UndistortChains, several rows side by side).
      thread_local std::vector<int> xs;
      // Per pixel of the block's chains: the ideal point, a = R (ideal, 1) and the rectified ray.
      thread_local std::vector<double> rays[8];
      const std::size_t row_stride = static_cast<std::size_t>(W) + 8;  // ListSearchedPixels' scratch
      xs.resize(row_stride * kBlock);
      for (std::vector<double>& r : rays) r.resize(row_stride * kBlock);
      detail::UndistortChain chains[kBlock];
      detail::SearchCounts counts[kBlock];
      for (int y = yb; y < ye; ++y) {
        const std::size_t at = static_cast<std::size_t>(y - yb) * row_stride;
        int* row_xs = xs.data() + at;
        const int count = detail::ListSearchedPixels(
            p.src_mask.ptr<uchar>(y), p.src_coord.ptr<float>(y), p.src_sigma.ptr<float>(y),
            p.reach.empty() ? nullptr : p.reach.ptr<uchar>(y), W, p.max_sigma, row_xs, &counts[y - yb]);
        chains[y - yb] = {row_xs,           count,           y,
                          rays[0].data() + at, rays[1].data() + at, rays[2].data() + at,
                          rays[3].data() + at, rays[4].data() + at, rays[5].data() + at,
                          rays[6].data() + at, rays[7].data() + at};
      }
      detail::UndistortChains(*p.src, chains, ye - yb, &turn);
      WalkRows(p, out, yb, ye, lanes, maps, chains, counts, w_buf, sigma_buf);
    });
    if (options.progress && !options.progress({stage, static_cast<std::size_t>(r1), static_cast<std::size_t>(H)}))
      return false;
  }
  return true;
}

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

void CheckSize(const CameraIntrinsics& cam, const DecodedCamera& d, const std::string& name, const std::string& path) {
  if (d.coordinate.cols != cam.width || d.coordinate.rows != cam.height)
    throw InputError({path, 0, "image_size"}, "the " + name + " calibration is " + std::to_string(cam.width) + "x" +
                                                  std::to_string(cam.height) + " but the " + name + " images are " +
                                                  std::to_string(d.coordinate.cols) + "x" +
                                                  std::to_string(d.coordinate.rows));
}

}  // namespace

std::string StereoMatchOptions::Validate() const {
  if (!(min_depth_mm > 0)) return "min_depth_mm: must be > 0";
  if (!(max_depth_mm > min_depth_mm)) return "max_depth_mm: must be > min_depth_mm";
  if (!(right_min_depth_mm == 0 && right_max_depth_mm == 0) &&
      !(right_min_depth_mm > 0 && right_max_depth_mm > right_min_depth_mm))
    return "right_min_depth_mm, right_max_depth_mm: both 0, or 0 < min < max";
  if (!std::isfinite(lr_tolerance_px)) return "lr_tolerance_px: must be finite";
  if (!(lr_sigma_factor >= 0 && std::isfinite(lr_sigma_factor))) return "lr_sigma_factor: must be >= 0 and finite";
  if (!(max_sigma_periods > 0)) return "max_sigma_periods: must be > 0";
  if (!(max_cell_span_periods > 0 && max_cell_span_periods <= 1)) return "max_cell_span_periods: must be in (0, 1]";
  if (!(max_modulation_ratio > 1)) return "max_modulation_ratio: must be > 1";
  if (!(search_step_px > 0 && search_step_px <= 4)) return "search_step_px: must be in (0, 4]";
  return "";
}

std::string StereoMatchSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(3);
  s << "match " << message << ": " << matched << " of " << left_valid << " left px matched ("
    << (left_valid ? 100.0 * matched / left_valid : 0.0) << "%; rejected " << rejected_noisy << " noisy, "
    << rejected_no_match << " no match, " << rejected_lr << " left-right, " << rejected_no_back_match
    << " without a back match; " << full_searches << " full searches), median sigma " << median_sigma_px << " px";
  return s.str();
}

namespace detail {
namespace {
std::mutex g_hooks_mutex;
StereoMatchTestHooks g_hooks;
}  // namespace

StereoMatchTestHooks CurrentStereoMatchTestHooks() {
  std::lock_guard<std::mutex> lock(g_hooks_mutex);
  return g_hooks;
}

void SetStereoMatchTestHooks(const StereoMatchTestHooks& hooks) {
  std::lock_guard<std::mutex> lock(g_hooks_mutex);
  g_hooks = hooks;
}
}  // namespace detail

StereoMatch MatchStereo(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
                        double period, const StereoMatchOptions& options, const std::string& calibration_path) {
  ThrowIfInvalid(options.Validate(), "StereoMatchOptions");
  const detail::StereoMatchTestHooks hooks = detail::CurrentStereoMatchTestHooks();
  CheckSize(calibration.left, left, "left", calibration_path);
  CheckSize(calibration.right, right, "right", calibration_path);
  if (!(period > 0)) throw InputError({"", 0, "period"}, "the fringe period must be > 0");
  const Mat3 R = calibration.right_from_left.linear();
  const Vec3 T = calibration.right_from_left.translation();

  const detail::RectifiedPair rectified =
      hooks.rectified_back_pass ? detail::MakeRectifiedPair(calibration) : detail::RectifiedPair{};
  auto make_pass = [&](bool left_to_right) {
    Pass p;
    const DecodedCamera& s = left_to_right ? left : right;
    const DecodedCamera& d = left_to_right ? right : left;
    p.src = left_to_right ? &calibration.left : &calibration.right;
    p.dst = left_to_right ? &calibration.right : &calibration.left;
    p.R = left_to_right ? R : Mat3(R.transpose());
    p.T = left_to_right ? T : Vec3(-R.transpose() * T);
    p.src_coord = s.coordinate;
    p.src_sigma = s.sigma_coordinate;
    p.src_mask = s.mask;
    p.dst_coord = d.coordinate;
    p.dst_sigma = d.sigma_coordinate;
    p.src_modulation = s.modulation;
    p.dst_modulation = d.modulation;
    p.dst_coord_rows = RowView(p.dst_coord);
    p.dst_sigma_rows = RowView(p.dst_sigma);
    p.dst_modulation_rows = RowView(p.dst_modulation);
    p.period = period;
    p.max_sigma = options.max_sigma_periods * period;
    p.max_span = options.max_cell_span_periods * period;
    p.cell_ok.assign(static_cast<std::size_t>(d.coordinate.rows) * d.coordinate.cols, 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, d.coordinate.rows - 1, 32), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y)
        detail::CellRow(d.coordinate.ptr<float>(y), d.coordinate.ptr<float>(y + 1), d.coordinate.cols - 1, p.max_span,
                        p.cell_ok.data() + static_cast<std::size_t>(y) * d.coordinate.cols);
    });
    if (hooks.rectified_back_pass && !left_to_right) {
      // The back pass (right to left): the left map on its rectified grid (at most 16 times the
      // image's pixels; without a grid the pass keeps the curve search).
      p.grid = detail::ResampleOnRectifiedGrid(*p.dst, rectified.rect_from_left, rectified.f, d.coordinate, p.cell_ok,
                                               16.0 * d.coordinate.total());
      if (!p.grid.coord.empty()) {
        p.grid_rows = RowView(p.grid.coord);
        p.rect = true;
        p.rect_from_src = rectified.rect_from_right;
        p.rect_f = rectified.f;
        p.rect_fb = rectified.f * rectified.baseline_mm;
        p.rect_sign = 1.0;  // the left camera sits at -B along the rectified x of the right one
      }
    }
    SetIdealBox(&p);
    if (!p.rect) BuildCurveTables(options, d.coordinate, &p);
    p.full_search = hooks.full_search;
    p.exhaustive = hooks.exhaustive_search;
    p.max_modulation_ratio = options.max_modulation_ratio;
    // Inverse depth along the source ray (its z = 1 direction). For the right camera's rays the
    // depth range is taken in its own frame, a close approximation for a rig whose cameras
    // face the same way.
    const bool own_range = !left_to_right && options.right_max_depth_mm > 0;
    p.w_lo = 1.0 / (own_range ? options.right_max_depth_mm : options.max_depth_mm);
    p.w_hi = 1.0 / (own_range ? options.right_min_depth_mm : options.min_depth_mm);
    return p;
  };

  StereoMatch result;
  StereoMatchSummary& sum = result.summary;
  PassResult back;
  const bool lr = options.lr_tolerance_px > 0;
  if (lr) {
    Pass rl = make_pass(false);
    rl.lr_tolerance = 0;
    sum.back_pass = rl.rect ? "rectified" : "curve";
    if (!RunPass(rl, &back, options, "match right->left")) {
      sum.termination = Termination::kCancelled;
      sum.message = "cancelled";
      return result;
    }
  }
  Pass lrp = make_pass(true);
  lrp.points = true;
  lrp.pixels = options.right_pixels;
  lrp.sigma_map = options.sigma_map;
  if (lr) {
    lrp.back_u = back.u;
    lrp.back_v = back.v;
    lrp.back_sigma = back.sigma;
    lrp.lr_tolerance = options.lr_tolerance_px;
    lrp.lr_sigma_factor = options.lr_sigma_factor;
    lrp.lr_check = !lrp.back_u.empty() && lrp.lr_tolerance > 0;
    lrp.lr_sigma = lrp.lr_sigma_factor > 0 && !lrp.back_sigma.empty();
    // The back maps are the back pass's own outputs, of the right image's size.
    lrp.back_u_rows = RowView(lrp.back_u);
    lrp.back_v_rows = RowView(lrp.back_v);
    lrp.back_sigma_rows = RowView(lrp.back_sigma);
    CV_Assert(!lrp.lr_check ||
              (lrp.back_v.size == lrp.back_u.size && lrp.back_v_rows.stride == lrp.back_u_rows.stride &&
               (!lrp.lr_sigma ||
                (lrp.back_sigma.size == lrp.back_u.size && lrp.back_sigma_rows.stride == lrp.back_u_rows.stride))));
    if (lrp.lr_check && hooks.skip_without_back_match)
      lrp.reach = BackReach(lrp, left.coordinate.cols, left.coordinate.rows);
  }
  PassResult fwd;
  if (!RunPass(lrp, &fwd, options, "match left->right")) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return result;
  }
  if (hooks.keep_back_matches) {
    result.back_u = back.u;
    result.back_v = back.v;
    result.back_sigma_px = back.sigma;
  }
  result.right_u = fwd.u;
  result.right_v = fwd.v;
  result.sigma_px = fwd.sigma;
  result.depth_mm = fwd.depth;
  result.point_sigma_mm = fwd.point_sigma;
  result.x_mm = fwd.x;
  result.y_mm = fwd.y;
  sum.left_valid = fwd.valid;
  sum.matched = fwd.matched;
  sum.rejected_noisy = fwd.noisy;
  sum.rejected_no_match = fwd.no_match;
  sum.rejected_lr = fwd.lr;
  sum.rejected_no_back_match = fwd.unreachable;
  sum.full_searches = fwd.full;
  float median_sigma = std::numeric_limits<float>::quiet_NaN();
  if (lrp.sigma_map) {
    median_sigma = detail::UpperMedian(fwd.sigma);
  } else {
    std::size_t count = 0;
    for (const std::vector<float>& part : fwd.sigma_parts) count += part.size();
    if (count) median_sigma = detail::ValuesAtRanks(fwd.sigma_parts, {count / 2})[0];
  }
  if (std::isfinite(median_sigma)) sum.median_sigma_px = median_sigma;
  return result;
}

}  // namespace ramtk::vision
