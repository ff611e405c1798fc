#pragma once
// The search of one source pixel's match along its epipolar curve in the destination image
// (Matcher). Its member functions are defined inline, by concern, in stereo_matcher.h (the curve
// and its samples), stereo_curve_search.h, stereo_local_search.h, stereo_rect_search.h and
// stereo_consistency.h; stereo_walk.cpp, the one file that runs them, includes all five so the
// search inlines into the walk as one unit.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ramtk/vision/kernels/fast_round.h"
#include "stereo_pass.h"

namespace ramtk::vision::detail {
namespace {  // internal to stereo_walk.cpp, the one file that includes it

struct Matcher {
  const Pass& p;
  Vec3 a = Vec3::Zero();  // R * ideal ray of the source pixel (z = 1 in the source frame)
  double c_src = 0;
  double w_lo = 0, w_hi = 0;           // the full search's range: the pass's, clipped to the image (SetRange)
  double speed_k = 0, step_per_k = 0;  // Speed(w) = speed_k / q_z(w)^2; step_px / speed_k (SetRange)
  // Pass::rect: the source ray r = rect_from_src (ideal, 1): its rectified pixel f r_x / r_z,
  // f r_y / r_z (the destination row) and r_z (SetRectRay).
  double rs_u = 0, rs_v = 0, rs_z = 1;
  struct Root {
    double w = 0, slope = 0;
    Sample at;
    // Velocity of the destination pixel per unit w near the root (LocalSearch: at its start, a
    // pixel or so away, which changes the speed by < 1e-4 relative); NaN: not known.
    Vec2 vel = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  };

  // The epipolar curve and its samples (stereo_matcher.h)
  static void Clip(double ac, double tc, double az, double tz, double b0, double b1, double* lo, double* hi);
  void SetRange();
  bool InRange(double w) const;
  bool Pixel(double w, Vec2* pix) const;
  double Speed(double w) const;
  double Step(double w) const;
  Sample Eval(double w) const;
  bool ValidCell(const Vec2& pix, int* u0, int* v0) const;
  Sample EvalAt(const Vec2& pix) const;
  Sample CellAt(const Vec2& pix) const;
  void Complete(Sample* sample) const;
  bool Refine(double wa, Sample sa, double wb, Sample sb, Root* root) const;
  bool PixelAndVelocity(double w, Vec2* pix, Vec2* vel) const;
  void NextSample(double w, const Sample& sk, Sample* prev, double* w_prev, std::vector<Root>* roots) const;

  // Every crossing along the curve, pruned by the tile bounds (stereo_curve_search.h)
  int TileSign(bool in_front, const Vec2& pix) const;
  int NearSign(bool in_front, const Vec2& pix) const;
  int MidSign(bool in_front, const Vec2& pix) const;
  bool SegmentClear(const Vec2& pa, const Vec2& pb, const Vec2& pm) const;
  int BoundSign(bool in_front, const Vec2& pix, int cell_px, int nx, int ny, int outside,
                const std::vector<float>& lo_of, const std::vector<float>& hi_of) const;
  void ExhaustiveSearch(std::vector<Root>* roots) const;
  bool RowsMayCross() const;
  void SampleStretch(const std::vector<double>& ws, const Vec2& pix_a, bool front_a, const Vec2& pix_b, bool front_b,
                     bool* prev_fine, Sample* prev, double* w_prev, std::vector<Root>* roots) const;
  void FullSearch(std::vector<Root>* roots) const;

  // The crossing near a neighbour's match (stereo_local_search.h)
  bool LineCrossing(const Vec2& pix, const Vec2& vel, double max_px, double* s_root, double* dfds) const;
  bool LocalSearch(double w0, Root* root) const;

  // The search on the rectified grid, Pass::rect (stereo_rect_search.h)
  bool SetRectRay(double u, double v, double z);
  double RectColumn(double w) const;
  double RectW(double column) const;
  bool RectRows(int* j, double* fv) const;
  bool RectCell(const float* r0, const float* r1, int i, double fv, double* g0, double* g1) const;
  bool RectRoot(double column, double dg_du, Root* root) const;
  bool RectLocalSearch(double w0, Root* root) const;
  void RectFullSearch(std::vector<Root>* roots) const;

