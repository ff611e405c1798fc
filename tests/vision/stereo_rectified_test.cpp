// The rectified back pass (detail::StereoMatchTestHooks::rectified_back_pass).
// - The rectified pair's geometry against projection: a scene point projected into both distorted
//   images and taken back through the rectification lands on the same row in both, at the
//   disparity f B / Z of its depth (closed form).
// - The resampled grid against a linear coordinate map, which bilinear interpolation reproduces
//   exactly: each sample holds the map's value at the distorted pixel of its rectified pixel.
// - The match with the rectified back pass against the match with the curve back pass, on the
//   real SLMaster capture (data nobody here generated; skipped if absent) and on a simulated set:
//   the same points where both accept, and back matches within a fraction of the left-right
//   check's tolerance. The points' truth is checked with either back pass in
//   ScanMatch.DepthMatchesTheSimulatorTruthWithinThePredictedSigma.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/stereo/detail/stereo_rectified_grid.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

// A verging rig with a vertical offset and distortion: the rectification must turn both cameras.
StereoCalibration VergingRig() {
  StereoCalibration c;
  for (CameraIntrinsics* k : {&c.left, &c.right}) {
    k->fx = 2400, k->fy = 2396, k->cx = 1023.5, k->cy = 767.5, k->width = 2048, k->height = 1536;
    k->distortion.k1 = -0.12, k->distortion.k2 = 0.08, k->distortion.p1 = 3e-4, k->distortion.p2 = -2e-4;
  }
  c.right.fx = 2410, c.right.cx = 1030;
  const Eigen::AngleAxisd turn(0.35, Vec3(0.05, 1, 0.03).normalized());
  c.right_from_left.linear() = turn.toRotationMatrix();
  c.right_from_left.translation() = Vec3(-240, 6, 45);
  return c;
}

TEST(StereoRectified, RowsOfTheRectifiedPairAreEpipolarLines) {
  const StereoCalibration c = VergingRig();
  const detail::RectifiedPair pair = detail::MakeRectifiedPair(c);
  // Rotations: orthonormal, right-handed.
  for (const Mat3& r : {pair.rect_from_left, pair.rect_from_right}) {
    EXPECT_LT((r * r.transpose() - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
  }
  const Vec3 right_centre_in_left = -c.right_from_left.linear().transpose() * c.right_from_left.translation();
  EXPECT_NEAR(pair.baseline_mm, right_centre_in_left.norm(), 1e-12);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-150, 150), z(500, 1200);
  int seen = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 x_in_left(xy(rng), xy(rng), z(rng));
    const Vec3 x_in_right = c.right_from_left * x_in_left;
    const Vec2 pl = ProjectPoint(c.left, x_in_left), pr = ProjectPoint(c.right, x_in_right);
    if (pl.x() < 0 || pl.y() < 0 || pl.x() > 2047 || pl.y() > 1535 || pr.x() < 0 || pr.y() < 0 || pr.x() > 2047 ||
        pr.y() > 1535)
      continue;
    ++seen;
    // Back from the distorted pixels through the rectification, as the match does.
    const Vec3 rl = pair.rect_from_left * PixelRay(c.left, pl), rr = pair.rect_from_right * PixelRay(c.right, pr);
    const double ul = pair.f * rl.x() / rl.z(), vl = pair.f * rl.y() / rl.z();
    const double ur = pair.f * rr.x() / rr.z(), vr = pair.f * rr.y() / rr.z();
    const double z_rect = (pair.rect_from_left * x_in_left).z();
    // Undistortion converges to 1e-15 in normalised coordinates: ~1e-11 px here.
    EXPECT_NEAR(vl, vr, 1e-8);
    EXPECT_NEAR(ul - ur, pair.f * pair.baseline_mm / z_rect, 1e-8);
    EXPECT_GT(ul - ur, 0);
  }
  EXPECT_GT(seen, 500);
}

// The cells (index row * cols + column of the top-left pixel) whose four corners are finite.
std::vector<uchar> FiniteCells(const cv::Mat& coord) {
  std::vector<uchar> cell_ok(coord.total(), 0);
  for (int y = 0; y + 1 < coord.rows; ++y)
    for (int x = 0; x + 1 < coord.cols; ++x)
      cell_ok[static_cast<std::size_t>(y) * coord.cols + x] =
          std::isfinite(coord.at<float>(y, x) + coord.at<float>(y, x + 1) + coord.at<float>(y + 1, x) +
                        coord.at<float>(y + 1, x + 1));
  return cell_ok;
}

