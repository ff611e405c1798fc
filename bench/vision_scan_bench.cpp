// Scan benchmark and accuracy sweep.
//
//   vision_scan_bench speed [--preset small|thesis] [--repeat N] [--supersampling S]
//       decode + match + triangulate + fit of one simulated stereo set (the simulator's native
//       8-bit frames, as `ramtk scan` reads them), each stage's share, and OpenCV's
//       cv::triangulatePoints on the same matches as a peer (ratio).
//   vision_scan_bench speed --manifest SET/manifest.json [--repeat N] [--float 1]
//       a set on disk loaded into memory once, then the same stages N times: min / median / max
//       per stage and its cost per pixel-frame, per valid pixel and per point
//       (vision_scan_bench_set_speed.cpp); --float 1 also times the decode of the frames
//       converted to float.
//   vision_scan_bench accuracy [--first-pose K] [--poses P] [--seeds S] [--state-kernel 1]
//       (--state-kernel 1: the calibration the scan reads states the rendered sampling kernel, so
//       the matcher applies its kernel and interpolation terms; default 0, not stated)
//       thesis geometry (the small preset = 640x512 windows of the 3312x2488 cameras cropped
//       around the ball, ~700 mm), the ball at P poses over the field (pose 0 = the bundled
//       default pose), S noise seeds each: the noise-free radiance is rendered once per pose and
//       only the sensor noise is redrawn per seed. Per scanned cloud: the scan's sphere, the same
//       cloud fitted with every inlier (no viewing-angle cut), and PCL's RANSAC sphere
//       (SACSegmentation, SACMODEL_SPHERE); centre / radius errors against the truth, predicted
//       centre sigma against the observed scatter, fit time ratio against PCL.
//   vision_scan_bench limb [--seed N] [--noise 0|1]
//       the default pose: per-point error against the true sphere binned by viewing angle, and
//       the fitted centre with and without the grazing points.
//   vision_scan_bench set --manifest SET/manifest.json [--phase-filter R]
//       a simulated set on disk (`ramtk simulate fringe`, its truth in SET/truth): per-point error
//       along the left ray against the true depth on clean pixels (ball, backdrop) and that
//       error over the point's sigma; the ball's points against the true sphere by viewing angle;
//       the fitted centre against the truth.
//   vision_scan_bench decode --manifest SET/manifest.json [--repeat N]
//       each camera's frames loaded once (native depth, as `ramtk scan`), then decoded N times
//       with the scan's options: wall time from each stage's progress report to the next (phase,
//       unwrap, nonlinearity, done), min and median over the repetitions.
#include <malloc.h>
#include <tbb/global_control.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/stereo/cloud_noise.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/stereo/detail/test_hooks.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "scan_sim.h"
#include "sphere_pcl_peer.h"

using namespace ramtk;
using namespace ramtk::vision;
using Clock = std::chrono::steady_clock;

namespace ramtk::vision {
int SetSpeed(const std::string& manifest_path, int repeat, bool with_float);  // vision_scan_bench_set_speed.cpp
}  // namespace ramtk::vision

namespace {

double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

int Arg(int argc, char** argv, const char* name, int fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], name)) return std::atoi(argv[i + 1]);
  return fallback;
}
std::string ArgS(int argc, char** argv, const char* name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], name)) return argv[i + 1];
  return fallback;
}

