// Stereo matching and triangulation against the simulator's ground truth (small preset).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/coordinate_filter.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "ramtk/vision/stereo/triangulate.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

using testing::DecodedStereo;
using testing::SimulateAndDecode;

// The small preset rendered and decoded once for every test in this file.
const DecodedStereo& SmallSet() {
  static const DecodedStereo set = [] {
    FringeSimulationConfig c = MakeFringePreset("small");
    c.seed = 11;
    return SimulateAndDecode(c);
  }();
  return set;
}
StereoCalibration SmallCalibration() { return WrittenCalibration(MakeFringePreset("small")); }

// A left pixel well inside one object in both cameras (away from limbs and shadow edges), where
// the pixel-centre truth equals the pixel mean the decoder sees.
bool CleanLeftPixel(const DecodedStereo& s, int u, int v, int object) {
  for (int dv = -2; dv <= 2; ++dv)
    for (int du = -2; du <= 2; ++du) {
      const int x = u + du, y = v + dv;
      if (x < 0 || y < 0 || x >= s.left_sim.truth.object_id.cols || y >= s.left_sim.truth.object_id.rows) return false;
      if (s.left_sim.truth.object_id.at<int>(y, x) != object || s.left_sim.truth.lit_fraction.at<float>(y, x) != 1.0f)
        return false;
    }
  return true;
}

struct DepthErrors {
  long n = 0;
  double rms_um = 0, worst_um = 0, normalised_rms = 0;
};

// Per-point error along the left ray against the simulator's true depth, and that error over
// the point's predicted sigma.
DepthErrors CompareDepth(const DecodedStereo& s, const StereoCalibration& calib, const cv::Mat& depth,
                         const cv::Mat& sigma_map, int object) {
  DepthErrors e;
  double sum_sq = 0, sum_norm_sq = 0;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      if (!std::isfinite(depth.at<float>(v, u)) || !CleanLeftPixel(s, u, v, object)) continue;
      const Vec3 ray = PixelRay(calib.left, Vec2(u, v));
      const double along = (depth.at<float>(v, u) - s.left_sim.truth.depth.at<float>(v, u)) / ray.z();
      sum_sq += along * along;
      sum_norm_sq += std::pow(along / sigma_map.at<float>(v, u), 2);
      e.worst_um = std::max(e.worst_um, 1000 * std::abs(along));
      ++e.n;
    }
  e.rms_um = 1000 * std::sqrt(sum_sq / std::max<long>(e.n, 1));
  e.normalised_rms = std::sqrt(sum_norm_sq / std::max<long>(e.n, 1));
  return e;
}

// A map of the cloud's sigma at its left pixels.
cv::Mat SigmaMap(const PointCloud& cloud, cv::Size size) {
  cv::Mat m(size, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  for (std::size_t i = 0; i < cloud.size(); ++i)
    m.at<float>(static_cast<int>(cloud.left_pixels[i].y()), static_cast<int>(cloud.left_pixels[i].x())) =
        cloud.sigma_mm[i];
  return m;
}

// With either back pass (detail::StereoMatchTestHooks::rectified_back_pass): along the distorted epipolar
// curves, and along rectified rows (the default).
TEST(ScanMatch, DepthMatchesTheSimulatorTruthWithinThePredictedSigma) {
  for (const bool rectified : {false, true}) {
    SCOPED_TRACE(rectified ? "rectified back pass" : "curve back pass");
    std::cout << (rectified ? "rectified back pass\n" : "curve back pass\n");
    const DecodedStereo& s = SmallSet();
    const StereoCalibration calib = SmallCalibration();
    detail::StereoMatchTestHooks hooks;
    hooks.rectified_back_pass = rectified;
    const StereoMatch match =
        testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, s.left, s.right, s.period, {}); });
    ASSERT_EQ(match.summary.termination, Termination::kSuccess);
    std::cout << match.summary.BriefReport() << "\n";
    TriangulationSummary tsum;
    cv::Mat depth;
    const PointCloud cloud = TriangulateMatches(calib, s.left, match, {}, &tsum, &depth);
    RecordProperty("match", match.summary.BriefReport());
    RecordProperty("triangulate", tsum.BriefReport());
    ASSERT_GT(cloud.size(), 100000u);
    const cv::Mat sigma = SigmaMap(cloud, depth.size());
    for (int object : {0, 1}) {  // the ball, the backdrop
      const DepthErrors e = CompareDepth(s, calib, depth, sigma, object);
      RecordProperty("object" + std::to_string(object),
                     std::to_string(e.n) + " px, along-ray RMS " + std::to_string(e.rms_um) + " um, worst " +
                         std::to_string(e.worst_um) + " um, RMS(error/sigma) " + std::to_string(e.normalised_rms));
      std::cout << "object " << object << ": " << e.n << " px, RMS " << e.rms_um << " um, worst " << e.worst_um
                << " um, RMS(err/sigma) " << e.normalised_rms << "\n";
      EXPECT_GT(e.n, 20000);
      // Unbiased matching: the errors are the predicted noise, error/sigma has unit RMS. The
      // per-pixel truth is the pixel-centre ray, the decoded phase the pixel mean (~1e-3 px apart
      // on clean pixels, docs/vision_simulator.md), far below the noise.
      EXPECT_NEAR(e.normalised_rms, 1.0, 0.15);
      // No gross mismatch: nothing beyond 6 sigma of the largest point sigma.
      EXPECT_LT(e.worst_um, 6 * 1000 * 0.2);
    }
  }
}