TEST(StereoRectified, ResampledGridReadsTheMapAtTheRectifiedPixel) {
  const StereoCalibration c = VergingRig();
  const detail::RectifiedPair pair = detail::MakeRectifiedPair(c);
  const CameraIntrinsics& cam = c.right;
  // A linear coordinate map (bilinear interpolation is exact on it), with a hole.
  cv::Mat coord(cam.height, cam.width, CV_32F);
  for (int y = 0; y < coord.rows; ++y)
    for (int x = 0; x < coord.cols; ++x) coord.at<float>(y, x) = static_cast<float>(0.25 * x + 0.05 * y + 10);
  coord(cv::Rect(900, 700, 40, 30)).setTo(std::numeric_limits<float>::quiet_NaN());
  const std::vector<uchar> cell_ok = FiniteCells(coord);
  const detail::RectifiedGrid grid =
      detail::ResampleOnRectifiedGrid(cam, pair.rect_from_right, pair.f, coord, cell_ok, 16.0 * coord.total());
  ASSERT_FALSE(grid.coord.empty());
  std::mt19937 rng(3);
  int valid = 0, invalid = 0;
  for (int k = 0; k < 20000; ++k) {
    const int i = std::uniform_int_distribution<int>(0, grid.coord.cols - 1)(rng);
    const int j = std::uniform_int_distribution<int>(0, grid.coord.rows - 1)(rng);
    // The rectified pixel's ray, projected into the distorted image (ProjectPoint, not the grid's code).
    const Vec3 ray = pair.rect_from_right.transpose() * Vec3((grid.u0 + i) / pair.f, (grid.v0 + j) / pair.f, 1.0);
    const Vec2 pix = ProjectPoint(cam, ray);
    const float sample = grid.coord.at<float>(j, i);
    const bool inside = pix.x() >= 0 && pix.y() >= 0 && pix.x() < cam.width - 1 && pix.y() < cam.height - 1;
    const bool in_hole = pix.x() > 898.5 && pix.x() < 940.5 && pix.y() > 698.5 && pix.y() < 730.5;
    if (inside && !in_hole) {
      ASSERT_TRUE(std::isfinite(sample)) << i << "," << j;
      // Float storage of a value ~500: 3e-5; ProjectPoint against the grid's own projection: ~1e-12.
      EXPECT_NEAR(sample, 0.25 * pix.x() + 0.05 * pix.y() + 10, 1e-4);
      ++valid;
    } else if (!inside || (pix.x() > 900 && pix.x() < 938 && pix.y() > 700 && pix.y() < 728)) {
      EXPECT_TRUE(std::isnan(sample)) << i << "," << j;
      ++invalid;
    }
  }
  EXPECT_GT(valid, 10000);
  EXPECT_GT(invalid, 100);
}