  // Whether a crossing is the same surface point (stereo_consistency.h)
  bool Accept(const Root& r, double b_src, double su, double sv) const;
  bool Consistent(const Vec2& dst_pix, double su, double sv) const;
};

// Narrows [lo, hi] to where g(w) = (ac + tc w) / (az + tz w) lies in [b0, b1]; g is monotonic
// (a Moebius function) while az + tz w > 0.
inline void Matcher::Clip(double ac, double tc, double az, double tz, double b0, double b1, double* lo, double* hi) {
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
inline void Matcher::SetRange() {
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
inline bool Matcher::InRange(double w) const {
  if (!(w >= p.w_lo && w <= p.w_hi)) return false;
  const double qz = a.z() + p.T.z() * w;
  if (!(qz > 1e-9)) return false;
  const double qx = a.x() + p.T.x() * w, qy = a.y() + p.T.y() * w;
  return qx >= p.box_x0 * qz && qx <= p.box_x1 * qz && qy >= p.box_y0 * qz && qy <= p.box_y1 * qz;
}

// Destination pixel of the point at inverse depth w on the source ray; false behind the camera.
inline bool Matcher::Pixel(double w, Vec2* pix) const {
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
inline double Matcher::Speed(double w) const {
  const double qz = a.z() + p.T.z() * w;
  return speed_k / (qz * qz);
}

// w + step_px / Speed(w), without the division.
inline double Matcher::Step(double w) const {
  const double qz = a.z() + p.T.z() * w;
  return w + step_per_k * qz * qz;
}

inline Sample Matcher::Eval(double w) const {
  Sample s;
  if (!Pixel(w, &s.pix)) return s;
  return EvalAt(s.pix);
}

// The cell under `pix` (its top-left pixel u0, v0): true if it lies in the image and is one of
// the cells EvalAt and LineCrossing interpolate (Pass::cell_ok).
inline bool Matcher::ValidCell(const Vec2& pix, int* u0, int* v0) const {
  *u0 = FloorToInt(pix.x());
  *v0 = FloorToInt(pix.y());
  if (*u0 < 0 || *v0 < 0 || *u0 + 1 >= p.dst_coord.cols || *v0 + 1 >= p.dst_coord.rows) return false;
  return p.cell_ok[static_cast<std::size_t>(*v0) * p.dst_coord.cols + *u0] != 0;
}

inline Sample Matcher::EvalAt(const Vec2& pix) const {
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
inline Sample Matcher::CellAt(const Vec2& pix) const {
  Sample s;
  s.pix = pix;
  s.ok = ValidCell(pix, &s.u0, &s.v0);
  return s;
}

// Fills the variance and modulation of a valid sample (EvalAt leaves them out: only the
// crossing's own sample needs them).
inline void Matcher::Complete(Sample* sample) const {
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

// Regula falsi (Illinois) on the bilinear surface between two samples of opposite sign. It stops
// at 1e-6 of a period in coordinate or a 1e-3 px bracket: the match sigma is ~0.05 px, and a
// tighter stop (1e-9 period / 1e-6 px) moves points by < 0.4 um for 5-7 % more match time
// (docs/performance.md).
inline bool Matcher::Refine(double wa, Sample sa, double wb, Sample sb, Root* root) const {
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
inline bool Matcher::PixelAndVelocity(double w, Vec2* pix, Vec2* vel) const {
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

// The search's rule between consecutive samples: a crossing lies between two valid samples of
// opposite sign (or at a zero); it is refined and kept. Then `sk` at w becomes the previous.
inline void Matcher::NextSample(double w, const Sample& sk, Sample* prev, double* w_prev,
                                std::vector<Root>* roots) const {
  if (sk.ok && prev->ok && ((sk.f > 0) != (prev->f > 0) || sk.f == 0)) {
    Root r;
    if (Refine(*w_prev, *prev, w, sk, &r)) roots->push_back(r);
  }
  *prev = sk;
  *w_prev = w;
}

}  // namespace
}  // namespace ramtk::vision::detail