// The match's own depths (StereoMatch::depth_mm) against intersecting the two rays again (the
// depths removed from the match). The rays meet at the match's point, so the two differ by the
// float rounding of the stored right pixel (half an ulp per coordinate, moving the point by
// |dX/ds| times that), of the stored depth and of the points. The sigmas are the same first-order quantity,
// |dX/dw| sigma_w against a central difference of 1e-3 px: with the full search, whose speed is
// taken at the root itself, they agree to the difference's truncation and float rounding.
TEST(ScanMatch, MatchDepthsGiveTheRayIntersection) {
  const DecodedStereo& s = SmallSet();
  const StereoCalibration calib = SmallCalibration();
  detail::StereoMatchTestHooks hooks;
  hooks.full_search = true;
  const StereoMatch match =
      testing::WithStereoHooks(hooks, [&] { return MatchStereo(calib, s.left, s.right, s.period, {}); });
  ASSERT_FALSE(match.depth_mm.empty());
  StereoMatch rays = match;
  rays.depth_mm = cv::Mat();
  rays.point_sigma_mm = cv::Mat();
  TriangulationSummary fast_sum, rays_sum;
  cv::Mat fast_depth, rays_depth;
  const PointCloud fast = TriangulateMatches(calib, s.left, match, {}, &fast_sum, &fast_depth);
  const PointCloud slow = TriangulateMatches(calib, s.left, rays, {}, &rays_sum, &rays_depth);
  ASSERT_EQ(fast.size(), slow.size());
  ASSERT_GT(fast.size(), 100000u);
  EXPECT_EQ(fast_sum.rejected_gap, 0);
  EXPECT_EQ(rays_sum.rejected_gap, 0);
  auto ulp = [](double x) { return std::nextafter(static_cast<float>(std::abs(x)), INFINITY) - std::abs(x); };
  double worst_position = 0, worst_sigma = 0;
  for (std::size_t k = 0; k < fast.size(); ++k) {
    ASSERT_EQ(fast.left_pixels[k], slow.left_pixels[k]);
    const int x = static_cast<int>(fast.left_pixels[k].x()), y = static_cast<int>(fast.left_pixels[k].y());
    const double u = match.right_u.at<float>(y, x), v = match.right_v.at<float>(y, x);
    const double dxds = slow.sigma_mm[k] / match.sigma_px.at<float>(y, x);  // mm per right px
    const double tolerance = dxds * 0.5 * (ulp(u) + ulp(v)) +
                             2 * ulp(std::max(fast.points_in_left[k].norm(), slow.points_in_left[k].norm()));
    const double position = (fast.points_in_left[k] - slow.points_in_left[k]).cast<double>().norm();
    worst_position = std::max(worst_position, position / tolerance);
    worst_sigma = std::max(worst_sigma, std::abs(fast.sigma_mm[k] / slow.sigma_mm[k] - 1.0));
    ASSERT_LE(position, tolerance) << "point " << k << " at (" << x << ", " << y << ")";
    ASSERT_NEAR(fast.sigma_mm[k], slow.sigma_mm[k], 1e-4 * slow.sigma_mm[k]) << "point " << k;
    EXPECT_EQ(fast.quality[k], slow.quality[k]);
  }
  std::cout << fast.size() << " points: worst position difference " << worst_position
            << " of its rounding bound, worst relative sigma difference " << worst_sigma << "\n";
  for (int y = 0; y < fast_depth.rows; ++y)
    for (int x = 0; x < fast_depth.cols; ++x)
      ASSERT_EQ(std::isfinite(fast_depth.at<float>(y, x)), std::isfinite(rays_depth.at<float>(y, x)));
}