// The grid's pixel positions on AVX2 lanes: the same grid bit for bit as the scalar loop (the
// map's values and NaNs, the row and block bounds), on a non-linear map with a hole.
TEST(StereoRectified, GridOnLanesIsTheScalarGridBitForBit) {
  if (!detail::Avx2Kernels()) GTEST_SKIP() << "no AVX2 on this CPU (or RAMTK_AVX2=0)";
  const StereoCalibration c = VergingRig();
  const detail::RectifiedPair pair = detail::MakeRectifiedPair(c);
  const CameraIntrinsics& cam = c.right;
  cv::Mat coord(cam.height, cam.width, CV_32F);
  for (int y = 0; y < coord.rows; ++y)
    for (int x = 0; x < coord.cols; ++x)
      coord.at<float>(y, x) = static_cast<float>(0.25 * x + 0.05 * y + 3 * std::sin(x / 37.0) * std::cos(y / 23.0));
  coord(cv::Rect(900, 700, 40, 30)).setTo(std::numeric_limits<float>::quiet_NaN());
  const std::vector<uchar> cell_ok = FiniteCells(coord);
  detail::SetAvx2Kernels(false);
  const detail::RectifiedGrid scalar =
      detail::ResampleOnRectifiedGrid(cam, pair.rect_from_right, pair.f, coord, cell_ok, 16.0 * coord.total());
  detail::SetAvx2Kernels(true);
  const detail::RectifiedGrid lanes =
      detail::ResampleOnRectifiedGrid(cam, pair.rect_from_right, pair.f, coord, cell_ok, 16.0 * coord.total());
  ASSERT_FALSE(scalar.coord.empty());
  ASSERT_EQ(lanes.coord.size(), scalar.coord.size());
  EXPECT_EQ(lanes.u0, scalar.u0);
  EXPECT_EQ(lanes.v0, scalar.v0);
  for (int j = 0; j < scalar.coord.rows; ++j)
    ASSERT_EQ(std::memcmp(lanes.coord.ptr(j), scalar.coord.ptr(j), scalar.coord.cols * sizeof(float)), 0)
        << "row " << j;
  EXPECT_EQ(std::memcmp(lanes.block_min.data(), scalar.block_min.data(), scalar.block_min.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(lanes.row_max.data(), scalar.row_max.data(), scalar.row_max.size() * sizeof(float)), 0);
}

// A rig without a usable baseline gives no grid (the match then keeps the curve search), and
// never an integer overflow from NaN or infinite bounds.
TEST(StereoRectified, NoGridForARigWithoutAUsableBaseline) {
  StereoCalibration c = VergingRig();
  cv::Mat coord(c.right.height, c.right.width, CV_32F, cv::Scalar(100.0f));
  const std::vector<uchar> cell_ok(coord.total(), 1);
  c.right_from_left = Isometry3::Identity();  // one centre
  detail::RectifiedPair pair = detail::MakeRectifiedPair(c);
  EXPECT_TRUE(
      detail::ResampleOnRectifiedGrid(c.right, pair.rect_from_right, pair.f, coord, cell_ok, 1e9).coord.empty());
  c.right_from_left.translation() = Vec3(0, 0, -100);  // one camera behind the other, same axis
  pair = detail::MakeRectifiedPair(c);
  EXPECT_TRUE(
      detail::ResampleOnRectifiedGrid(c.right, pair.rect_from_right, pair.f, coord, cell_ok, 1e9).coord.empty());
}

// Same bytes, not merely close values.
bool SameFloat(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Agreement {
  long curve = 0, rectified = 0, both = 0;
  long different = 0;  // matched by both, at another point (another walk seed after a skipped pixel)
  long back_curve = 0, back_rectified = 0;  // right pixels matched back into the left image
  long back_inside = 0, back_apart = 0;     // inside surfaces; of those, at another crossing (> 1 px apart)
  // RMS distance of the two back matches inside surfaces at the same crossing, px and in their sigmas.
  double back_rms_px = 0, back_rms_sigma = 0;
};

// The match with the back pass along the curves and along rectified rows: the points (the
// left-to-right pass's own: depth, sigma and right pixel) and the back matches.
Agreement Compare(const StereoCalibration& calib, const DecodedCamera& l, const DecodedCamera& r, double period) {
  detail::StereoMatchTestHooks hooks;
  hooks.keep_back_matches = true;
  hooks.rectified_back_pass = false;
  // The back passes compared, not the kernel terms: an estimate from each pass's own matches
  // differs a little and moves every point by its terms.
  StereoMatchOptions o;
  o.kernel_estimate = StereoMatchOptions::KernelEstimate::kOff;
  const StereoMatch curve = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  hooks.rectified_back_pass = true;
  const StereoMatch rect = testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, l, r, period, o); });
  std::cout << "curve back pass: " << curve.summary.BriefReport()
            << "\nrectified back pass: " << rect.summary.BriefReport() << "\n";
  EXPECT_EQ(curve.summary.back_pass, "curve");
  EXPECT_EQ(rect.summary.back_pass, "rectified");
  Agreement a;
  a.curve = curve.summary.matched;
  a.rectified = rect.summary.matched;
  for (int y = 0; y < curve.depth_mm.rows; ++y)
    for (int x = 0; x < curve.depth_mm.cols; ++x) {
      if (!std::isfinite(curve.depth_mm.at<float>(y, x)) || !std::isfinite(rect.depth_mm.at<float>(y, x))) continue;
      ++a.both;
      a.different += !(SameFloat(curve.depth_mm.at<float>(y, x), rect.depth_mm.at<float>(y, x)) &&
                       SameFloat(curve.point_sigma_mm.at<float>(y, x), rect.point_sigma_mm.at<float>(y, x)) &&
                       SameFloat(curve.right_u.at<float>(y, x), rect.right_u.at<float>(y, x)) &&
                       SameFloat(curve.right_v.at<float>(y, x), rect.right_v.at<float>(y, x)));
    }
  // The back matches themselves, inside the surfaces (every right pixel within 3 px matched back
  // by both passes).
  for (int y = 0; y < curve.back_u.rows; ++y)
    for (int x = 0; x < curve.back_u.cols; ++x) {
      a.back_curve += std::isfinite(curve.back_u.at<float>(y, x));
      a.back_rectified += std::isfinite(rect.back_u.at<float>(y, x));
      bool inside = y >= 3 && x >= 3 && y + 3 < curve.back_u.rows && x + 3 < curve.back_u.cols;
      for (int dy = -3; dy <= 3 && inside; ++dy)
        for (int dx = -3; dx <= 3 && inside; ++dx)
          inside = std::isfinite(curve.back_u.at<float>(y + dy, x + dx)) &&
                   std::isfinite(rect.back_u.at<float>(y + dy, x + dx));
      if (!inside) continue;
      ++a.back_inside;
      const double d = std::hypot(rect.back_u.at<float>(y, x) - curve.back_u.at<float>(y, x),
                                  rect.back_v.at<float>(y, x) - curve.back_v.at<float>(y, x));
      if (d > 1.0) {
        ++a.back_apart;
        continue;
      }
      const double n = d / curve.back_sigma_px.at<float>(y, x);
      a.back_rms_sigma += n * n;
      a.back_rms_px += d * d;
    }
  // The same crossing: closer than 1 px (the rest, in the RMS below, would dominate it).
  a.back_rms_sigma = std::sqrt(a.back_rms_sigma / std::max<long>(a.back_inside - a.back_apart, 1));
  a.back_rms_px = std::sqrt(a.back_rms_px / std::max<long>(a.back_inside - a.back_apart, 1));
  std::cout << "points: both " << a.both << ", " << a.different << " at another point; back matches: curve "
            << a.back_curve << ", rectified " << a.back_rectified << ", inside surfaces " << a.back_inside << " (RMS "
            << a.back_rms_px << " px = " << a.back_rms_sigma << " sigma apart at the same crossing, " << a.back_apart
            << " > 1 px)\n";
  return a;
}

