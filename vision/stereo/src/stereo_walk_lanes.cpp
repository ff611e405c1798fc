// The match's walk on four lanes (stereo_walk_lanes.h). Each step names the scalar function whose
// expressions it repeats (stereo_matcher.h and the headers beside it, Matcher); the products and sums keep their order.
#include "ramtk/vision/stereo/detail/stereo_walk_lanes.h"

#include <immintrin.h>

#include <atomic>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/distort_lanes.h"

namespace ramtk::vision::detail {
namespace {

std::atomic<bool> g_check{false};
std::atomic<long> g_checked{0}, g_mismatched{0};

RAMTK_AVX2_INLINE __m256d K(double v) { return _mm256_set1_pd(v); }
RAMTK_AVX2_INLINE __m256d Add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Div(__m256d a, __m256d b) { return _mm256_div_pd(a, b); }
RAMTK_AVX2_INLINE __m256d And(__m256d a, __m256d b) { return _mm256_and_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Or(__m256d a, __m256d b) { return _mm256_or_pd(a, b); }
RAMTK_AVX2_INLINE __m256d Not(__m256d a) { return _mm256_xor_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))); }
// b where m, else a.
RAMTK_AVX2_INLINE __m256d Pick(__m256d m, __m256d a, __m256d b) { return _mm256_blendv_pd(a, b, m); }
RAMTK_AVX2_INLINE __m256d Lt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
RAMTK_AVX2_INLINE __m256d Le(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
RAMTK_AVX2_INLINE __m256d Gt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
RAMTK_AVX2_INLINE __m256d Ge(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
RAMTK_AVX2_INLINE __m256d Eq(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
RAMTK_AVX2_INLINE __m256d Ne(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
RAMTK_AVX2_INLINE __m256d Abs(__m256d a) {
  return _mm256_andnot_pd(_mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull))), a);
}
RAMTK_AVX2_INLINE __m256d IsNan(__m256d a) { return _mm256_cmp_pd(a, a, _CMP_UNORD_Q); }
// x - x is 0 for a finite x and NaN otherwise.
RAMTK_AVX2_INLINE __m256d IsFinite(__m256d a) { return Eq(Sub(a, a), K(0.0)); }
// std::copysign(mag, sgn) for a magnitude without sign bit (a square root).
RAMTK_AVX2_INLINE __m256d CopySign(__m256d mag, __m256d sgn) {
  const __m256d sign = _mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull)));
  return Or(_mm256_andnot_pd(sign, mag), And(sign, sgn));
}
// std::min(a, b) and std::max(a, b): (b < a) ? b : a and (a < b) ? b : a.
RAMTK_AVX2_INLINE __m256d Min(__m256d a, __m256d b) { return Pick(Lt(b, a), a, b); }
RAMTK_AVX2_INLINE __m256d Max(__m256d a, __m256d b) { return Pick(Lt(a, b), a, b); }
// The same in float.
RAMTK_AVX2_INLINE __m128 MinF(__m128 a, __m128 b) { return _mm_blendv_ps(a, b, _mm_cmplt_ps(b, a)); }
RAMTK_AVX2_INLINE __m128 MaxF(__m128 a, __m128 b) { return _mm_blendv_ps(a, b, _mm_cmplt_ps(a, b)); }
RAMTK_AVX2_INLINE __m256d Load(const double* v) { return _mm256_loadu_pd(v); }

// A four-bit lane mask as 64-bit lanes (Pick's masks) and as 32-bit ones (tables: the shifts and
// inserts were a tenth of the kernel's instructions).
struct LaneTables {
  alignas(32) long long m64[16][4];
  alignas(16) int m32[16][4];
  LaneTables() {
    for (int m = 0; m < 16; ++m)
      for (int i = 0; i < 4; ++i) m64[m][i] = -static_cast<long long>((m >> i) & 1), m32[m][i] = -((m >> i) & 1);
  }
};
const LaneTables kLaneTables;
RAMTK_AVX2_INLINE __m256d Lanes(int mask) {
  return _mm256_load_pd(reinterpret_cast<const double*>(kLaneTables.m64[mask]));
}
RAMTK_AVX2_INLINE __m128i Lanes32(int mask) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneTables.m32[mask]));
}

