#pragma once
// The crossing near a neighbour's match: the tangent line and its cells (Matcher::LocalSearch). Included by
// stereo_walk.cpp only (stereo_matcher.h).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stereo_matcher.h"

namespace ramtk::vision::detail {
namespace {  // internal to stereo_walk.cpp, the one file that includes it

// The crossing of the bilinear surface along the line pix + vel * s (s in units of w) nearest
// to s = 0 on the side where |f| falls, at most max_px pixels away. Within one cell the
// bilinear interpolant is quadratic in s, so each cell's crossing is solved in closed form and
// the cells are walked in order. False if the line leaves the image, meets a cell with an
// invalid corner or a wrap (span > max_span), or no crossing lies within reach.
inline bool Matcher::LineCrossing(const Vec2& pix, const Vec2& vel, double max_px, double* s_root, double* dfds) const {
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
inline bool Matcher::LocalSearch(double w0, Root* root) const {
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

}  // namespace
}  // namespace ramtk::vision::detail
