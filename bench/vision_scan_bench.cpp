// Scan benchmark and accuracy sweep.
//
//   vision_scan_bench speed [--preset small|thesis] [--repeat N]
//       decode + match + triangulate + fit of one simulated stereo set, each stage's share, and
//       OpenCV's cv::triangulatePoints on the same matches as a peer (ratio).
//   vision_scan_bench accuracy [--poses P] [--seeds S]
//       thesis geometry (the small preset = 640x512 windows of the 3312x2488 cameras cropped
//       around the ball, ~700 mm), the ball at P poses over the field, S noise seeds each: the
//       noise-free radiance is rendered once per pose and only the sensor noise is redrawn per
//       seed. Prints centre / radius errors against the truth and the predicted centre sigma
//       against the observed scatter.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode.h"
#include "ramtk/vision/fringe_simulator.h"
#include "ramtk/vision/scan.h"
#include "scan_sim.h"

using namespace ramtk;
using namespace ramtk::vision;
using Clock = std::chrono::steady_clock;

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

// Images of one camera with fresh sensor noise on a noise-free render.
SimulatedCamera Renoise(const FringeSimulationConfig& c, const SimulatedCamera& clean, int camera) {
  SimulatedCamera out;
  out.truth = clean.truth;
  SensorOptions sensor = c.sensor;
  sensor.blur_sigma_px = c.effects.defocus;
  for (std::size_t i = 0; i < clean.truth.radiance.size(); ++i)
    out.images.push_back(
        ApplySensor(clean.truth.radiance[i], 1.0, sensor, c.seed, static_cast<std::uint64_t>(camera) * 1000 + i));
  return out;
}