// The offsets v0 * stride + u0 of four cells (whole u0, v0; lanes off the mask: 0, a cell every
// map has). LanesWalk (stereo_walk.cpp) keeps the maps within int offsets.
RAMTK_AVX2_INLINE __m128i Offsets(__m256d u0, __m256d v0, int stride, int mask) {
  const __m128i off =
      _mm_add_epi32(_mm_mullo_epi32(_mm256_cvttpd_epi32(v0), _mm_set1_epi32(stride)), _mm256_cvttpd_epi32(u0));
  return _mm_and_si128(off, Lanes32(mask));
}

// Of the lanes in `mask`, those whose cell (top-left corner u0, v0, whole) lies inside an image of
// cols x rows (ValidCell's bounds; FloorToInt's range |v| < 1e9 is within them), exact in double.
RAMTK_AVX2_INLINE int Inside(__m256d u0, __m256d v0, int cols, int rows, int mask) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d inside =
      And(And(Ge(u0, zero), Ge(v0, zero)), And(Lt(Add(u0, one), K(cols)), Lt(Add(v0, one), K(rows))));
  return _mm256_movemask_pd(inside) & mask;
}

// Of the lanes in `mask`, the cells inside the image whose Pass::cell_ok is set (ValidCell).
RAMTK_AVX2_INLINE int ValidCells(const WalkMaps& m, __m256d u0, __m256d v0, int mask) {
  const int in = Inside(u0, v0, m.cols, m.rows, mask);
  alignas(16) int o[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(o), Offsets(u0, v0, m.cols, in));
  int ok = 0;
  for (int i = 0; i < 4; ++i) ok |= (m.cell_ok[o[i]] != 0) << i;
  return ok & in;
}

// The cells under four pixels (ValidCell): their floors, the lanes whose cell is valid and the
// cells' offsets in the maps.
struct Cells {
  __m256d u0, v0;
  int ok = 0;
  __m128i at;
};
RAMTK_AVX2_INLINE Cells CellsAt(const WalkMaps& m, __m256d u, __m256d v, int mask) {
  Cells c;
  c.u0 = _mm256_floor_pd(u);
  c.v0 = _mm256_floor_pd(v);
  c.ok = ValidCells(m, c.u0, c.v0, mask);
  c.at = Offsets(c.u0, c.v0, m.stride, c.ok);
  return c;
}

// The four corners of cells (c00 at the offset, c10 right of it, c01 below, c11 diagonal), each
// float widened to double (exact).
struct Corners {
  __m256d c00, c10, c01, c11;
};
RAMTK_AVX2_INLINE Corners CornersOf(const float* map, int stride, __m128i at) {
  alignas(16) int o[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(o), at);
  const float *p0 = map + o[0], *p1 = map + o[1], *p2 = map + o[2], *p3 = map + o[3];
  const int s = stride, t = stride + 1;
  return {_mm256_cvtps_pd(_mm_setr_ps(p0[0], p1[0], p2[0], p3[0])),
          _mm256_cvtps_pd(_mm_setr_ps(p0[1], p1[1], p2[1], p3[1])),
          _mm256_cvtps_pd(_mm_setr_ps(p0[s], p1[s], p2[s], p3[s])),
          _mm256_cvtps_pd(_mm_setr_ps(p0[t], p1[t], p2[t], p3[t]))};
}

// The bilinear weights at (u, v) of cells with top-left corner (u0, v0), as EvalAt and Complete
// take them.
struct Weights {
  __m256d w00, w10, w01, w11;
};
RAMTK_AVX2_INLINE Weights WeightsAt(__m256d u, __m256d v, __m256d u0, __m256d v0) {
  const __m256d fu = Sub(u, u0), fv = Sub(v, v0), one = K(1.0);
  return {Mul(Sub(one, fu), Sub(one, fv)), Mul(fu, Sub(one, fv)), Mul(Sub(one, fu), fv), Mul(fu, fv)};
}
RAMTK_AVX2_INLINE __m256d Blend(const Weights& w, const Corners& c) {
  return Add(Add(Add(Mul(w.w00, c.c00), Mul(w.w10, c.c10)), Mul(w.w01, c.c01)), Mul(w.w11, c.c11));
}

// EvalAt: the interpolated coordinate minus c_src at four pixels; `ok` the lanes with a valid cell.
RAMTK_AVX2_INLINE __m256d EvalAt(const WalkMaps& m, __m256d u, __m256d v, __m256d c_src, int mask, int* ok) {
  const Cells cells = CellsAt(m, u, v, mask);
  *ok = cells.ok;
  const Corners c = CornersOf(m.coord, m.stride, cells.at);
  return Sub(Blend(WeightsAt(u, v, cells.u0, cells.v0), c), c_src);
}