// Bounds.
// - Points: the left-to-right pass is the same code; only its left-right check reads other back
//   matches. A pixel the check now skips or rejects resets the walk's seed of the pixels after
//   it, which can then reach another crossing where a curve crosses the coordinate twice (near
//   edges): measured 0.08 % of the pixels both matched on SLMaster, 0.28 % on the noisier
//   simulated set; 1 % bounds them (as StereoWalk's), a regression moves far more. Counts: the
//   check differs at edges only (~1 %).
// - Back matches inside a surface, at the same crossing: the grid's crossing against the curve
//   search's on the same bilinear surface, interpolated twice. Noise and the coordinate's
//   curvature move them apart by a fraction of the noise on the simulated set and by about the
//   noise on the real capture, whose sigma (~0.01 px) is below the map's sub-pixel structure.
//   Either way it is far below the check's 0.5 px tolerance, whose tenth bounds the RMS; a wrong
//   row or rectification would put them pixels apart. Another crossing (> 1 px): under 1 %.
void ExpectAgreement(const Agreement& a) {
  EXPECT_GT(a.rectified, 0.99 * a.curve);
  EXPECT_LT(a.rectified, 1.01 * a.curve);
  EXPECT_GT(a.both, 0.985 * a.curve);
  EXPECT_LT(a.different, 1e-2 * a.both);
  EXPECT_GT(a.back_rectified, 0.98 * a.back_curve);
  EXPECT_GT(a.back_inside, a.back_curve / 2);
  EXPECT_LT(a.back_rms_px, 0.05);
  EXPECT_LT(a.back_rms_sigma, 1.5);
  EXPECT_LT(a.back_apart, 1e-2 * a.back_inside);
}

TEST(StereoRectified, AgreesWithTheCurveSearchOnTheRealCapture) {
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const DecodedCamera l = DecodeCamera(m, "left", DecodeOptions{});
  const DecodedCamera r = DecodeCamera(m, "right", DecodeOptions{});
  ExpectAgreement(Compare(ReadStereoCalibration(m.calibration), l, r, l.summary.period_px));
}

TEST(StereoRectified, AgreesWithTheCurveSearchOnASimulatedSet) {
  FringeSimulationConfig cfg = MakeFringePreset("small");
  cfg.seed = 41;
  const testing::DecodedStereo s = testing::SimulateAndDecode(cfg);
  ExpectAgreement(Compare(WrittenCalibration(MakeFringePreset("small")), s.left, s.right, s.period));
}

}  // namespace
}  // namespace ramtk::vision
