#pragma once
// The sampling kernel's and the bilinear interpolant's second-order terms at a crossing
// (Pass::kernel_terms). Included by stereo_walk.cpp only (after stereo_matcher.h).
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
// c_uu and c_vv are the maps' second differences: at the left pixel, and interpolated over the
// crossing cell's four corners on the right.

#include <cmath>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {

// Second differences of a coordinate map at (x, y) along u and v; false if a neighbour lies
// outside the map or is not finite.
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

// Largest shift of a crossing by the kernel terms, destination px: the terms are ~0.01 px; a
// larger one comes from second differences across an edge or an unwrap error, and is not applied.
constexpr double kMaxKernelShiftPx = 0.1;

// Moves `root` (the crossing of source pixel (x, y)) to where the kernel-free coordinates cross.
// False (root unchanged) where a second difference is unavailable or the shift is implausible.
inline bool ApplyKernelTerms(const Pass& p, const Matcher& m, int x, int y, Matcher::Root* root) {
  double luu = 0, lvv = 0;
  if (!SecondDifferences(p.src_coord, x, y, &luu, &lvv)) return false;
  const int u0 = root->at.u0, v0 = root->at.v0;
  const double fu = root->at.pix.x() - u0, fv = root->at.pix.y() - v0;
  double ruu = 0, rvv = 0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      double duu = 0, dvv = 0;
      if (!SecondDifferences(p.dst_coord, u0 + i, v0 + j, &duu, &dvv)) return false;
      const double weight = (i ? fu : 1 - fu) * (j ? fv : 1 - fv);
      ruu += weight * duu;
      rvv += weight * dvv;
    }
  }
  const double bias_dst = 0.5 * (fu * (1 - fu) * ruu + fv * (1 - fv) * rvv) + 0.5 * p.kernel_var_dst * (ruu + rvv);
  const double bias_src = 0.5 * p.kernel_var_src * (luu + lvv);
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

}  // namespace
}  // namespace ramtk::vision::detail