// TriangulateMatches on `match` throws an InputError naming `field`.
void ExpectTriangulationRefuses(const StereoCalibration& calib, const DecodedCamera& left, const StereoMatch& match,
                                const std::string& field) {
  try {
    TriangulateMatches(calib, left, match, {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, field);
  }
}

// Maps of the wrong shape are an input error naming the field, not a crash. Without the right
// pixels (StereoMatchOptions::right_pixels false, as the scan runs) the cloud is the same.
TEST(ScanMatch, BadDepthMapsAreAnInputErrorAndRightPixelsAreOptional) {
  const DecodedStereo& s = SmallSet();
  const StereoCalibration calib = SmallCalibration();
  StereoMatch match = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  match.point_sigma_mm = cv::Mat(3, 3, CV_32F, cv::Scalar(0));
  ExpectTriangulationRefuses(calib, s.left, match, "depth_mm");
  StereoMatchOptions o;
  o.right_pixels = false;
  const StereoMatch lean = MatchStereo(calib, s.left, s.right, s.period, o);
  EXPECT_TRUE(lean.right_u.empty() && lean.right_v.empty());
  const StereoMatch full = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  const PointCloud a = TriangulateMatches(calib, s.left, lean, {}), b = TriangulateMatches(calib, s.left, full, {});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a.points_in_left[k], b.points_in_left[k]) << k;
}

// Without the sigma map (StereoMatchOptions::sigma_map false, as the scan runs) the summary's
// median is the map's upper median, std::nth_element's middle of its matched pixels' values, and
// the points and counts are the same.
TEST(ScanMatch, WithoutTheSigmaMapTheMedianIsTheMapsMiddleValue) {
  const DecodedStereo& s = SmallSet();
  const StereoCalibration calib = SmallCalibration();
  StereoMatchOptions o;
  o.sigma_map = false;
  const StereoMatch lean = MatchStereo(calib, s.left, s.right, s.period, o);
  const StereoMatch full = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  EXPECT_TRUE(lean.sigma_px.empty());
  std::vector<float> values;
  for (int y = 0; y < full.sigma_px.rows; ++y)
    for (int x = 0; x < full.sigma_px.cols; ++x)
      if (std::isfinite(full.sigma_px.at<float>(y, x))) values.push_back(full.sigma_px.at<float>(y, x));
  ASSERT_EQ(static_cast<long>(values.size()), full.summary.matched);
  ASSERT_GT(values.size(), 1000u);
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  EXPECT_EQ(static_cast<float>(lean.summary.median_sigma_px), values[values.size() / 2]);
  EXPECT_EQ(lean.summary.median_sigma_px, full.summary.median_sigma_px);
  EXPECT_EQ(lean.summary.matched, full.summary.matched);
  EXPECT_EQ(lean.summary.rejected_lr, full.summary.rejected_lr);
  EXPECT_EQ(lean.summary.rejected_no_match, full.summary.rejected_no_match);
  const PointCloud a = TriangulateMatches(calib, s.left, lean, {}), b = TriangulateMatches(calib, s.left, full, {});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.points_in_left[k], b.points_in_left[k]) << k;
    ASSERT_EQ(a.sigma_mm[k], b.sigma_mm[k]) << k;
  }
}