// PixelAndVelocity(w): the destination pixel of inverse depth w on the source rays a and its
// velocity per unit w; returns the lanes in front of the camera.
RAMTK_AVX2_INLINE int PixelAndVelocity(const WalkMaps& m, __m256d ax, __m256d ay, __m256d az, __m256d w, __m256d* pix_x,
                                       __m256d* pix_y, __m256d* vel_x, __m256d* vel_y) {
  const __m256d tx = K(m.t[0]), ty = K(m.t[1]), tz = K(m.t[2]), fx = K(m.fx), fy = K(m.fy);
  const __m256d qx = Add(ax, Mul(tx, w)), qy = Add(ay, Mul(ty, w)), qz = Add(az, Mul(tz, w));
  const __m256d iz = Div(K(1.0), qz);
  const __m256d ix = Mul(qx, iz), iy = Mul(qy, iz);
  __m256d r2, radial, dx, dy;
  DistortNormalized4(m.distortion, ix, iy, &r2, &radial, &dx, &dy);
  *pix_x = Add(Mul(fx, dx), K(m.cx));
  *pix_y = Add(Mul(fy, dy), K(m.cy));
  const __m256d di_x = Mul(Mul(Sub(Mul(tx, az), Mul(ax, tz)), iz), iz);
  const __m256d di_y = Mul(Mul(Sub(Mul(ty, az), Mul(ay, tz)), iz), iz);
  __m256d j00, j01, j10, j11;
  DistortJacobian4(m.distortion, ix, iy, r2, radial, &j00, &j01, &j10, &j11);
  // Eigen's 2 x 2 product: each row's two products summed left to right.
  *vel_x = Mul(fx, Add(Mul(j00, di_x), Mul(j01, di_y)));
  *vel_y = Mul(fy, Add(Mul(j10, di_x), Mul(j11, di_y)));
  return _mm256_movemask_pd(Gt(qz, K(1e-12)));
}

// InRange(w) from q = a + T w: the pass's range, in front of the destination camera, inside its box.
RAMTK_AVX2_INLINE int InRange(const WalkMaps& m, __m256d w, __m256d qx, __m256d qy, __m256d qz) {
  const __m256d in_range = And(And(And(Ge(w, K(m.w_lo)), Le(w, K(m.w_hi))), Gt(qz, K(1e-9))),
                               And(And(Ge(qx, Mul(K(m.box_x0), qz)), Le(qx, Mul(K(m.box_x1), qz))),
                                   And(Ge(qy, Mul(K(m.box_y0), qz)), Le(qy, Mul(K(m.box_y1), qz)))));
  return _mm256_movemask_pd(in_range);
}