int Speed(const std::string& preset, int repeat, int supersampling) {
  FringeSimulationConfig c = MakeFringePreset(preset);
  if (supersampling > 0) c.supersampling = supersampling;
  std::printf("rendering the %s preset...\n", preset.c_str());
  const SimulatedCamera l = SimulateCamera(c, 0), r = SimulateCamera(c, 1);
  const StereoCalibration calib = WrittenCalibration(c);
  for (int k = 0; k < repeat; ++k) {
    auto t = Clock::now();
    const DecodeOptions decode = ScanOptions().decode;
    const double full_scale = (1 << c.sensor.bits) - 1.0;
    const DecodedCamera dl = DecodeFrames(testing::ManifestForConfig(c), l.images, full_scale, decode, "left");
    const DecodedCamera dr = DecodeFrames(testing::ManifestForConfig(c), r.images, full_scale, decode, "right");
    const double decode_s = Since(t);
    const ScanResult res = ScanDecoded(calib, dl, dr, dl.summary.period_px, ScanOptions{});
    const ScanSummary& s = res.summary;
    const double total = decode_s + s.match_s + s.triangulate_s + s.fit_s;
    std::printf(
        "%dx%d: %ld points, total %.2f s: decode %.2f s (%.0f%%), match %.2f s (%.0f%%), triangulate %.2f s "
        "(%.0f%%), fit %.2f s (%.0f%%)\n  %s\n",
        s.width, s.height, s.triangulation.points, total, decode_s, 100 * decode_s / total, s.match_s,
        100 * s.match_s / total, s.triangulate_s, 100 * s.triangulate_s / total, s.fit_s, 100 * s.fit_s / total,
        s.BriefReport().c_str());
    // Peer: cv::undistortPoints + cv::triangulatePoints (DLT on undistorted points) on the same
    // matches: the left pixels, and the right positions they matched (our points re-projected
    // into the right camera: they lie on the matched positions to ~1e-9 px).
    std::vector<cv::Point2d> pl, pr, ul, ur;
    for (std::size_t i = 0; i < res.cloud.size(); ++i) {
      pl.emplace_back(res.cloud.left_pixels[i].x(), res.cloud.left_pixels[i].y());
      const Vec2 q = ProjectPoint(calib.right, calib.right_from_left * res.cloud.points_in_left[i].cast<double>());
      pr.emplace_back(q.x(), q.y());
    }
    cv::Mat K1, K2, D1, D2;
    cv::eigen2cv(Eigen::Matrix3d(calib.left.K()), K1);
    cv::eigen2cv(Eigen::Matrix3d(calib.right.K()), K2);
    D1 = (cv::Mat_<double>(1, 5) << calib.left.distortion.k1, calib.left.distortion.k2, calib.left.distortion.p1,
          calib.left.distortion.p2, calib.left.distortion.k3);
    D2 = (cv::Mat_<double>(1, 5) << calib.right.distortion.k1, calib.right.distortion.k2, calib.right.distortion.p1,
          calib.right.distortion.p2, calib.right.distortion.k3);
    t = Clock::now();
    cv::undistortPoints(pl, ul, K1, D1);
    cv::undistortPoints(pr, ur, K2, D2);
    cv::Mat R, T;
    cv::eigen2cv(Eigen::Matrix3d(calib.right_from_left.linear()), R);
    cv::eigen2cv(Eigen::Vector3d(calib.right_from_left.translation()), T);
    cv::Mat P1 = cv::Mat::eye(3, 4, CV_64F), P2(3, 4, CV_64F);
    R.copyTo(P2(cv::Rect(0, 0, 3, 3)));
    T.copyTo(P2(cv::Rect(3, 0, 1, 3)));
    cv::Mat X4;
    cv::triangulatePoints(P1, P2, ul, ur, X4);
    const double cv_s = Since(t);
    double max_diff = 0;
    for (int i = 0; i < X4.cols; ++i) {
      const Eigen::Vector3d Xc(X4.at<double>(0, i) / X4.at<double>(3, i), X4.at<double>(1, i) / X4.at<double>(3, i),
                               X4.at<double>(2, i) / X4.at<double>(3, i));
      max_diff = std::max(max_diff, (Xc - res.cloud.points_in_left[i].cast<double>()).norm());
    }
    std::printf(
        "  peer: cv::undistortPoints + cv::triangulatePoints (no sigma) %.3f s vs ramtk triangulate (with "
        "sigma Jacobian) %.3f s: ratio %.2f; max point difference %.2g mm (float32 storage)\n",
        cv_s, s.triangulate_s, s.triangulate_s / cv_s, max_diff);
  }
  // The same frames with windows around the ball (`ramtk scan --roi auto`), in memory: the coarse
  // pass, then decode and match of the windows. Beside it the memory floor: one copy of the
  // set's samples into fresh memory (what loading the set can at best cost).
  std::vector<cv::Mat> lf = l.images, rf = r.images;
  std::size_t bytes = 0;
  for (const auto* v : {&lf, &rf})
    for (const cv::Mat& m : *v) bytes += m.total() * m.elemSize();
  for (int k = 0; k < repeat; ++k) {
    auto t = Clock::now();
    std::vector<cv::Mat> copies;
    for (const auto* v : {&lf, &rf})
      for (const cv::Mat& m : *v) copies.push_back(m.clone());
    const double floor_s = Since(t);
    ScanOptions o;
    o.roi.mode = ScanRoiOptions::Mode::kAuto;
    t = Clock::now();
    const ScanResult res = ScanFrames(testing::ManifestForConfig(c), calib, lf, rf, (1 << c.sensor.bits) - 1.0, o);
    const double total = Since(t);
    const ScanSummary& s = res.summary;
    std::printf(
        "roi auto: total %.3f s in memory (coarse pass %.3f s, decode %.3f s, match %.3f s, triangulate %.3f s, "
        "fit %.3f s); left window %s, %ld points\n  memory floor: one copy of the set's %.0f MB %.3f s "
        "(ratio %.1f)\n  %s\n",
        total, s.roi_s, s.decode_s, s.match_s, s.triangulate_s, s.fit_s, WindowText(s.windows.left).c_str(),
        s.triangulation.points, bytes / 1e6, floor_s, total / floor_s, s.BriefReport().c_str());
  }
  return 0;
}

