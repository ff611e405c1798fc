#pragma once
// Whether a crossing is the same surface point: modulation ratio and left-right check. Included by stereo_walk.cpp only
// (stereo_matcher.h).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {  // internal to stereo_walk.cpp, the one file that includes it

// Same surface point: the modulations agree (a matte surface sends the same radiance to both
// cameras), and the destination position's own match back in the source image lands on the
// source pixel (left-right consistency).
inline bool Matcher::Accept(const Root& r, double b_src, double su, double sv) const {
  const double ratio = std::max(1e-6, r.at.modulation) / std::max(1e-6, b_src);
  if (ratio > p.max_modulation_ratio || ratio * p.max_modulation_ratio < 1.0) return false;
  return Consistent(r.at.pix, su, sv);
}

inline bool Matcher::Consistent(const Vec2& dst_pix, double su, double sv) const {
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
  const bool all = ((fu4[0] - fu4[0]) + (fu4[1] - fu4[1]) + (fu4[2] - fu4[2]) + (fu4[3] - fu4[3]) + (fv4[0] - fv4[0]) +
                    (fv4[1] - fv4[1]) + (fv4[2] - fv4[2]) + (fv4[3] - fv4[3])) == 0.0f;
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

}  // namespace
}  // namespace ramtk::vision::detail