// The end of both walks: Complete at the crossing `at` (its cell `cell`), Accept (the modulations
// agree, and the left-right check passes through the interpolated back match; its other cases go
// to the scalar walk), and the settled lanes' roots into `l`.
RAMTK_AVX2_INLINE void Settle(const WalkMaps& m, int alive, __m256d w, __m256d slope, __m256d at_x, __m256d at_y,
                              const Cells& cell, __m256d vel_x, __m256d vel_y, WalkLanes* l) {
  const __m256d zero = K(0.0), one = K(1.0);
  const Weights wt = WeightsAt(at_x, at_y, cell.u0, cell.v0);
  const Corners sg = CornersOf(m.sigma, m.stride, cell.at);
  __m256d var =
      Add(Add(Add(Mul(Mul(Mul(wt.w00, wt.w00), sg.c00), sg.c00), Mul(Mul(Mul(wt.w10, wt.w10), sg.c10), sg.c10)),
              Mul(Mul(Mul(wt.w01, wt.w01), sg.c01), sg.c01)),
          Mul(Mul(Mul(wt.w11, wt.w11), sg.c11), sg.c11));
  var = And(var, IsFinite(var));  // not finite: 0
  const __m256d modulation = Blend(wt, CornersOf(m.modulation, m.stride, cell.at));
  const __m256d tiny = K(1e-6);
  const __m256d ratio = Div(Max(tiny, modulation), Max(tiny, Load(l->b_src)));
  const __m256d mmr = K(m.max_modulation_ratio);
  alive &= ~_mm256_movemask_pd(Or(Gt(ratio, mmr), Lt(Mul(ratio, mmr), one)));
  if (m.lr_check && alive) {
    // Consistent: the back matches' cells (the crossing's floors), inside the back maps.
    alive = Inside(cell.u0, cell.v0, m.back_cols, m.back_rows, alive);
    const __m128i at = Offsets(cell.u0, cell.v0, m.back_stride, alive);
    const Corners bu = CornersOf(m.back_u, m.back_stride, at);
    const Corners bv = CornersOf(m.back_v, m.back_stride, at);
    const __m256d all = IsFinite(Add(Add(Add(Add(Sub(bu.c00, bu.c00), Sub(bu.c10, bu.c10)), Sub(bu.c01, bu.c01)),
                                         Add(Sub(bu.c11, bu.c11), Sub(bv.c00, bv.c00))),
                                     Add(Add(Sub(bv.c10, bv.c10), Sub(bv.c01, bv.c01)), Sub(bv.c11, bv.c11))));
    alive &= _mm256_movemask_pd(all);
    __m256d tolerance = K(m.lr_tolerance);
    if (m.lr_sigma) {
      const Corners bs = CornersOf(m.back_sigma, m.back_stride, at);
      for (const __m256d s : {bs.c00, bs.c10, bs.c01, bs.c11})
        tolerance = Pick(IsFinite(s), tolerance, Max(tolerance, Mul(K(m.lr_sigma_factor), s)));
    }
    const __m256d mu =
        Add(Add(Add(Add(zero, Mul(wt.w00, bu.c00)), Mul(wt.w10, bu.c10)), Mul(wt.w01, bu.c01)), Mul(wt.w11, bu.c11));
    const __m256d mv =
        Add(Add(Add(Add(zero, Mul(wt.w00, bv.c00)), Mul(wt.w10, bv.c10)), Mul(wt.w01, bv.c01)), Mul(wt.w11, bv.c11));
    __m256d spread = zero;
    for (int k = 0; k < 4; ++k) {
      const __m256d ku = k == 0 ? bu.c00 : k == 1 ? bu.c10 : k == 2 ? bu.c01 : bu.c11;
      const __m256d kv = k == 0 ? bv.c00 : k == 1 ? bv.c10 : k == 2 ? bv.c01 : bv.c11;
      const __m256d du = Sub(ku, bu.c00), dv = Sub(kv, bv.c00);
      spread = Max(spread, Add(Mul(du, du), Mul(dv, dv)));
    }
    alive &= _mm256_movemask_pd(Lt(spread, K(16.0)));
    const __m256d eu = Sub(mu, Load(l->su)), ev = Sub(mv, Load(l->sv));
    alive &= _mm256_movemask_pd(Le(Add(Mul(eu, eu), Mul(ev, ev)), Mul(tolerance, tolerance)));
  }
  if (!alive) return;
  l->found = alive;
  _mm256_storeu_pd(l->w, w);
  _mm256_storeu_pd(l->slope, slope);
  _mm256_storeu_pd(l->pix_x, at_x);
  _mm256_storeu_pd(l->pix_y, at_y);
  _mm256_storeu_pd(l->var, var);
  _mm256_storeu_pd(l->modulation, modulation);
  _mm256_storeu_pd(l->vel_x, vel_x);
  _mm256_storeu_pd(l->vel_y, vel_y);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(l->u0), _mm256_cvttpd_epi32(cell.u0));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(l->v0), _mm256_cvttpd_epi32(cell.v0));
  // RunPass's outputs. Match sigma: var(w) = (sigma_src^2 + var(c_dst)) / slope^2, along the
  // curve at the pixel's speed; the point X(w) = (ideal, 1) / w, x and y from the depth as
  // stored, |dX/dw| = |(ideal, 1)| / w^2.
  const __m256d s_src = Load(l->sigma_src);
  const __m256d sigma_w = Div(_mm256_sqrt_pd(Add(Mul(s_src, s_src), var)), Abs(slope));
  const __m256d speed = _mm256_sqrt_pd(Add(Mul(vel_x, vel_x), Mul(vel_y, vel_y)));
  const __m256d sigma_px = Mul(speed, sigma_w);
  _mm_storeu_ps(l->out_u, _mm256_cvtpd_ps(at_x));
  _mm_storeu_ps(l->out_v, _mm256_cvtpd_ps(at_y));
  _mm_storeu_ps(l->out_sigma, _mm256_cvtpd_ps(sigma_px));
  _mm256_storeu_pd(l->out_sigma_d, sigma_px);
  if (!m.points) return;
  const __m256d z = Div(K(1.0), w);
  const __m128 zf = _mm256_cvtpd_ps(z);
  const __m256d zd = _mm256_cvtps_pd(zf);
  const __m256d ix = Load(l->ideal_x), iy = Load(l->ideal_y);
  const __m256d px = Mul(ix, zd), py = Mul(iy, zd);
  const __m256d ray = _mm256_sqrt_pd(Add(Add(Mul(ix, ix), Mul(iy, iy)), K(1.0)));
  const __m256d point_sigma = Mul(Mul(Mul(ray, z), z), sigma_w);
  _mm_storeu_ps(l->out_depth, zf);
  _mm_storeu_ps(l->out_x, _mm256_cvtpd_ps(px));
  _mm_storeu_ps(l->out_y, _mm256_cvtpd_ps(py));
  _mm_storeu_ps(l->out_point_sigma, _mm256_cvtpd_ps(point_sigma));
  _mm256_storeu_pd(l->out_x_d, px);
  _mm256_storeu_pd(l->out_y_d, py);
  _mm256_storeu_pd(l->out_point_sigma_d, point_sigma);
}