// Running statistics of one method over the seeds of one pose and over the whole sweep.
struct MethodStats {
  std::vector<Vec3> centres;
  std::vector<double> e2_all, radius_all;  // over all poses
  Vec3 sigma_pred = Vec3::Zero(), sigma_pred_raw = Vec3::Zero();
  double radius_sum = 0, seconds = 0;
  int misses = 0;
  std::vector<double> ratio, ratio_raw;  // predicted / observed sigma per axis and pose
  double max_bias = 0;

  void Add(const Vec3& centre, double radius, const Vec3& sigma, double correlation_factor, const Vec3& ball) {
    centres.push_back(centre);
    e2_all.push_back((centre - ball).squaredNorm());
    radius_all.push_back(radius - 19.05);
    radius_sum += radius - 19.05;
    sigma_pred += sigma;
    sigma_pred_raw += sigma / std::sqrt(correlation_factor);
  }
  // Prints the pose line and resets the per-pose part.
  void EndPose(const char* name, const Vec3& ball) {
    const double n = static_cast<double>(centres.size());
    if (n < 2) {
      std::printf("  %-22s %zu scans\n", name, centres.size());
      centres.clear();
      return;
    }
    Vec3 mean = Vec3::Zero(), sd = Vec3::Zero();
    for (const Vec3& x : centres) mean += x / n;
    for (const Vec3& x : centres) sd += (x - mean).cwiseAbs2() / (n - 1);
    sd = sd.cwiseSqrt();
    const Vec3 bias = mean - ball, pred = sigma_pred / n, raw = sigma_pred_raw / n;
    max_bias = std::max(max_bias, bias.norm());
    std::printf("  %-22s bias (%+.2f, %+.2f, %+.2f) um, scatter (%.2f, %.2f, %.2f) um, radius %+.2f um", name,
                1000 * bias.x(), 1000 * bias.y(), 1000 * bias.z(), 1000 * sd.x(), 1000 * sd.y(), 1000 * sd.z(),
                1000 * radius_sum / n);
    if (pred.norm() > 0) {
      std::printf(", predicted sigma (%.2f, %.2f, %.2f) um [independent points (%.2f, %.2f, %.2f)]", 1000 * pred.x(),
                  1000 * pred.y(), 1000 * pred.z(), 1000 * raw.x(), 1000 * raw.y(), 1000 * raw.z());
      for (int k = 0; k < 3; ++k) ratio.push_back(pred[k] / sd[k]), ratio_raw.push_back(raw[k] / sd[k]);
    }
    std::printf("\n");
    centres.clear();
    sigma_pred = sigma_pred_raw = Vec3::Zero();
    radius_sum = 0;
  }
  void Summary(const char* name) {
    double se = 0, sr = 0;
    for (double x : e2_all) se += x;
    for (double x : radius_all) sr += x;
    const double n = std::max<double>(1, e2_all.size());
    std::printf(
        "%-22s %zu scans (%d without a sphere): centre error RMS %.2f um (largest pose bias %.2f um), mean "
        "radius error %+.2f um, %.3f s per fit",
        name, e2_all.size(), misses, 1000 * std::sqrt(se / n), 1000 * max_bias, 1000 * sr / n, seconds / n);
    auto range = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      std::printf(" median %.2f, range %.2f..%.2f", v[v.size() / 2], v.front(), v.back());
    };
    if (!ratio.empty()) {
      std::printf("\n  predicted/observed centre sigma per axis:");
      range(ratio);
      std::printf("; without the correlation factor:");
      range(ratio_raw);
    }
    std::printf("\n");
  }
};

// The stereo match's test hooks with the back pass `rectified` 0 (along the curves) / 1 (rectified
// rows); -1 keeps the default.
detail::StereoMatchTestHooks BackPassHooks(int rectified) {
  detail::StereoMatchTestHooks hooks;
  if (rectified >= 0) hooks.rectified_back_pass = rectified != 0;
  return hooks;
}

// Pose p of the sweep: p = 0 the bundled default pose (0, 0, 700); then a 5 x 4 grid over the
// field (x -40..40, y -30..30 mm) with z alternating 680 / 720 mm.
Vec3 SweepPose(int p) {
  if (p == 0) return Vec3(0, 0, 700);
  const int q = p - 1, ix = q % 5, iy = (q / 5) % 4;
  return Vec3(-40 + 20 * ix, -30 + 20 * iy, q % 2 ? 720 : 680);
}