// The match's own points (StereoMatch::x_mm, y_mm, copied by TriangulateMatches) against the
// left ray undistorted again from the pixel and placed at the stored depth (the maps removed):
// the same cloud bit for bit, the same depth map, and maps of another size are an input error.
TEST(ScanMatch, MatchPointsAreTheUndistortedRayAtTheStoredDepth) {
  const DecodedStereo& s = SmallSet();
  const StereoCalibration calib = SmallCalibration();
  const StereoMatch match = MatchStereo(calib, s.left, s.right, s.period, StereoMatchOptions{});
  ASSERT_FALSE(match.x_mm.empty());
  ASSERT_FALSE(match.y_mm.empty());
  StereoMatch again = match;
  again.x_mm = cv::Mat();
  again.y_mm = cv::Mat();
  TriangulationOptions to;
  to.keep_pixels = true;
  cv::Mat copied_depth, again_depth;
  const PointCloud copied = TriangulateMatches(calib, s.left, match, to, nullptr, &copied_depth);
  const PointCloud undistorted = TriangulateMatches(calib, s.left, again, to, nullptr, &again_depth);
  ASSERT_EQ(copied.size(), undistorted.size());
  ASSERT_GT(copied.size(), 100000u);
  for (std::size_t k = 0; k < copied.size(); ++k) {
    ASSERT_EQ(copied.left_pixels[k], undistorted.left_pixels[k]) << k;
    ASSERT_EQ(copied.points_in_left[k], undistorted.points_in_left[k]) << k;
    ASSERT_EQ(copied.sigma_mm[k], undistorted.sigma_mm[k]) << k;
    ASSERT_EQ(copied.quality[k], undistorted.quality[k]) << k;
  }
  ASSERT_EQ(copied_depth.size(), again_depth.size());
  EXPECT_EQ(0, std::memcmp(copied_depth.data, again_depth.data, copied_depth.total() * sizeof(float)));
  StereoMatch bad = match;
  bad.y_mm = cv::Mat(3, 3, CV_32F, cv::Scalar(0));
  ExpectTriangulationRefuses(calib, s.left, bad, "x_mm");
}

// The phase-domain filter (DecodeOptions::coordinate_filter) on both cameras: the depth error
// stays consistent with the sigma the filter reports, and it shrinks.
TEST(ScanMatch, PhaseFilterKeepsDepthWithinItsSigma) {
  const DecodedStereo& s = SmallSet();
  const StereoCalibration calib = SmallCalibration();
  DecodedCamera left = s.left, right = s.right;
  left.coordinate = left.coordinate.clone(), left.sigma_coordinate = left.sigma_coordinate.clone();
  right.coordinate = right.coordinate.clone(), right.sigma_coordinate = right.sigma_coordinate.clone();
  CoordinateFilterOptions fo;
  fo.radius_px = 2;
  for (DecodedCamera* d : {&left, &right}) {
    const CoordinateFilterSummary fs =
        FilterCoordinate(fo, d->summary.phase_ripple_rad * d->summary.period_px / (2 * CV_PI), d);
    std::cout << "filtered " << fs.filtered << " px, median sigma x" << fs.median_sigma_ratio << "\n";
    EXPECT_LT(fs.median_sigma_ratio, 0.8);
  }
  auto depth_errors = [&](const DecodedCamera& l, const DecodedCamera& r, int object) {
    const StereoMatch match = MatchStereo(calib, l, r, s.period, StereoMatchOptions{});
    cv::Mat depth;
    const PointCloud cloud = TriangulateMatches(calib, l, match, {}, nullptr, &depth);
    return CompareDepth(s, calib, depth, SigmaMap(cloud, depth.size()), object);
  };
  for (int object : {0, 1}) {
    const DepthErrors raw = depth_errors(s.left, s.right, object);
    const DepthErrors e = depth_errors(left, right, object);
    std::cout << "object " << object << ": filtered " << e.n << " px, RMS " << e.rms_um << " um (unfiltered "
              << raw.rms_um << "), RMS(err/sigma) " << e.normalised_rms << "\n";
    EXPECT_GT(e.n, 20000);
    EXPECT_NEAR(e.normalised_rms, 1.0, 0.15);
    EXPECT_LT(e.rms_um, 0.8 * raw.rms_um);
  }
}

}  // namespace
}  // namespace ramtk::vision