// The curve search's walk (Matcher::LocalSearch from w0, then Accept).
RAMTK_AVX2 void WalkFourLanesAvx2(const WalkMaps& m, WalkLanes* l) {
  const __m256d zero = K(0.0), one = K(1.0);
  const __m256d ax = Load(l->a_x), ay = Load(l->a_y), az = Load(l->a_z), c_src = Load(l->c_src);
  int alive = l->active;
  l->found = 0;

  // PixelAndVelocity(w0).
  const __m256d w0 = Load(l->w0);
  __m256d pix_x, pix_y, vel_x, vel_y;
  alive &= PixelAndVelocity(m, ax, ay, az, w0, &pix_x, &pix_y, &vel_x, &vel_y);
  // LineCrossing(pix, vel, 16 step_px): at most three cells on the lanes.
  const __m256d speed = _mm256_sqrt_pd(Add(Mul(vel_x, vel_x), Mul(vel_y, vel_y)));
  alive &= _mm256_movemask_pd(Gt(speed, zero));
  const __m256d s_max = Div(K(16.0 * m.step_px), speed);
  __m256d u0 = _mm256_floor_pd(pix_x), v0 = _mm256_floor_pd(pix_y);
  __m256d dir = zero, s_in = zero, s_root = zero, dfds = zero;
  int settled = 0;  // lanes whose crossing is found
  for (int cell = 0; cell < 3; ++cell) {
    const int open = alive & ~settled;
    if (!open) break;
    const int in = ValidCells(m, u0, v0, open);
    alive &= ~(open & ~in);  // off the image or an invalid cell: the scalar walk fails there too
    if (!in) break;
    const Corners c = CornersOf(m.coord, m.stride, Offsets(u0, v0, m.stride, in));
    const __m256d au = Sub(pix_x, u0), av = Sub(pix_y, v0);
    const __m256d ka = Sub(c.c10, c.c00), kb = Sub(c.c01, c.c00), kc = Add(Sub(Sub(c.c11, c.c10), c.c01), c.c00);
    const __m256d A = Add(Add(Add(Sub(c.c00, c_src), Mul(ka, au)), Mul(kb, av)), Mul(Mul(kc, au), av));
    const __m256d B = Add(Add(Mul(ka, vel_x), Mul(kb, vel_y)), Mul(kc, Add(Mul(au, vel_y), Mul(av, vel_x))));
    const __m256d C = Mul(Mul(kc, vel_x), vel_y);
    if (cell == 0) {
      const __m256d f0 = Add(Add(A, Mul(B, s_in)), Mul(Mul(C, s_in), s_in));
      const __m256d g0 = Add(B, Mul(Mul(K(2.0), C), s_in));
      // f0 == 0 (a crossing at the seed's pixel, rare), or g0 zero or not finite: the scalar walk.
      alive &= ~_mm256_movemask_pd(Or(Eq(f0, zero), Or(Eq(g0, zero), Not(IsFinite(g0)))));
      dir = Pick(Gt(Mul(f0, g0), zero), one, K(-1.0));
    }
    const int live = in & alive;
    // Where the line leaves the cell, going in direction dir.
    const __m256d ddx = Mul(dir, vel_x), ddy = Mul(dir, vel_y);
    // ((u0 + 1) - pix) / d going right, (u0 - pix) / d going left, 1e300 not moving: one division.
    const __m256d right = Gt(ddx, zero), down = Gt(ddy, zero);
    const __m256d ex = Pick(Or(right, Lt(ddx, zero)), K(1e300), Div(Sub(Pick(right, u0, Add(u0, one)), pix_x), ddx));
    const __m256d ey = Pick(Or(down, Lt(ddy, zero)), K(1e300), Div(Sub(Pick(down, v0, Add(v0, one)), pix_y), ddy));
    const __m256d t_out = Min(Min(ex, ey), s_max);  // std::min({ex, ey, s_max})
    const __m256d e_in = Mul(dir, s_in), e_out = Mul(dir, t_out);
    const __m256d lo = Min(e_in, e_out), hi = Max(e_in, e_out);
    // The roots of A + B s + C s^2 (stable form), the first one met going in direction dir.
    const __m256d disc = Sub(Mul(B, B), Mul(Mul(K(4.0), A), C));
    const __m256d real = Ge(disc, zero);
    const __m256d q = Mul(K(-0.5), Add(B, CopySign(_mm256_sqrt_pd(disc), B)));
    const __m256d nan = K(std::numeric_limits<double>::quiet_NaN());
    const __m256d r1 = Pick(Ne(q, zero), nan, Div(A, q)), r2 = Pick(Ne(C, zero), nan, Div(q, C));
    const __m256d lo_m = Sub(lo, Mul(K(1e-12), Add(Abs(lo), K(1e-300))));
    const __m256d hi_m = Add(hi, Mul(K(1e-12), Add(Abs(hi), K(1e-300))));
    __m256d best = nan;
    for (const __m256d r : {r1, r2}) {
      const __m256d take = And(And(Ge(r, lo_m), Le(r, hi_m)), Or(IsNan(best), Lt(Mul(dir, r), Mul(dir, best))));
      best = Pick(And(real, take), best, r);
    }
    const __m256d got = Not(IsNan(best));
    const int got_mask = _mm256_movemask_pd(got) & live;
    const __m256d got_lanes = Lanes(got_mask);
    const __m256d slope = Add(B, Mul(Mul(K(2.0), C), best));
    s_root = Pick(got_lanes, s_root, best);
    dfds = Pick(got_lanes, dfds, slope);
    alive &= ~(got_mask & _mm256_movemask_pd(Eq(slope, zero)));  // LineCrossing's dfds != 0
    settled |= got_mask;
    // The others go on into the next cell, unless the reach ends here.
    const int on = live & ~got_mask;
    alive &= ~(on & _mm256_movemask_pd(Ge(t_out, s_max)));
    s_in = Pick(got_lanes, Mul(dir, t_out), s_in);
    u0 = Pick(got_lanes, Add(u0, Pick(Le(ex, ey), zero, Pick(right, K(-1.0), one))), u0);
    v0 = Pick(got_lanes, Add(v0, Pick(Le(ey, ex), zero, Pick(down, K(-1.0), one))), v0);
  }
  alive &= settled;
  if (!alive) return;

  // LocalSearch's first round: the curve's own pixel at w0 + s, within 1e-4 px of the line's.
  const __m256d w = Add(w0, s_root);
  const __m256d qx = Add(ax, Mul(K(m.t[0]), w)), qy = Add(ay, Mul(K(m.t[1]), w)), qz = Add(az, Mul(K(m.t[2]), w));
  alive &= _mm256_movemask_pd(Gt(qz, K(1e-12)));
  __m256d at_x, at_y;
  {
    __m256d r2, radial, dx, dy;
    DistortNormalized4(m.distortion, Div(qx, qz), Div(qy, qz), &r2, &radial, &dx, &dy);
    const __m256d on_x = Add(Mul(K(m.fx), dx), K(m.cx)), on_y = Add(Mul(K(m.fy), dy), K(m.cy));
    const __m256d gap_x = Sub(on_x, Add(pix_x, Mul(vel_x, s_root))), gap_y = Sub(on_y, Add(pix_y, Mul(vel_y, s_root)));
    alive &= _mm256_movemask_pd(Lt(Add(Mul(gap_x, gap_x), Mul(gap_y, gap_y)), K(1e-8)));
    alive &= InRange(m, w, qx, qy, qz);
    // The crossing: pix + vel s with s = 0.
    at_x = Add(on_x, Mul(vel_x, zero));
    at_y = Add(on_y, Mul(vel_y, zero));
  }
  if (!alive) return;
  const Cells cell = CellsAt(m, at_x, at_y, alive);  // CellAt
  alive = cell.ok;
  if (!alive) return;
  // The slope: the secant over step_px / 4 on each side along the tangent, else the derivative.
  const __m256d hs = Div(K(0.25 * m.step_px), speed);
  int ok_a = 0, ok_b = 0;
  const __m256d fa = EvalAt(m, Sub(at_x, Mul(vel_x, hs)), Sub(at_y, Mul(vel_y, hs)), c_src, alive, &ok_a);
  const __m256d fb = EvalAt(m, Add(at_x, Mul(vel_x, hs)), Add(at_y, Mul(vel_y, hs)), c_src, alive, &ok_b);
  const int both = ok_a & ok_b;
  const __m256d both_lanes = Lanes(both);
  const __m256d secant =
      Pick(And(both_lanes, Le(Abs(Sub(fb, fa)), K(m.max_span))), zero, Div(Sub(fb, fa), Mul(K(2.0), hs)));
  const __m256d slope = Pick(Gt(Mul(secant, dfds), zero), dfds, secant);
  Settle(m, alive, w, slope, at_x, at_y, cell, vel_x, vel_y, l);
}