// `rectified` 0 / 1 sets the test hook StereoMatchTestHooks::rectified_back_pass, -1 keeps the default.
int Accuracy(int first_pose, int poses, int seeds, int rectified, bool state_kernel) {
  const detail::ScopedStereoMatchTestHooks hooks(BackPassHooks(rectified));
  MethodStats ours, all_points, pcl;
  for (int p = first_pose; p < first_pose + poses; ++p) {
    const Vec3 ball = SweepPose(p);
    FringeSimulationConfig c = MakeFringePreset("small", ball);
    c.sensor.noise = false;
    const SimulatedCamera l0 = SimulateCamera(c, 0), r0 = SimulateCamera(c, 1);
    c.sensor.noise = true;
    const StereoCalibration calib = WrittenCalibration(state_kernel ? StateRenderedKernel(c) : c);
    for (int s = 0; s < seeds; ++s) {
      c.seed = 1000 + s;
      const SimulatedCamera l = ResenseCamera(c, l0, 0), r = ResenseCamera(c, r0, 1);
      const DecodedCamera dl = testing::DecodeSimulated(c, l), dr = testing::DecodeSimulated(c, r);
      ScanOptions options;
      const ScanResult res = ScanDecoded(calib, dl, dr, dl.summary.period_px, options);
      if (res.summary.spheres.spheres.empty()) {
        std::printf("pose %d seed %d: %s\n", p, s, res.summary.BriefReport().c_str());
        ++ours.misses;
      } else {
        const SphereResult& b = res.summary.spheres.spheres[0];
        ours.Add(b.centre_mm, b.radius_mm, b.CentreSigma(), b.correlation_factor, ball);
        ours.seconds += res.summary.fit_s;
      }
      // The same cloud fitted with every inlier (no viewing-angle cut, independent-point sigma).
      SphereFitOptions so = options.sphere;
      so.max_view_angle_deg = 0;
      auto t = Clock::now();
      const SphereFitSummary fa = FindSpheres(res.cloud.points_in_left, res.cloud.sigma_mm, so);
      all_points.seconds += Since(t);
      if (fa.spheres.empty())
        ++all_points.misses;
      else
        all_points.Add(fa.spheres[0].centre_mm, fa.spheres[0].radius_mm, fa.spheres[0].CentreSigma(), 1.0, ball);
      // Peer: PCL's RANSAC sphere (SACSegmentation, SACMODEL_SPHERE, optimised coefficients) on
      // the same scanned cloud, band 0.1 mm (3x the points' noise along the normal), radius prior +-2 mm.
      t = Clock::now();
      const test::PclSphere ps = test::PclFitSphere(test::ToPcl(res.cloud.points_in_left), 0.1, 17.05, 21.05);
      pcl.seconds += Since(t);
      if (!ps.found)
        ++pcl.misses;
      else
        pcl.Add(ps.centre, ps.radius, Vec3::Zero(), 1.0, ball);
    }
    std::printf("pose %2d ball (%.0f, %.0f, %.0f), %d seeds:\n", p, ball.x(), ball.y(), ball.z(), seeds);
    ours.EndPose("ramtk (scan defaults)", ball);
    all_points.EndPose("ramtk, all inliers", ball);
    pcl.EndPose("PCL RANSAC sphere", ball);
    std::fflush(stdout);
  }
  std::printf("summary over %d poses x %d seeds:\n", poses, seeds);
  ours.Summary("ramtk (scan defaults)");
  all_points.Summary("ramtk, all inliers");
  pcl.Summary("PCL RANSAC sphere");
  std::printf("fit time ratio ramtk / PCL: %.2f\n", ours.seconds / std::max(1e-9, pcl.seconds));
  return ours.e2_all.empty() ? 1 : 0;
}

