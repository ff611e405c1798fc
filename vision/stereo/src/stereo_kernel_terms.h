#pragma once
// The second-order terms at a crossing: the sampling kernel's and the bilinear interpolant's
// (Pass::kernel_terms) and the noise's (Pass::noise_term, ApplyNoiseTerm below), applied by
// ApplySecondOrderTerms. Included by stereo_walk.cpp only (after stereo_matcher.h).
//
// A camera whose pixel samples the coordinate c through a kernel of per-axis variance k
// (SamplingKernel::VariancePx2: box fill_factor²/12 plus PSF σ²) reads, at second order,
//     c + ½·k·(c_uu + c_vv)                                             (the kernel term)
// (the phase of the kernel-weighted fringe ∫K(s)·e^{i(φ0 + g·s + ½h·s²)} ds is φ0 + ½·k·h for a
// symmetric kernel). Between four such samples the bilinear value at cell fractions (t_u, t_v) is
//     c + ½·t_u(1 − t_u)·c_uu + ½·t_v(1 − t_v)·c_vv + ½·k_dst·(c_uu + c_vv)   (interpolation + kernel)
// (the chord of a convex function lies above it). The matcher solves bilinear = left value; the
// true crossing solves bilinear − bias_dst = c_src − bias_src, one Newton step along the curve:
//     w' = w + (bias_dst − bias_src) / (df/dw).
// The kernel also weights the fringe by its modulation B: the phase moves to the kernel's
// B-weighted centroid, + k·(c_u·B_u + c_v·B_v)/B at first order (the shading term), on both maps.
// The derivatives are the maps' central and second differences (at the left pixel; interpolated
// over the crossing cell's corners on the right).

#include <cmath>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {

// Second differences of a coordinate map at (x, y) along u and v; false if a neighbour lies
// outside the map or is not finite. (The matches' bias follows these three-sample differences:
// a parabola fitted over 5 samples and 3 lines removed half of it on a point-sampled render.)
inline bool SecondDifferences(const cv::Mat& map, int x, int y, double* duu, double* dvv) {
  if (x < 1 || y < 1 || x + 1 >= map.cols || y + 1 >= map.rows) return false;
  const float* up = map.ptr<float>(y - 1);
  const float* row = map.ptr<float>(y);
  const float* down = map.ptr<float>(y + 1);
  const double c = row[x];
  *duu = static_cast<double>(row[x - 1]) - 2.0 * c + row[x + 1];
  *dvv = static_cast<double>(up[x]) - 2.0 * c + down[x];
  return std::isfinite(*duu) && std::isfinite(*dvv);
}

// The shading term of a kernel of variance k at (x, y): k·(c_u·B_u + c_v·B_v)/B (the modulation B
// weights the kernel: the fringe's phase moves to its B-weighted centroid), central differences of
// the coordinate c and the modulation B. False where a neighbour is missing.
inline bool ShadingTerm(const cv::Mat& coord, const cv::Mat& modulation, int x, int y, double k, double* term) {
  *term = 0;
  if (k == 0) return true;
  if (x < 1 || y < 1 || x + 1 >= coord.cols || y + 1 >= coord.rows) return false;
  auto at = [](const cv::Mat& m, int u, int v) { return static_cast<double>(m.ptr<float>(v)[u]); };
  const double cu = 0.5 * (at(coord, x + 1, y) - at(coord, x - 1, y));
  const double cv = 0.5 * (at(coord, x, y + 1) - at(coord, x, y - 1));
  const double bu = 0.5 * (at(modulation, x + 1, y) - at(modulation, x - 1, y));
  const double bv = 0.5 * (at(modulation, x, y + 1) - at(modulation, x, y - 1));
  const double b = at(modulation, x, y);
  *term = k * (cu * bu + cv * bv) / b;
  return b > 0 && std::isfinite(*term);
}

// Largest shift of a crossing by the kernel terms, destination px: the terms are ~0.01 px; a
// larger one comes from differences across an edge or an unwrap error, and is not applied.
constexpr double kMaxKernelShiftPx = 0.1;
// Smallest shift the noise term applies, destination px.
constexpr double kMinNoiseShiftPx = 1e-5;

// The destination map's second differences (c_uu, c_vv, c_uv) interpolated over the crossing
// cell's four corners, read once for both terms; ok false where a neighbour lies outside the map
// or is not finite.
struct CellCurvature {
  double uu = 0, vv = 0, uv = 0;
  bool ok = false;
};

inline CellCurvature CrossingCellCurvature(const Pass& p, const Matcher::Root& root) {
  CellCurvature k;
  const int u0 = root.at.u0, v0 = root.at.v0;
  if (u0 < 1 || v0 < 1 || u0 + 2 >= p.dst_coord.cols || v0 + 2 >= p.dst_coord.rows) return k;
  const double fu = root.at.pix.x() - u0, fv = root.at.pix.y() - v0;
  double c[4][4];  // rows v0 − 1 … v0 + 2, columns u0 − 1 … u0 + 2
  for (int j = 0; j < 4; ++j) {
    const float* row = p.dst_coord.ptr<float>(v0 - 1 + j) + (u0 - 1);
    for (int i = 0; i < 4; ++i) c[j][i] = row[i];
  }
  for (int j = 1; j < 3; ++j)
    for (int i = 1; i < 3; ++i) {
      const double weight = (i == 2 ? fu : 1 - fu) * (j == 2 ? fv : 1 - fv);
      k.uu += weight * (c[j][i - 1] - 2 * c[j][i] + c[j][i + 1]);
      k.vv += weight * (c[j - 1][i] - 2 * c[j][i] + c[j + 1][i]);
      k.uv += weight * 0.25 * (c[j + 1][i + 1] - c[j + 1][i - 1] - c[j - 1][i + 1] + c[j - 1][i - 1]);
    }
  k.ok = std::isfinite(k.uu) && std::isfinite(k.vv) && std::isfinite(k.uv);
  return k;
}