// The rectified search's walk (Matcher::RectLocalSearch from w0, RectRoot, then Accept).
RAMTK_AVX2 void RectWalkFourLanesAvx2(const WalkMaps& m, WalkLanes* l) {
  const __m256d zero = K(0.0), one = K(1.0);
  const __m256d rs_u = Load(l->rs_u), rs_v = Load(l->rs_v), rs_z = Load(l->rs_z), c_src = Load(l->c_src);
  const __m256d sign = K(m.rect_sign), fb = K(m.rect_fb);
  int alive = l->active & _mm256_movemask_pd(Gt(rs_z, K(1e-9)));  // SetRectRay
  l->found = 0;
  // RectRows: the grid row pair (j, j + 1) around v and v's fraction between them.
  const __m256d v = Sub(rs_v, K(m.grid_v0));
  alive &= _mm256_movemask_pd(And(Ge(v, zero), Lt(v, K(m.grid_rows - 1))));
  const __m256d j = _mm256_floor_pd(v), fv = Sub(v, j);
  // RectColumn(w0).
  const __m256d c0 = Sub(Add(rs_u, Div(Mul(Mul(sign, fb), Load(l->w0)), rs_z)), K(m.grid_u0));
  alive &= _mm256_movemask_pd(And(Ge(c0, zero), Lt(c0, K(m.grid_cols - 1))));
  if (!alive) return;
  __m256d i = _mm256_floor_pd(c0), dir = zero;
  __m256d column = zero, dg_du = zero;
  const __m128i rows = Offsets(zero, j, m.grid_stride, alive);  // j * stride: the row pair's start
  alignas(16) int row_at[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(row_at), rows);
  int settled = 0;
  for (int n = 0; n < 4; ++n) {
    // The loop's bounds (i >= 0, i + 1 < cols) before each cell.
    const int open = Inside(i, zero, m.grid_cols, 2, alive & ~settled);
    alive &= ~((alive & ~settled) & ~open);  // walked off the grid: the scalar walk fails too
    if (!open) break;
    // RectCell: the four samples as float, their span and finiteness, g at both columns.
    alignas(16) int col[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(col), _mm_and_si128(_mm256_cvttpd_epi32(i), Lanes32(open)));
    const float* g = m.grid;
    const int s = m.grid_stride;
    const __m128 a0 =
        _mm_setr_ps(g[row_at[0] + col[0]], g[row_at[1] + col[1]], g[row_at[2] + col[2]], g[row_at[3] + col[3]]);
    const __m128 a1 = _mm_setr_ps(g[row_at[0] + col[0] + 1], g[row_at[1] + col[1] + 1], g[row_at[2] + col[2] + 1],
                                  g[row_at[3] + col[3] + 1]);
    const __m128 b0 = _mm_setr_ps(g[row_at[0] + s + col[0]], g[row_at[1] + s + col[1]], g[row_at[2] + s + col[2]],
                                  g[row_at[3] + s + col[3]]);
    const __m128 b1 = _mm_setr_ps(g[row_at[0] + s + col[0] + 1], g[row_at[1] + s + col[1] + 1],
                                  g[row_at[2] + s + col[2] + 1], g[row_at[3] + s + col[3] + 1]);
    const __m256d hi = _mm256_cvtps_pd(MaxF(MaxF(a0, a1), MaxF(b0, b1)));
    const __m256d lo = _mm256_cvtps_pd(MinF(MinF(a0, a1), MinF(b0, b1)));
    const __m128 fin = _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_sub_ps(a0, a0), _mm_sub_ps(a1, a1)), _mm_sub_ps(b0, b0)),
                                  _mm_sub_ps(b1, b1));
    const int cell_ok = _mm256_movemask_pd(Le(Sub(hi, lo), K(m.max_span))) &
                        _mm_movemask_ps(_mm_cmpeq_ps(fin, _mm_setzero_ps())) & open;
    alive &= ~(open & ~cell_ok);  // a jump or an invalid sample: the scalar walk fails too
    const __m256d da0 = _mm256_cvtps_pd(a0), da1 = _mm256_cvtps_pd(a1);
    const __m256d g0 = Sub(Add(da0, Mul(fv, Sub(_mm256_cvtps_pd(b0), da0))), c_src);
    const __m256d g1 = Sub(Add(da1, Mul(fv, Sub(_mm256_cvtps_pd(b1), da1))), c_src);
    // A sign change (or g0 == 0): the root; g0 == g1 there: the scalar walk fails.
    const __m256d crossing = Or(_mm256_xor_pd(Gt(g0, zero), Gt(g1, zero)), Eq(g0, zero));
    const int here = _mm256_movemask_pd(crossing) & cell_ok & alive;
    alive &= ~(here & _mm256_movemask_pd(Eq(g0, g1)));
    const int root = here & alive;
    const __m256d root_lanes = Lanes(root);
    column = Pick(root_lanes, column, Add(i, Div(g0, Sub(g0, g1))));
    dg_du = Pick(root_lanes, dg_du, Sub(g1, g0));
    settled |= root;
    // The others step on, in the direction in which |g| falls at the first cell.
    if (n == 0) dir = Pick(_mm256_xor_pd(Gt(g0, zero), Gt(g1, g0)), K(-1.0), one);  // equal: -1
    i = Pick(Lanes(cell_ok & ~here), i, Add(i, dir));
  }
  alive &= settled;
  if (!alive) return;
  // RectRoot: w at the column, in range, its pixel and velocity, the slope from the grid cell.
  const __m256d w = Div(Mul(Mul(Sub(Add(column, K(m.grid_u0)), rs_u), sign), rs_z), fb);
  const __m256d ax = Load(l->a_x), ay = Load(l->a_y), az = Load(l->a_z);
  const __m256d qx = Add(ax, Mul(K(m.t[0]), w)), qy = Add(ay, Mul(K(m.t[1]), w)), qz = Add(az, Mul(K(m.t[2]), w));
  alive &= InRange(m, w, qx, qy, qz);
  __m256d pix_x, pix_y, vel_x, vel_y;
  alive &= PixelAndVelocity(m, ax, ay, az, w, &pix_x, &pix_y, &vel_x, &vel_y);
  if (!alive) return;
  const Cells cell = CellsAt(m, pix_x, pix_y, alive);  // CellAt
  alive = cell.ok;
  if (!alive) return;
  const __m256d slope = Div(Mul(Mul(dg_du, sign), fb), rs_z);
  Settle(m, alive, w, slope, pix_x, pix_y, cell, vel_x, vel_y, l);
}

}  // namespace

void WalkFourLanes(const WalkMaps& maps, WalkLanes* lanes) {
  if (maps.rect)
    RectWalkFourLanesAvx2(maps, lanes);
  else
    WalkFourLanesAvx2(maps, lanes);
}

void SetWalkLaneCheck(bool on) {
  g_check.store(on, std::memory_order_relaxed);
  g_checked.store(0, std::memory_order_relaxed);
  g_mismatched.store(0, std::memory_order_relaxed);
}
bool WalkLaneCheck() { return g_check.load(std::memory_order_relaxed); }
void CountWalkLaneCheck(bool same) {
  g_checked.fetch_add(1, std::memory_order_relaxed);
  if (!same) g_mismatched.fetch_add(1, std::memory_order_relaxed);
}
void CountWalkLaneMismatch() { g_mismatched.fetch_add(1, std::memory_order_relaxed); }
long WalkLanesChecked() { return g_checked.load(std::memory_order_relaxed); }
long WalkLaneMismatches() { return g_mismatched.load(std::memory_order_relaxed); }

}  // namespace ramtk::vision::detail