// Per-point error against the true sphere binned by the viewing angle (between the left
// camera's line of sight and the true surface normal): where the fitted centre's bias comes from.
int Limb(const Vec3& ball, int seed, bool noise) {
  FringeSimulationConfig c = MakeFringePreset("small", ball);
  c.seed = seed;
  c.sensor.noise = noise;
  const SimulatedCamera l = SimulateCamera(c, 0), r = SimulateCamera(c, 1);
  const DecodedCamera dl = testing::DecodeSimulated(c, l), dr = testing::DecodeSimulated(c, r);
  ScanOptions o;
  o.fit_spheres = false;
  const ScanResult res = ScanDecoded(WrittenCalibration(c), dl, dr, dl.summary.period_px, o);
  const Sphere& truth = c.scene.spheres[0];
  constexpr int kBins = 9;  // 10 degree bins
  double n[kBins] = {}, sum[kBins] = {}, sum2[kBins] = {}, sum_sigma[kBins] = {}, sw[kBins] = {}, swe[kBins] = {},
         sr[kBins] = {};
  for (std::size_t i = 0; i < res.cloud.size(); ++i) {
    const Vec3 p = res.cloud.points_in_left[i].cast<double>();
    const Vec3 normal = (p - truth.centre_in_left).normalized();
    const double e = (p - truth.centre_in_left).norm() - truth.radius;
    if (std::abs(e) > 0.5) continue;  // backdrop
    const double cos_view = std::clamp(-normal.dot(p.normalized()), -1.0, 1.0);
    const int b = std::min(kBins - 1, static_cast<int>(std::acos(cos_view) * 180 / M_PI / 10));
    n[b] += 1;
    sum[b] += e;
    sum2[b] += e * e;
    sum_sigma[b] += res.cloud.sigma_mm[i] * std::abs(cos_view);  // sigma along the normal (approx.)
    const double sn = res.cloud.sigma_mm[i] * std::sqrt(cos_view * cos_view + 4e-4 * (1 - cos_view * cos_view));
    sw[b] += 1 / (sn * sn);
    swe[b] += e / (sn * sn);
    sr[b] += e / std::max(0.01, cos_view);
  }
  std::printf("ball (%.0f, %.0f, %.0f), seed %d: error along the true normal by viewing angle\n", ball.x(), ball.y(),
              ball.z(), seed);
  for (int b = 0; b < kBins; ++b)
    if (n[b] > 0)
      std::printf(
          "  %2d-%2d deg: %6.0f points, mean %+7.2f um (fit-weighted %+7.2f, along the ray %+7.2f), rms %6.2f um, "
          "mean sigma_n %6.2f um\n",
          10 * b, 10 * b + 10, n[b], 1000 * sum[b] / n[b], 1000 * swe[b] / sw[b], 1000 * sr[b] / n[b],
          1000 * std::sqrt(sum2[b] / n[b]), 1000 * sum_sigma[b] / n[b]);
  auto fit = [&](const char* what, const SphereFitOptions& so, const std::vector<Eigen::Vector3f>& pts,
                 const std::vector<float>& sig) {
    const SphereFitSummary f = FindSpheres(pts, sig, so);
    if (f.spheres.empty()) return;
    const SphereResult& b = f.spheres[0];
    const Vec3 e = 1000 * (b.centre_mm - truth.centre_in_left);
    std::printf("  %-40s centre error (%+.2f, %+.2f, %+.2f) um, radius %+.2f um, %d points, vf %.2f\n", what, e.x(),
                e.y(), e.z(), 1000 * (b.radius_mm - truth.radius), b.num_points, b.variance_factor);
  };
  const ScanOptions def;
  {
    // The neighbour correlation of the scan's fit residuals (what the scan inflates sigma by).
    ScanOptions o2;
    const ScanResult fitted = ScanDecoded(WrittenCalibration(c), dl, dr, dl.summary.period_px, o2);
    if (!fitted.summary.spheres.spheres.empty()) {
      const SphereResult& b = fitted.summary.spheres.spheres[0];
      std::vector<Eigen::Vector2f> px;
      std::vector<double> z;
      for (int i : b.inlier_indices) {
        const Vec3 p = fitted.cloud.points_in_left[i].cast<double>();
        px.push_back(fitted.cloud.left_pixels[i]);
        z.push_back(((p - b.centre_mm).norm() - b.radius_mm) / fitted.cloud.sigma_mm[i]);
      }
      const NeighbourCorrelation nc =
          EstimateNeighbourCorrelation(px, z, cv::Size(fitted.summary.width, fitted.summary.height));
      std::printf("  residual correlation: rho(1,0) %.3f, rho(0,1) %.3f, factor %.3f (scan: %.3f)\n", nc.rho_right,
                  nc.rho_down, nc.factor, b.correlation_factor);
    }
  }
  fit("scan defaults (fitted normal <= 60 deg)", def.sphere, res.cloud.points_in_left, res.cloud.sigma_mm);
  SphereFitOptions all = def.sphere;
  all.max_view_angle_deg = 0;
  fit("all inliers", all, res.cloud.points_in_left, res.cloud.sigma_mm);
  SphereFitOptions iso = all;
  iso.noise_model = PointNoiseModel::kIsotropic;
  fit("all inliers, unweighted", iso, res.cloud.points_in_left, {});
  // Cuts by the true viewing angle.
  for (double max_deg : {80.0, 70.0, 50.0}) {
    std::vector<Eigen::Vector3f> pts;
    std::vector<float> sig;
    for (std::size_t i = 0; i < res.cloud.size(); ++i) {
      const Vec3 p = res.cloud.points_in_left[i].cast<double>();
      const Vec3 normal = (p - truth.centre_in_left).normalized();
      if ((p - truth.centre_in_left).norm() - truth.radius < 0.5 &&
          std::acos(std::clamp(-normal.dot(p.normalized()), -1.0, 1.0)) * 180 / M_PI > max_deg)
        continue;
      pts.push_back(res.cloud.points_in_left[i]);
      sig.push_back(res.cloud.sigma_mm[i]);
    }
    fit(("true viewing angle <= " + std::to_string(static_cast<int>(max_deg)) + " deg").c_str(), all, pts, sig);
  }
  return 0;
}