// Moves `root` (the crossing of source pixel (x, y)) to where the kernel-free coordinates cross.
// The destination's terms are interpolated over the crossing cell's four corners. False (root unchanged) where a second difference
// is unavailable or the shift is implausible.
inline bool ApplyKernelTerms(const Pass& p, const Matcher& m, int x, int y, const CellCurvature& k,
                             Matcher::Root* root) {
  double luu = 0, lvv = 0;
  if (!k.ok || !SecondDifferences(p.src_coord, x, y, &luu, &lvv)) return false;
  const int u0 = root->at.u0, v0 = root->at.v0;
  const double fu = root->at.pix.x() - u0, fv = root->at.pix.y() - v0;
  const double ruu = k.uu, rvv = k.vv;
  double rsh = 0, lsh = 0;
  if (!ShadingTerm(p.src_coord, p.src_modulation, x, y, p.kernel_var_src, &lsh)) return false;
  if (p.kernel_var_dst != 0) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        double sh = 0;
        if (!ShadingTerm(p.dst_coord, p.dst_modulation, u0 + i, v0 + j, p.kernel_var_dst, &sh)) return false;
        rsh += (i ? fu : 1 - fu) * (j ? fv : 1 - fv) * sh;
      }
    }
  }
  const double bias_dst = 0.5 * (fu * (1 - fu) * ruu + fv * (1 - fv) * rvv) + 0.5 * p.kernel_var_dst * (ruu + rvv) + rsh;
  const double bias_src = 0.5 * p.kernel_var_src * (luu + lvv) + lsh;
  if (!(root->slope != 0)) return false;
  const double dw = (bias_dst - bias_src) / root->slope;
  Vec2 pix, vel;
  if (!m.PixelAndVelocity(root->w + dw, &pix, &vel)) return false;
  if (!(std::abs(dw) * vel.norm() < kMaxKernelShiftPx)) return false;
  root->w += dw;
  root->at.pix = pix;
  root->vel = vel;
  return true;
}

// The noise's second-order term. The matcher solves h(w) = c_src for w, h(w) = c_dst(pix(w))
// the destination coordinate along the epipolar curve; with zero-mean noise of variance
// s² = σ_src² + var(c_dst) on the two sides, the root's expectation moves by
//     E[δw] = −½·h''·s² / h'³        (the inverse function's curvature, (h⁻¹)'' = −h''/h'³),
// so the root is moved back by +½·h''·s²/h'³, with
//     h'' = velᵀ·H·vel + ∇c·acc,   acc = −2·(T_z / q_z)·vel
// H the destination map's second differences (c_uu, c_uv, c_vv) interpolated over the crossing
// cell's corners,
// vel = d pix/dw, and acc the curve's second derivative: the ideal point (a + T·w)_xy / (a + T·w)_z
// is a Möbius map of w, whose second derivative is −2·T_z/q_z times its first (the lens's own
// curvature over the step is left out), so ∇c·acc = −2·(T_z/q_z)·h'. The pixel moves along vel.
// Where the maps bend (a ball's limb seen at a grazing angle) and the noise is large this moves
// the points by up to a few µm, always the same way: the scatter's mean, not its spread. False
// (root unchanged) where a neighbour is missing or the shift is implausible.
inline bool ApplyNoiseTerm(const Pass& p, const Matcher& m, int x, int y, const CellCurvature& k,
                           Matcher::Root* root) {
  const double h1 = root->slope;
  if (!k.ok || p.src_sigma.empty() || !(h1 != 0)) return false;
  const double s_src = p.src_sigma.ptr<float>(y)[x];
  const double s2 = s_src * s_src + root->at.var;
  if (!(s2 > 0) || !std::isfinite(s2)) return false;
  const double cuu = k.uu, cvv = k.vv, cuv = k.uv;
  Vec2 vel = root->vel;
  if (!std::isfinite(vel.x())) {
    Vec2 pix;
    if (!m.PixelAndVelocity(root->w, &pix, &vel)) return false;
  }
  const double qz = m.a.z() + p.T.z() * root->w;
  const double h2 =
      vel.x() * vel.x() * cuu + 2 * vel.x() * vel.y() * cuv + vel.y() * vel.y() * cvv - 2 * (p.T.z() / qz) * h1;
  const double dw = 0.5 * h2 * s2 / (h1 * h1 * h1);
  const double shift_px = std::abs(dw) * vel.norm();
  // Below kMinNoiseShiftPx the match stays (and keeps the walk's own outputs): a systematic
  // shift that small is < 0.01 µm at 1 mm of depth per pixel.
  if (!std::isfinite(dw) || !(shift_px < kMaxKernelShiftPx) || shift_px < kMinNoiseShiftPx) return false;
  root->w += dw;
  root->at.pix += vel * dw;
  root->vel = vel;
  return true;
}

// The second-order terms the pass applies (Pass::kernel_terms, Pass::noise_term), in that order.
inline void ApplySecondOrderTerms(const Pass& p, const Matcher& m, int x, int y, Matcher::Root* root) {
  const CellCurvature k = CrossingCellCurvature(p, *root);  // at the search's root, for both terms
  if (p.kernel_terms) ApplyKernelTerms(p, m, x, y, k, root);
  if (p.noise_term) ApplyNoiseTerm(p, m, x, y, k, root);
}

}  // namespace
}  // namespace ramtk::vision::detail
