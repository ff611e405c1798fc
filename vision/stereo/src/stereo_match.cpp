// Stereo matching of equal absolute projector coordinate along epipolar curves (stereo_match.h):
// the two passes (right to left for the check, then left to right) and the result. The passes
// themselves: stereo_pass.h.
#include "ramtk/vision/stereo/stereo_match.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <mutex>
#include <sstream>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/vision/kernels/rank_select.h"
#include "ramtk/vision/stereo/detail/stereo_kernel_estimate.h"
#include "ramtk/vision/stereo/detail/stereo_rectified_grid.h"
#include "ramtk/vision/stereo/detail/stereo_search_list.h"
#include "ramtk/vision/stereo/detail/test_hooks.h"
#include "stereo_pass.h"

namespace ramtk::vision {
namespace {

using detail::Pass;
using detail::PassResult;
using detail::RowView;

void CheckSize(const CameraIntrinsics& cam, const DecodedCamera& d, const std::string& name, const std::string& path) {
  if (d.coordinate.cols != cam.width || d.coordinate.rows != cam.height)
    throw InputError({path, 0, "image_size"}, "the " + name + " calibration is " + std::to_string(cam.width) + "x" +
                                                  std::to_string(cam.height) + " but the " + name + " images are " +
                                                  std::to_string(d.coordinate.cols) + "x" +
                                                  std::to_string(d.coordinate.rows));
}

// One pass: from the left camera to the right one (`left_to_right`) or back; the rectified grid
// for the back pass with StereoMatchTestHooks::rectified_back_pass.
Pass MakePass(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
              double period, const StereoMatchOptions& options, const detail::StereoMatchTestHooks& hooks,
              const detail::RectifiedPair& rectified, bool left_to_right) {
  const Mat3 R = calibration.right_from_left.linear();
  const Vec3 T = calibration.right_from_left.translation();
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
}

// Largest jackknife σ of an estimated kernel variance k the terms are applied with: 0.01 px²
// plus 5 % of k (a variance error of 0.01 px² moves a centre on SLMaster's rig by ~0.5 µm along
// z; on rigs with small pixels the σ is larger, the estimate biased low, and the terms matter less).
constexpr double kMaxKernelSigmaPx2 = 0.01;
constexpr double kMaxKernelSigmaShare = 0.05;
// Smallest KernelVarianceEstimate::leverage applied: on small pixels the pairs' spread in
// ½·(q_left − q_right) is about its noise (SLMaster's rig: 3.7, its real capture 5.2, the
// small rigs 0.8–1.1), and the estimate there reads 0.01–0.05 px² for a box's 0.078.
constexpr double kMinKernelLeverage = 2.0;
constexpr double kMaxKernelVariancePx2 = 1.5;  // estimates are clamped to [0, this]

// The kernel variances of the points pass's terms: both stated, or estimated from the back
// pass's matches for the camera(s) that state none (StereoMatchOptions::kernel_estimate).
KernelVarianceEstimate ChooseKernel(const StereoCalibration& calibration, const DecodedCamera& left,
                                    const DecodedCamera& right, const PassResult& back, double period,
                                    const StereoMatchOptions& options) {
  const auto& lk = calibration.left.sampling_kernel;
  const auto& rk = calibration.right.sampling_kernel;
  KernelVarianceEstimate e;
  if (lk && rk) {
    e.status = "stated";
    e.left_px2 = lk->VariancePx2();
    e.right_px2 = rk->VariancePx2();
    return e;
  }
  if (options.kernel_estimate == StereoMatchOptions::KernelEstimate::kOff) return e;
  e = detail::EstimateKernelVariance(left, right, back.u, back.v, period,
                                     lk ? std::optional<double>(lk->VariancePx2()) : std::nullopt,
                                     rk ? std::optional<double>(rk->VariancePx2()) : std::nullopt);
  if (e.status != "estimated") return e;
  if (!(e.leverage >= kMinKernelLeverage)) {
    e.status = "too little leverage";
    return e;
  }
  if (!(e.sigma_px2 <= kMaxKernelSigmaPx2 + kMaxKernelSigmaShare * std::abs(e.variance_px2))) {
    e.status = "not significant";
    return e;
  }
  const double k = std::clamp(e.variance_px2, 0.0, kMaxKernelVariancePx2);
  e.status = "applied";
  e.applied = true;
  e.left_px2 = lk ? lk->VariancePx2() : k;
  e.right_px2 = rk ? rk->VariancePx2() : k;
  return e;
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
  if (kernel.status != "off") {
    s << "; sampling kernel " << kernel.status;
    if (std::isfinite(kernel.variance_px2))
      s << ", k = " << kernel.variance_px2 << " +- " << kernel.sigma_px2 << " px^2 over " << kernel.pixels << " px";
  }
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
                        double period, const StereoMatchOptions& options) {
  ThrowIfInvalid(options.Validate(), "StereoMatchOptions");
  const detail::StereoMatchTestHooks hooks = detail::CurrentStereoMatchTestHooks();
  CheckSize(calibration.left, left, "left", calibration.source_path);
  CheckSize(calibration.right, right, "right", calibration.source_path);
  if (!(period > 0)) throw InputError({"", 0, "period"}, "the fringe period must be > 0");
  const detail::RectifiedPair rectified =
      hooks.rectified_back_pass ? detail::MakeRectifiedPair(calibration) : detail::RectifiedPair{};

  StereoMatch result;
  StereoMatchSummary& sum = result.summary;
  PassResult back;
  const bool lr = options.lr_tolerance_px > 0;
  if (lr) {
    Pass rl = MakePass(calibration, left, right, period, options, hooks, rectified, false);
    rl.lr_tolerance = 0;
    sum.back_pass = rl.rect ? "rectified" : "curve";
    if (!RunPass(rl, &back, options, "match right->left")) {
      sum.termination = Termination::kCancelled;
      sum.message = "cancelled";
      return result;
    }
  }
  Pass lrp = MakePass(calibration, left, right, period, options, hooks, rectified, true);
  lrp.points = true;
  sum.kernel = ChooseKernel(calibration, left, right, back, period, options);
  if (sum.kernel.status == "stated" || sum.kernel.applied) {
    lrp.kernel_terms = true;
    lrp.kernel_var_src = sum.kernel.left_px2;
    lrp.kernel_var_dst = sum.kernel.right_px2;
  }
  lrp.noise_term = options.noise_bias_term;
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