// Per-point errors of a scanned set on disk against its rendered truth maps.
int SetErrors(const std::string& manifest, int phase_filter) {
  const std::string dir = manifest.substr(0, manifest.find_last_of('/'));
  ScanOptions o;
  o.decode.coordinate_filter.radius_px = phase_filter;
  const ScanResult res = ScanFringeSet(manifest, o);
  const cv::Mat depth = cv::imread(dir + "/truth/left_depth.tif", cv::IMREAD_UNCHANGED);
  const cv::Mat object = cv::imread(dir + "/truth/left_object_id.tif", cv::IMREAD_UNCHANGED);
  const cv::Mat lit = cv::imread(dir + "/truth/left_lit_fraction.tif", cv::IMREAD_UNCHANGED);
  if (depth.type() != CV_32F || lit.type() != CV_32F || object.empty()) {
    std::fprintf(stderr, "%s/truth: expected float TIFF truth maps\n", dir.c_str());
    return 1;
  }
  const Sphere truth = ReadTruthSpheres(dir + "/truth/truth.json").at(0);
  const StereoCalibration calib = ReadStereoCalibration(dir + "/calibration.yml");
  auto object_at = [&](int x, int y) {
    return object.depth() == CV_32F ? static_cast<int>(object.at<float>(y, x)) : object.at<int>(y, x);
  };
  auto clean = [&](int u, int v, int id) {
    for (int dv = -2; dv <= 2; ++dv)
      for (int du = -2; du <= 2; ++du) {
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return false;
        if (object_at(x, y) != id || lit.at<float>(y, x) != 1.0f) return false;
      }
    return true;
  };
  constexpr int kBins = 9;
  double n[2] = {}, sq[2] = {}, nsq[2] = {}, mean[2] = {};
  double bn[kBins] = {}, bsum[kBins] = {}, bnsq[kBins] = {}, bsig[kBins] = {};
  for (std::size_t i = 0; i < res.cloud.size(); ++i) {
    const int u = static_cast<int>(res.cloud.left_pixels[i].x()), v = static_cast<int>(res.cloud.left_pixels[i].y());
    const Vec3 p = res.cloud.points_in_left[i].cast<double>();
    const double sigma = res.cloud.sigma_mm[i];
    for (int id : {0, 1}) {
      if (!clean(u, v, id)) continue;
      const Vec3 ray = PixelRay(calib.left, Vec2(u, v));
      const double along = (p.z() - depth.at<float>(v, u)) / ray.z();
      n[id] += 1, sq[id] += along * along, nsq[id] += std::pow(along / sigma, 2), mean[id] += along;
    }
    const double e = (p - truth.centre_in_left).norm() - truth.radius;
    if (std::abs(e) > 0.5) continue;
    const Vec3 normal = (p - truth.centre_in_left).normalized();
    const double cos_view = std::clamp(-normal.dot(p.normalized()), -1.0, 1.0);
    const int b = std::min(kBins - 1, static_cast<int>(std::acos(cos_view) * 180 / M_PI / 10));
    const double sn = sigma * std::abs(cos_view);  // sigma along the normal, for a ray-aligned error
    bn[b] += 1, bsum[b] += e, bnsq[b] += sn > 0 ? e * e / (sn * sn) : 0, bsig[b] += sn;
  }
  std::printf("%s%s: %zu points\n", manifest.c_str(), phase_filter ? " (phase filter)" : "", res.cloud.size());
  const char* names[2] = {"ball", "backdrop"};
  for (int id : {0, 1})
    if (n[id] > 0)
      std::printf("  %-8s clean px %7.0f: error along the ray mean %+7.2f um, RMS %7.2f um, RMS(error/sigma) %.3f\n",
                  names[id], n[id], 1000 * mean[id] / n[id], 1000 * std::sqrt(sq[id] / n[id]),
                  std::sqrt(nsq[id] / n[id]));
  std::printf("  ball points against the true sphere, by viewing angle:\n");
  for (int b = 0; b < kBins; ++b)
    if (bn[b] > 0)
      std::printf("    %2d-%2d deg: %6.0f points, mean %+7.2f um, RMS(error/sigma_n) %.3f, mean sigma_n %6.2f um\n",
                  10 * b, 10 * b + 10, bn[b], 1000 * bsum[b] / bn[b], std::sqrt(bnsq[b] / bn[b]),
                  1000 * bsig[b] / bn[b]);
  {
    // The true errors' correlation between neighbouring ball points (what the scan's fit
    // estimates from its residuals), over growing lags.
    std::vector<Eigen::Vector2f> px;
    std::vector<double> z;
    for (std::size_t i = 0; i < res.cloud.size(); ++i) {
      const Vec3 p = res.cloud.points_in_left[i].cast<double>();
      const double e = (p - truth.centre_in_left).norm() - truth.radius;
      if (std::abs(e) > 0.5) continue;
      const double cos_view = std::abs((p - truth.centre_in_left).normalized().dot(p.normalized()));
      if (cos_view < 0.5) continue;  // the fit's 60 deg cut
      px.push_back(res.cloud.left_pixels[i]);
      z.push_back(e / (res.cloud.sigma_mm[i] * cos_view));
    }
    std::printf("  true-error correlation of ball points (<= 60 deg):");
    for (int lag : {1, 2, 4, 6, 8})
      std::printf(" lag<=%d factor %.3f;", lag,
                  EstimateNeighbourCorrelation(px, z, cv::Size(res.summary.width, res.summary.height), lag).factor);
    std::printf("\n");
  }
  if (!res.summary.spheres.spheres.empty()) {
    const SphereResult& s = res.summary.spheres.spheres[0];
    const Vec3 e = 1000 * (s.centre_mm - truth.centre_in_left);
    std::printf(
        "  centre error (%+.2f, %+.2f, %+.2f) um, predicted sigma (%.2f, %.2f, %.2f) um, radius %+.2f um, "
        "correlation factor %.2f, variance factor %.2f\n",
        e.x(), e.y(), e.z(), 1000 * std::sqrt(s.centre_covariance_mm2(0, 0)),
        1000 * std::sqrt(s.centre_covariance_mm2(1, 1)), 1000 * std::sqrt(s.centre_covariance_mm2(2, 2)),
        1000 * (s.radius_mm - truth.radius), s.correlation_factor, s.variance_factor);
  }
  return 0;
}