int Speed(const std::string& preset, int repeat) {
  FringeSimulationConfig c = MakeFringePreset(preset);
  std::printf("rendering the %s preset...\n", preset.c_str());
  const SimulatedCamera l = SimulateCamera(c, 0), r = SimulateCamera(c, 1);
  const StereoCalibration calib = WrittenCalibration(c);
  for (int k = 0; k < repeat; ++k) {
    auto t = Clock::now();
    const DecodedCamera dl = testing::DecodeSimulated(c, l), dr = testing::DecodeSimulated(c, r);
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
    // Peer: cv::triangulatePoints (DLT on undistorted points) on the same matches.
    std::vector<cv::Point2d> pl, pr;
    for (std::size_t i = 0; i < res.cloud.size(); ++i) {
      const int x = static_cast<int>(res.cloud.left_pixels[i].x()), y = static_cast<int>(res.cloud.left_pixels[i].y());
      pl.emplace_back(x, y);
      (void)y;
    }
    // Right positions: re-project our points (they lie on the matched right positions to ~1e-9 px).
    for (std::size_t i = 0; i < res.cloud.size(); ++i) pr.emplace_back(0, 0);
    t = Clock::now();
    TriangulationSummary ts;
    (void)ts;
    std::vector<cv::Point2d> ul, ur;
    cv::Mat K1, K2, D1, D2;
    cv::eigen2cv(Eigen::Matrix3d(calib.left.K()), K1);
    cv::eigen2cv(Eigen::Matrix3d(calib.right.K()), K2);
    D1 = (cv::Mat_<double>(1, 5) << calib.left.distortion.k1, calib.left.distortion.k2, calib.left.distortion.p1,
          calib.left.distortion.p2, calib.left.distortion.k3);
    D2 = (cv::Mat_<double>(1, 5) << calib.right.distortion.k1, calib.right.distortion.k2, calib.right.distortion.p1,
          calib.right.distortion.p2, calib.right.distortion.k3);
    for (std::size_t i = 0; i < res.cloud.size(); ++i) {
      const Vec3 X = res.cloud.points_in_left[i].cast<double>();
      const Vec2 q = ProjectPoint(calib.right, calib.right_from_left * X);
      pr[i] = cv::Point2d(q.x(), q.y());
    }
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
  return 0;
}

int Accuracy(int poses, int seeds) {
  std::vector<double> e2, rad, ratio;
  double max_bias = 0;
  for (int p = 0; p < poses; ++p) {
    // Poses over the field: a 5 x 4 grid in x, y (+-40, +-30 mm) with z alternating 680 / 720 mm.
    const int ix = p % 5, iy = (p / 5) % 4;
    const Vec3 ball(poses == 1 ? 0 : -40 + 20 * ix, poses == 1 ? 0 : -30 + 20 * iy, p % 2 ? 720 : 680);
    FringeSimulationConfig c = MakeFringePreset("small", ball);
    c.sensor.noise = false;
    const SimulatedCamera l0 = SimulateCamera(c, 0), r0 = SimulateCamera(c, 1);
    c.sensor.noise = true;
    const StereoCalibration calib = WrittenCalibration(c);
    std::vector<Vec3> centres;
    Vec3 sigma_pred = Vec3::Zero();
    double rad_mean = 0;
    for (int s = 0; s < seeds; ++s) {
      c.seed = 1000 + s;
      const SimulatedCamera l = Renoise(c, l0, 0), r = Renoise(c, r0, 1);
      const DecodedCamera dl = testing::DecodeSimulated(c, l), dr = testing::DecodeSimulated(c, r);
      const ScanResult res = ScanDecoded(calib, dl, dr, dl.summary.period_px, ScanOptions{});
      if (res.summary.spheres.spheres.empty()) {
        std::printf("pose %d seed %d: %s\n", p, s, res.summary.BriefReport().c_str());
        continue;
      }
      const SphereResult& b = res.summary.spheres.spheres[0];
      const Vec3 e = b.centre_mm - ball;
      centres.push_back(b.centre_mm);
      e2.push_back(e.squaredNorm());
      rad.push_back(b.radius_mm - 19.05);
      rad_mean += rad.back() / seeds;
      sigma_pred += b.CentreSigma() / seeds;
    }
    Vec3 mean = Vec3::Zero();
    for (const Vec3& x : centres) mean += x / centres.size();
    Vec3 sd = Vec3::Zero();
    for (const Vec3& x : centres) sd += (x - mean).cwiseAbs2() / std::max<std::size_t>(1, centres.size() - 1);
    sd = sd.cwiseSqrt();
    const Vec3 bias = mean - ball;
    max_bias = std::max(max_bias, bias.norm());
    for (int k = 0; k < 3; ++k) ratio.push_back(sigma_pred[k] / sd[k]);
    std::printf(
        "pose %2d ball (%.0f, %.0f, %.0f): bias (%+.2f, %+.2f, %+.2f) um, scatter (%.2f, %.2f, %.2f) um, "
        "predicted sigma (%.2f, %.2f, %.2f) um, radius error %+.2f um\n",
        p, ball.x(), ball.y(), ball.z(), 1000 * bias.x(), 1000 * bias.y(), 1000 * bias.z(), 1000 * sd.x(),
        1000 * sd.y(), 1000 * sd.z(), 1000 * sigma_pred.x(), 1000 * sigma_pred.y(), 1000 * sigma_pred.z(),
        1000 * rad_mean);
    std::fflush(stdout);
  }
  double se = 0, sr = 0;
  for (double x : e2) se += x;
  for (double x : rad) sr += x;
  std::sort(ratio.begin(), ratio.end());
  std::printf(
      "summary: %zu scans; centre error RMS %.2f um (largest pose bias %.2f um); mean radius error %+.2f um; "
      "predicted/observed centre sigma per axis: median %.2f, range %.2f..%.2f\n",
      e2.size(), 1000 * std::sqrt(se / std::max<std::size_t>(1, e2.size())), 1000 * max_bias,
      1000 * sr / std::max<std::size_t>(1, rad.size()), ratio.empty() ? 0 : ratio[ratio.size() / 2],
      ratio.empty() ? 0 : ratio.front(), ratio.empty() ? 0 : ratio.back());
  return e2.empty() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "speed";
  if (mode == "speed") return Speed(ArgS(argc, argv, "--preset", "small"), Arg(argc, argv, "--repeat", 1));
  if (mode == "accuracy") return Accuracy(Arg(argc, argv, "--poses", 20), Arg(argc, argv, "--seeds", 50));
  std::fprintf(stderr, "usage: vision_scan_bench speed [--preset small|thesis] | accuracy [--poses P] [--seeds S]\n");
  return 2;
}
