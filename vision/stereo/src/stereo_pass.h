#pragma once
// One direction of the stereo match (stereo_match.h): the maps and tables a pass searches (Pass),
// its outputs (PassResult) and the functions that build and run it. Private to vision/stereo.

#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/kernels/fast_round.h"
#include "ramtk/vision/stereo/detail/stereo_rectified_grid.h"
#include "ramtk/vision/stereo/stereo_match.h"

namespace ramtk::vision::detail {

inline double Sq(double x) { return x * x; }

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
  // Both cameras state their sampling kernel (CameraIntrinsics::sampling_kernel): each match of
  // the points pass is moved by the kernel and interpolation terms (stereo_kernel_terms.h), with
  // the kernels' per-axis variances, px².
  bool kernel_terms = false;
  double kernel_var_src = 0, kernel_var_dst = 0;
  // Each match of the points pass is moved by the noise's second-order term (ApplyNoiseTerm,
  // stereo_kernel_terms.h): StereoMatchOptions::noise_bias_term.
  bool noise_term = false;
  bool SecondOrderTerms() const { return kernel_terms || noise_term; }
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

struct PassResult {
  cv::Mat u, v, sigma;               // sigma: Pass::sigma_map only
  cv::Mat depth, point_sigma, x, y;  // Pass::points only
  std::atomic<long> noisy{0}, no_match{0}, lr{0}, unreachable{0}, full{0}, matched{0}, valid{0};
  // Without Pass::sigma_map: the matched pixels' sigmas, one part per block (for their median).
  std::mutex sigma_mutex;
  std::vector<std::vector<float>> sigma_parts;
};

// Pass::box_*: the destination image's bounding box in ideal normalised coordinates, from its
// border pixels, 2 px margin (stereo_curve_tables.cpp).
void SetIdealBox(Pass* pass);
// The tables of the search along the distorted epipolar curve (stereo_curve_tables.cpp).
void BuildCurveTables(const StereoMatchOptions& options, const cv::Mat& dst_coord, Pass* pass);
// Pass::reach: the source pixels the left-right check can accept (stereo_back_reach.cpp).
cv::Mat BackReach(const Pass& p, int src_cols, int src_rows);
// Runs one pass over every source row; false if cancelled (stereo_walk.cpp).
bool RunPass(const Pass& p, PassResult* out, const StereoMatchOptions& options, const std::string& stage);

}  // namespace ramtk::vision::detail