int DecodeStages(const std::string& manifest_path, int repeat) {
  if (manifest_path.empty()) {
    std::fprintf(stderr, "decode: --manifest SET/manifest.json is required\n");
    return 2;
  }
  const FringeManifest m = ReadFringeManifest(manifest_path);
  for (const auto& [camera, files] : m.cameras) {
    std::vector<std::string> paths;
    for (const std::string& f : files) paths.push_back(m.Resolve(f));
    const ImageStack stack = LoadImageStack(paths, 0.02, true);
    std::vector<std::string> stages;
    std::vector<std::vector<double>> times;  // per stage, per repetition
    for (int r = 0; r < repeat; ++r) {
      DecodeOptions o = ScanOptions().decode;
      auto last = std::chrono::steady_clock::now();
      int k = 0;
      o.progress = [&](const ramtk::Progress& p) {
        const auto now = std::chrono::steady_clock::now();
        if (r == 0) {
          stages.push_back(p.stage);
          times.emplace_back();
        }
        if (k < static_cast<int>(times.size())) times[k++].push_back(std::chrono::duration<double>(now - last).count());
        last = now;
        return true;
      };
      const DecodedCamera d = DecodeFrames(m, stack.frames, stack.full_scale, o, camera);
      if (r == 0) std::printf("%s: %s\n", camera.c_str(), d.summary.BriefReport().c_str());
    }
    std::printf("%s, %d repetitions, ms (min / median):", camera.c_str(), repeat);
    double total_min = 0;
    for (std::size_t k = 0; k < stages.size(); ++k) {
      std::vector<double> t = times[k];
      std::sort(t.begin(), t.end());
      total_min += t.front();
      std::printf(" %s %.1f / %.1f;", stages[k].c_str(), 1e3 * t.front(), 1e3 * t[t.size() / 2]);
    }
    std::printf(" sum of minima %.1f\n", 1e3 * total_min);
  }
  return 0;
}

