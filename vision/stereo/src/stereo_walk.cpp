// The walk of a pass over its source rows (RunPass, stereo_pass.h): each pixel seeded from its
// neighbours' matches, settled by the AVX2 lanes where they can, else searched by the Matcher.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/rank_select.h"
#include "ramtk/vision/stereo/detail/stereo_search_list.h"
#include "ramtk/vision/stereo/detail/stereo_walk_lanes.h"
#include "ramtk/vision/stereo/detail/undistort_chains.h"
#include "stereo_consistency.h"
#include "stereo_curve_search.h"
#include "stereo_kernel_terms.h"
#include "stereo_local_search.h"
#include "stereo_matcher.h"
#include "stereo_rect_search.h"

namespace ramtk::vision::detail {
namespace {

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

// Writes a matched root's outputs at the row's cursor (root.vel known).
void WriteOutputs(const Pass& p, RowWalk* r, const Matcher::Root& root, const Vec2& ideal) {
  const int x = r->x;
  const PixelOutputs o = Outputs(r->srow[x], root.at.var, root.slope, root.vel, root.w, ideal);
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

// The root lane k of `in` settled.
Matcher::Root SettledRoot(const detail::WalkLanes& in, int k) {
  Matcher::Root root;
  root.w = in.w[k];
  root.slope = in.slope[k];
  root.at.ok = true;
  root.at.pix = Vec2(in.pix_x[k], in.pix_y[k]);
  root.at.u0 = in.u0[k], root.at.v0 = in.v0[k];
  root.at.var = in.var[k];
  root.at.modulation = in.modulation[k];
  root.vel = Vec2(in.vel_x[k], in.vel_y[k]);
  return root;
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
  if (p.SecondOrderTerms()) ApplySecondOrderTerms(p, m, x, y, &root);  // the outputs only: the seeds stay the search's
  if (!std::isfinite(root.vel.x())) {
    Vec2 unused;
    m.PixelAndVelocity(root.w, &unused, &root.vel);
  }
  WriteOutputs(p, r, root, ideal);
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
void EmitSettled(const Pass& p, Matcher& m, RowWalk* r, const detail::WalkLanes& in, int k) {
  const int x = r->x;
  r->last_x = x;
  const int entry = r->next_ray++;
  ++r->matched;
  r->w_prev = in.w[k];
  r->w_last = in.w[k];
  r->w_row[x] = in.w[k];
  if (p.SecondOrderTerms()) {
    Matcher::Root root = SettledRoot(in, k);
    m.a = Vec3(r->chain->a_x[entry], r->chain->a_y[entry], r->chain->a_z[entry]);
    m.c_src = r->crow[x];
    if (p.kernel_terms) {
      // The lanes' root through the second-order terms, its outputs as SearchPixel forms them.
      ApplySecondOrderTerms(p, m, x, r->y, &root);
      WriteOutputs(p, r, root, Vec2(r->chain->ideal_x[entry], r->chain->ideal_y[entry]));
      return;
    }
    // The noise term alone: where it moves the root, its outputs as SearchPixel forms them; where
    // it does not, the lanes' own.
    if (ApplyNoiseTerm(p, m, x, r->y, CrossingCellCurvature(p, root), &root)) {
      WriteOutputs(p, r, root, Vec2(r->chain->ideal_x[entry], r->chain->ideal_y[entry]));
      return;
    }
  }
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
  const Matcher::Root root = SettledRoot(in, k);
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
  // With the second-order terms EmitSettled writes SearchPixel's outputs itself, not the lanes'.
  for (int i = 0; i < 7 && !p.SecondOrderTerms(); ++i)
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
          EmitSettled(p, m, &r, in, k);
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

}  // namespace

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
        for (std::vector<float>& buf : sigma_buf) buf.resize(W);
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
        chains[y - yb] = {row_xs,
                          count,
                          y,
                          rays[0].data() + at,
                          rays[1].data() + at,
                          rays[2].data() + at,
                          rays[3].data() + at,
                          rays[4].data() + at,
                          rays[5].data() + at,
                          rays[6].data() + at,
                          rays[7].data() + at};
      }
      detail::UndistortChains(*p.src, chains, ye - yb, &turn);
      WalkRows(p, out, yb, ye, lanes, maps, chains, counts, w_buf, sigma_buf);
    });
    if (options.progress && !options.progress({stage, static_cast<std::size_t>(r1), static_cast<std::size_t>(H)}))
      return false;
  }
  return true;
}

}  // namespace ramtk::vision::detail