// The match of one set, repeated on the decoded cameras: each pass's time (min / median) and the
// summary. `threads` > 0 caps TBB's threads (1: the per-pixel cost without the machine's
// scheduling noise).
// `rectified` 0 / 1 sets the test hook StereoMatchTestHooks::rectified_back_pass, -1 keeps the default.
// `noise_term` 0 turns StereoMatchOptions::noise_bias_term off (its cost).
int MatchPasses(const std::string& manifest_path, int repeat, int threads, int rectified, int noise_term) {
  const detail::ScopedStereoMatchTestHooks hooks(BackPassHooks(rectified));
  if (manifest_path.empty()) {
    std::fprintf(stderr, "match: --manifest SET/manifest.json is required\n");
    return 2;
  }
  std::unique_ptr<tbb::global_control> cap;
  if (threads > 0) cap = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  const FringeManifest m = ReadFringeManifest(manifest_path);
  const ScanOptions so;
  const StereoCalibration calibration = ReadStereoCalibration(m.Resolve(m.calibration));
  auto decode = [&](const std::string& camera) {
    std::vector<std::string> paths;
    for (const std::string& f : m.cameras.at(camera)) paths.push_back(m.Resolve(f));
    const ImageStack stack = LoadImageStack(paths, so.decode.dark_fraction, true);
    return DecodeFrames(m, stack.frames, stack.full_scale, so.decode, camera);
  };
  const DecodedCamera left = decode(so.left_camera), right = decode(so.right_camera);
  std::vector<std::string> stages;
  std::vector<std::vector<double>> times;
  for (int r = 0; r < repeat; ++r) {
    StereoMatchOptions o = so.match;
    o.noise_bias_term = noise_term != 0;
    auto last = Clock::now();
    std::string stage;
    std::size_t k = 0;
    o.progress = [&](const ramtk::Progress& p) {
      if (p.done < p.total) return true;  // a pass ends at done == total
      const auto now = Clock::now();
      if (r == 0) {
        stages.push_back(p.stage);
        times.emplace_back();
      }
      if (k < times.size()) times[k++].push_back(std::chrono::duration<double>(now - last).count());
      last = now;
      return true;
    };
    const StereoMatch match = MatchStereo(calibration, left, right, left.summary.period_px, o);
    if (r == 0) std::printf("%s\n", match.summary.BriefReport().c_str());
  }
  std::printf("%d repetitions, %s threads, ms (min / median):", repeat,
              threads > 0 ? std::to_string(threads).c_str() : "all");
  for (std::size_t k = 0; k < stages.size(); ++k) {
    std::vector<double> t = times[k];
    std::sort(t.begin(), t.end());
    std::printf(" %s %.1f / %.1f;", stages[k].c_str(), 1e3 * t.front(), 1e3 * t[t.size() / 2]);
  }
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "speed";
  const bool set_speed = mode == "speed" && !ArgS(argc, argv, "--manifest", "").empty();
  if (mode == "decode" || mode == "match" || mode == "speed") {
    // Freed blocks stay in the process, as in `ramtk scan` (tools/huge_pages.h): without it each
    // repetition's fresh maps cost page faults that the scan does not pay, and the decode
    // stages measured 2-3x slower (vision_scan_speed sets the same, for the same reason).
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  }
  if (set_speed)
    return SetSpeed(ArgS(argc, argv, "--manifest", ""), Arg(argc, argv, "--repeat", 3), Arg(argc, argv, "--float", 0));
  if (mode == "speed")
    return Speed(ArgS(argc, argv, "--preset", "small"), Arg(argc, argv, "--repeat", 1),
                 Arg(argc, argv, "--supersampling", 0));
  if (mode == "limb") return Limb(Vec3(0, 0, 700), Arg(argc, argv, "--seed", 1), Arg(argc, argv, "--noise", 1) != 0);
  if (mode == "set") return SetErrors(ArgS(argc, argv, "--manifest", ""), Arg(argc, argv, "--phase-filter", 0));
  if (mode == "decode") return DecodeStages(ArgS(argc, argv, "--manifest", ""), Arg(argc, argv, "--repeat", 5));
  if (mode == "match")
    return MatchPasses(ArgS(argc, argv, "--manifest", ""), Arg(argc, argv, "--repeat", 5),
                       Arg(argc, argv, "--threads", 0), Arg(argc, argv, "--rectified-back-pass", -1),
                       Arg(argc, argv, "--noise-term", 1));
  if (mode == "accuracy")
    return Accuracy(Arg(argc, argv, "--first-pose", 0), Arg(argc, argv, "--poses", 20), Arg(argc, argv, "--seeds", 50),
                    Arg(argc, argv, "--rectified-back-pass", -1), Arg(argc, argv, "--state-kernel", 0) != 0);
  std::fprintf(
      stderr,
      "usage: vision_scan_bench speed [--preset small|thesis] [--repeat N] [--supersampling S] | speed --manifest "
      "SET/manifest.json [--repeat N] [--float 1] | accuracy [--first-pose K] [--poses P] [--seeds S] "
      "[--rectified-back-pass 0|1] | "
      "limb [--seed N] [--noise 0|1] | set --manifest SET/manifest.json [--phase-filter R] | decode --manifest "
      "SET/manifest.json [--repeat N] | match --manifest SET/manifest.json [--repeat N] [--threads T] "
      "[--rectified-back-pass 0|1]\n");
  return 2;
}
