// The scan pipeline: decode -> match -> triangulate -> sphere fit (scan.h).
#include "ramtk/vision/scan/scan.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/decode/detail/test_hooks.h"
#include "ramtk/vision/stereo/cloud_noise.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan_monocular.h"
#include "scan_fit.h"
#include "scan_frames.h"

namespace ramtk::vision {
using detail::SetFrames;
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

bool Report(const ScanOptions& o, const std::string& stage, std::size_t done, std::size_t total) {
  return !o.progress || o.progress({stage, done, total});
}

}  // namespace

ScanOptions::ScanOptions() {
  sphere.radius_mm = 19.05;  // the 38.1 mm precision ball
  // A triangulated point moves only along its left-camera ray (the left pixel is fixed; the
  // phase noise moves the match along the epipolar curve): the fit measures each point's error
  // along that ray (kAlongRay; a distance along the normal is biased by such noise, docs/scan.md).
  sphere.noise_model = PointNoiseModel::kAlongRay;
  sphere.viewpoint_mm = Eigen::Vector3d::Zero();
  sphere.perpendicular_sigma_ratio = 0.02;
  // Beyond 60 deg from the left camera's line of sight the noise biases the triangulated depth
  // (second order in the phase noise, >= 3 um along the ray at 60-80 deg on the simulated ball,
  // bench/vision_scan_bench limb); below 60 deg it stays under 1 um (docs/scan.md).
  sphere.max_view_angle_deg = 60;
  // The scan reads only the coordinate, its sigma, the modulation and the mask.
  decode.keep_diagnostic_maps = false;
}

std::string ScanOptions::Validate() const {
  if (left_camera.empty() || right_camera.empty() || left_camera == right_camera)
    return "left_camera: the left and right camera names must differ and not be empty";
  if (std::string p = decode.Validate(); !p.empty()) return "decode." + p;
  if (std::string p = match.Validate(); !p.empty()) return "match." + p;
  if (std::string p = triangulation.Validate(); !p.empty()) return "triangulation." + p;
  if (std::string p = projector.Validate(); !p.empty()) return "projector." + p;
  if (fit_spheres)
    if (std::string p = sphere.Validate(); !p.empty()) return "sphere." + p;
  if (std::string p = roi.Validate(); !p.empty()) return p;  // its fields are named roi.*
  if (roi.mode != ScanRoiOptions::Mode::kFull && !fit_spheres)
    return "roi: a window around the ball needs the sphere fit (fit_spheres)";
  if (!(max_sphere_variance_factor >= 1)) return "max_sphere_variance_factor: must be >= 1";
  return "";
}

std::string ScanSummary::BriefReport() const {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(4);
  s << "scan " << message << ": " << triangulation.points << " points";
  if (termination == Termination::kCancelled) return s.str();
  if (spheres.spheres.empty()) {
    if (!spheres.no_sphere_reason.empty()) s << "; " << spheres.no_sphere_reason;
    return s.str();
  }
  for (std::size_t i = 0; i < spheres.spheres.size(); ++i) {
    const SphereResult& r = spheres.spheres[i];
    const Eigen::Vector3d sig = r.CentreSigma();
    s << "; ball_in_left_camera" << (spheres.spheres.size() > 1 ? "[" + std::to_string(i) + "]" : "") << " ("
      << r.centre_mm.x() << ", " << r.centre_mm.y() << ", " << r.centre_mm.z() << ") mm +- (" << sig.x() * 1000 << ", "
      << sig.y() * 1000 << ", " << sig.z() * 1000 << ") um, radius " << r.radius_mm << " mm, rms " << r.rms_mm * 1000
      << " um, " << r.num_points << " pts";
  }
  return s.str();
}

namespace {

// ScanDecoded on cameras it may release: each map is dropped as soon as no later stage reads it
// (the right camera after matching, the left one but its modulation before triangulation, the
// rest and the matches after it), so the
// sphere fit does not run beside them. Memory is returned only where the caller holds no other
// reference to the maps (cv::Mat counts them).
ScanResult ScanDecodedReleasing(const StereoCalibration& calibration, DecodedCamera left, DecodedCamera right,
                                double period, const ScanOptions& options, const std::string& calibration_path) {
  ScanResult result;
  ScanSummary& sum = result.summary;
  sum.calibration = calibration_path;
  sum.calibration_rms_px = calibration.rms_px;
  sum.calibration_parameter_std = calibration.parameter_std;
  sum.left = left.summary;
  sum.right = right.summary;
  sum.width = left.coordinate.cols;
  sum.height = left.coordinate.rows;
  sum.windows = FullFrameWindows(calibration);

  auto t0 = std::chrono::steady_clock::now();
  StereoMatchOptions mo = options.match;
  mo.progress = {};
  mo.right_pixels = false;  // the cloud needs the depths only
  mo.sigma_map = false;     // the points carry their own sigma (StereoMatch::point_sigma_mm)
  StereoMatch match = MatchStereo(calibration, left, right, period, mo, calibration_path);
  right = DecodedCamera();
  sum.match = match.summary;
  sum.match_s = Seconds(t0);
  if (!Report(options, "match", 3, 5)) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return result;
  }

  t0 = std::chrono::steady_clock::now();
  TriangulationOptions to = options.triangulation;
  // Triangulation reads only the left modulation (the points' quality) and summary: the other
  // left maps go first (~74 MB on a thesis frame, the peak being the cloud beside the matches).
  {
    DecodedCamera kept;
    kept.summary = left.summary;
    kept.modulation = left.modulation;
    left = std::move(kept);
  }
  result.cloud = TriangulateMatches(calibration, left, match, to, &sum.triangulation, &result.depth);
  left = DecodedCamera();
  match = StereoMatch();
  sum.triangulate_s = Seconds(t0);
  if (!Report(options, "triangulate", 4, 5)) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return result;
  }

  FitSpheresBesideCloud(result, options);
  RAMTK_LOG(kDebug) << sum.match.BriefReport();
  RAMTK_LOG(kDebug) << sum.triangulation.BriefReport();
  return result;
}

}  // namespace

// The sphere fit (with its gates and the neighbour-correlation inflation) on result.cloud, beside
// ScanOptions::on_cloud, into result.summary (scan_fit.h).
void FitSpheresBesideCloud(ScanResult& result, const ScanOptions& options) {
  ScanSummary& sum = result.summary;
  auto fit = [&] {
    const auto fit_t0 = std::chrono::steady_clock::now();
    SphereFitOptions so = options.sphere;
    so.progress = {};
    if (result.cloud.size() < static_cast<std::size_t>(so.min_points)) {
      sum.spheres.termination = Termination::kNoResult;
      sum.spheres.message = "no sphere found";
      sum.spheres.input_points = static_cast<int>(result.cloud.size());
      sum.spheres.no_sphere_reason = "too few points: the cloud has " + std::to_string(result.cloud.size()) +
                                     ", a sphere needs at least " + std::to_string(so.min_points);
    } else {
      sum.spheres = FindSpheres(result.cloud.points_in_left, result.cloud.sigma_mm, so);
    }
    // Gates: a "sphere" that does not fit its points at their noise level, or whose radius is
    // off the prior, is not reported as a centre.
    std::vector<SphereResult> kept;
    std::string why;
    for (const SphereResult& r : sum.spheres.spheres) {
      std::ostringstream reason;
      reason.precision(4);
      if (!(r.radius_mm > 0 && r.centre_mm.allFinite() && r.centre_covariance_mm2.allFinite())) {
        reason << "rejected a sphere candidate: its fit is not finite (radius " << r.radius_mm << " mm)";
      } else if (!(r.variance_factor <= options.max_sphere_variance_factor)) {
        reason << "rejected a sphere candidate (radius " << r.radius_mm << " mm): surface RMS " << r.rms_mm * 1000
               << " um is " << std::sqrt(r.variance_factor) << "x the points' predicted noise (variance factor "
               << r.variance_factor << " > " << options.max_sphere_variance_factor << ")";
      } else if (so.radius_mm > 0 && !so.fix_radius && std::abs(r.radius_mm - so.radius_mm) > so.radius_tolerance_mm) {
        reason << "rejected a sphere candidate: radius " << r.radius_mm << " mm is off the prior " << so.radius_mm
               << " +- " << so.radius_tolerance_mm << " mm";
      } else {
        kept.push_back(r);
        continue;
      }
      why = reason.str();
      RAMTK_LOG(kInfo) << why;
    }
    // Neighbouring pixels' noise is correlated (blur; right pixels shared through the bilinear
    // interpolation), which the fit's independent-point covariance leaves out: inflate it by the
    // factor estimated from the residuals' correlation at pixel lags <= 2.
    if (result.cloud.left_pixels.size() == result.cloud.size() && !result.cloud.sigma_mm.empty()) {
      for (SphereResult& r : kept) {
        std::vector<Eigen::Vector2f> px;
        std::vector<double> z;
        for (int i : r.inlier_indices) {
          const Eigen::Vector3d p = result.cloud.points_in_left[i].cast<double>();
          const Eigen::Vector3d normal = (p - r.centre_mm).normalized();
          const double c = normal.dot((p - so.viewpoint_mm).normalized());
          const double ratio = so.noise_model != PointNoiseModel::kIsotropic ? so.perpendicular_sigma_ratio : 1.0;
          const double sigma_n = result.cloud.sigma_mm[i] * std::sqrt(c * c + ratio * ratio * std::max(0.0, 1 - c * c));
          if (!(sigma_n > 0)) continue;
          px.push_back(result.cloud.left_pixels[i]);
          z.push_back(((p - r.centre_mm).norm() - r.radius_mm) / sigma_n);
        }
        // A phase filter of radius R shares noise between pixels up to 2R apart.
        const int lag = 2 + 2 * options.decode.coordinate_filter.radius_px;
        const NeighbourCorrelation nc = EstimateNeighbourCorrelation(px, z, cv::Size(sum.width, sum.height), lag);
        // Never below 1: on white residuals the estimate scatters around 1 and would shrink the
        // independent-point covariance half the time.
        const double factor = std::max(1.0, nc.factor);
        r.correlation_factor = factor;
        r.centre_covariance_mm2 *= factor;
        r.radius_sigma_mm *= std::sqrt(factor);
      }
    }
    if (kept.size() != sum.spheres.spheres.size()) {
      if (kept.empty()) {
        sum.spheres.termination = Termination::kNoResult;
        sum.spheres.message = "no sphere found";
        sum.spheres.no_sphere_reason = why;
      }
    }
    sum.spheres.spheres = kept;
    sum.fit_s = Seconds(fit_t0);
    if (sum.spheres.spheres.empty()) {
      sum.termination = Termination::kNoResult;
      sum.message = "no sphere found";
    }
  };
  // The outputs' writer (ScanOptions::on_cloud) beside the fit, whose serial parts leave a core idle.
  tbb::parallel_invoke(
      [&] {
        if (options.fit_spheres) fit();
      },
      [&] {
        if (options.on_cloud) options.on_cloud(result.cloud, result.depth);
      });
  if (options.fit_spheres) Report(options, "fit", 5, 5);
}

ScanResult ScanDecoded(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
                       double period, const ScanOptions& options, const std::string& calibration_path) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  return ScanDecodedReleasing(calibration, left, right, period, options, calibration_path);
}

namespace {

ScanResult Cancelled() {
  ScanResult r;
  r.summary.termination = Termination::kCancelled;
  r.summary.message = "cancelled";
  return r;
}

// Decodes the windows of both cameras' frames and runs the rest of the pipeline on them; the
// cloud's pixels and the depth image are returned in full-frame pixels. With `last_use`, each
// camera's frames are released once read (SetFrames::Release), so they are dropped once decoded.
ScanResult ScanWindowsOfFrames(const FringeManifest& m, const StereoCalibration& calibration, SetFrames& frames,
                               bool last_use, double full_scale, const ScanWindows& windows, const ScanOptions& options,
                               const std::string& calibration_path) {
  const ScanWindows full = FullFrameWindows(calibration);
  const bool whole = windows.left == full.left && windows.right == full.right;
  const StereoCalibration cropped = whole ? calibration : CropCalibration(calibration, windows);
  auto t0 = std::chrono::steady_clock::now();
  DecodeOptions dopt = options.decode;
  dopt.progress = {};
  auto decode = [&](int camera, const cv::Rect& window, const std::string& name) {
    const std::vector<cv::Mat> f = frames.Read(camera, window, 1);
    if (last_use) frames.Release(camera);
    return DecodeFrames(m, f, full_scale, dopt, name);
  };
  DecodedCamera left = decode(0, windows.left, options.left_camera);
  if (!Report(options, "decode " + options.left_camera, 1, 5)) return Cancelled();
  DecodedCamera right = decode(1, windows.right, options.right_camera);
  const double decode_s = Seconds(t0);
  if (!Report(options, "decode " + options.right_camera, 2, 5)) return Cancelled();
  const double period = left.summary.period_px;
  ScanResult result =
      ScanDecodedReleasing(cropped, std::move(left), std::move(right), period, options, calibration_path);
  result.summary.decode_s = decode_s;
  result.summary.windows = windows;
  if (!whole) {
    const Eigen::Vector2f shift(static_cast<float>(windows.left.x), static_cast<float>(windows.left.y));
    for (Eigen::Vector2f& px : result.cloud.left_pixels) px += shift;
    if (!result.depth.empty()) {
      // The full-frame map (NaN outside the window), its rows filled in parallel: on a thesis
      // frame it is 33 MB of fresh pages, whose first touch cost ~20 ms on one thread.
      cv::Mat depth(calibration.left.height, calibration.left.width, CV_32F);
      const cv::Rect w = windows.left;
      const cv::Mat& window_depth = result.depth;
      tbb::parallel_for(tbb::blocked_range<int>(0, depth.rows, 64), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
          float* row = depth.ptr<float>(y);
          std::fill_n(row, depth.cols, std::numeric_limits<float>::quiet_NaN());
          if (y >= w.y && y < w.y + w.height) std::copy_n(window_depth.ptr<float>(y - w.y), w.width, row + w.x);
        }
      });
      result.depth = depth;
    }
    result.summary.width = calibration.left.width;
    result.summary.height = calibration.left.height;
  }
  return result;
}

// The coarse pass of roi auto: every stride-th pixel through the whole pipeline; the spheres it
// finds (empty, with the reason in *why, if none).
std::vector<Sphere> CoarseSpheres(const FringeManifest& m, const StereoCalibration& calibration,
                                  const SetFrames& frames, double full_scale, int stride, const ScanOptions& options,
                                  std::string* why) {
  const StereoCalibration coarse = SubsampleCalibration(calibration, stride);
  ScanOptions o = options;
  o.progress = {};
  o.roi = ScanRoiOptions();
  o.fit_spheres = true;
  o.on_cloud = {};
  // A window only needs the centre to a fraction of a millimetre: no nonlinearity correction,
  // and the variance gate is left to the windowed pass (the coarse cloud's noise model is not
  // the point here); the radius gate stays, so a backdrop is not taken for the ball.
  o.decode.correct_nonlinearity = false;
  o.max_sphere_variance_factor = std::numeric_limits<double>::max();
  // No left-right check (it is a second, right-to-left match pass): a wrong crossing left in the
  // coarse cloud is an outlier to the sphere search, which the windowed pass then checks.
  o.match.lr_tolerance_px = 0;
  // The coarse ball has ~1/stride^2 of the points; a few dozen fix its centre to ~0.1 mm.
  o.sphere.min_points = std::min(o.sphere.min_points, 50);
  const ScanWindows full = FullFrameWindows(calibration);
  SetFrames subsampled(frames.Read(0, full.left, stride), frames.Read(1, full.right, stride));
  const ScanResult r = ScanWindowsOfFrames(m, coarse, subsampled, true, full_scale, FullFrameWindows(coarse), o, "");
  std::vector<Sphere> spheres;
  for (const SphereResult& s : r.summary.spheres.spheres) {
    Sphere sp;
    sp.centre_in_left = s.centre_mm;
    sp.radius = s.radius_mm;
    spheres.push_back(sp);
  }
  if (spheres.empty())
    *why = "the coarse pass (stride " + std::to_string(stride) + ", " + std::to_string(r.summary.triangulation.points) +
           " points) found no sphere" +
           (r.summary.spheres.no_sphere_reason.empty() ? "" : ": " + r.summary.spheres.no_sphere_reason);
  return spheres;
}

}  // namespace

namespace {

// The options for a windowed pass: the match's depth ranges (left and right camera frames)
// narrowed to the spheres' depth +- (radius + margin_mm + depth_margin_mm), inside the match's
// own range. Unchanged without spheres, with depth_margin_mm < 0, or if the window would be empty.
ScanOptions WithDepthWindow(const ScanOptions& options, const StereoCalibration& calibration,
                            const std::vector<Sphere>& spheres) {
  ScanOptions o = options;
  if (spheres.empty() || options.roi.depth_margin_mm < 0) return o;
  double l0 = 1e300, l1 = -1e300, r0 = 1e300, r1 = -1e300;
  for (const Sphere& s : spheres) {
    const double reach = s.radius + options.roi.margin_mm + options.roi.depth_margin_mm;
    const double zl = s.centre_in_left.z(), zr = (calibration.right_from_left * s.centre_in_left).z();
    l0 = std::min(l0, zl - reach), l1 = std::max(l1, zl + reach);
    r0 = std::min(r0, zr - reach), r1 = std::max(r1, zr + reach);
  }
  l0 = std::max(l0, options.match.min_depth_mm), l1 = std::min(l1, options.match.max_depth_mm);
  if (!(l0 > 0 && l1 > l0 && r0 > 0 && r1 > r0)) return o;
  o.match.min_depth_mm = l0, o.match.max_depth_mm = l1;
  if (options.match.right_max_depth_mm > 0) {
    r0 = std::max(r0, options.match.right_min_depth_mm), r1 = std::min(r1, options.match.right_max_depth_mm);
    if (!(r1 > r0)) return options;
  }
  o.match.right_min_depth_mm = r0, o.match.right_max_depth_mm = r1;
  return o;
}

// ScanFrames on frames it may drop once they are no longer needed (ScanWindowsOfFrames); their
// sizes are the calibration's (the callers check).
ScanResult ScanFramesReleasing(const FringeManifest& m, const StereoCalibration& calibration, SetFrames frames,
                               double full_scale, const ScanOptions& options, const std::string& calibration_path) {
  const ScanRoiOptions& roi = options.roi;
  const ScanWindows full = FullFrameWindows(calibration);
  ScanWindows windows = full;
  std::string source = "full", fallback_why;
  std::vector<Sphere> around;  // the spheres the windows are built around
  auto t0 = std::chrono::steady_clock::now();
  if (roi.mode == ScanRoiOptions::Mode::kAuto) {
    constexpr int kCoarseWidth = 350;
    const int stride = roi.coarse_stride > 0 ? roi.coarse_stride
                                             : std::max(2, (calibration.left.width + kCoarseWidth - 1) / kCoarseWidth);
    // A ball too small for this stride gives too few coarse points: halve the stride (down to 2)
    // before falling back to the full frame.
    std::vector<Sphere> found;
    for (int s = stride;; s /= 2) {
      fallback_why.clear();
      found = CoarseSpheres(m, calibration, frames, full_scale, s, options, &fallback_why);
      source = "auto (coarse pass, stride " + std::to_string(s) + ")";
      if (!found.empty() || s / 2 < 2) break;
      RAMTK_LOG(kInfo) << "scan --roi auto: " << fallback_why << "; trying stride " << s / 2;
      frames.LoadWhole();  // a finer coarse pass, perhaps the full frame after it
    }
    if (!found.empty()) {
      windows = WindowsAroundSpheres(calibration, found, roi.margin_mm, roi.margin_px);
      around = found;
    }
  } else if (roi.mode == ScanRoiOptions::Mode::kPredicted) {
    source = "predicted";
    std::vector<Sphere> predicted;
    for (const Vec3& c : roi.predicted_centres_in_left_mm) {
      Sphere s;
      s.centre_in_left = c;
      s.radius = options.sphere.radius_mm > 0 ? options.sphere.radius_mm : 19.05;
      predicted.push_back(s);
    }
    windows = WindowsAroundSpheres(calibration, predicted, roi.margin_mm, roi.margin_px);
    around = predicted;
  }
  const double roi_s = Seconds(t0);
  const ScanOptions windowed_options = WithDepthWindow(options, calibration, around);
  if (!fallback_why.empty() && !roi.fall_back_to_full) {
    ScanResult r;
    r.summary.termination = Termination::kNoResult;
    r.summary.message = "no sphere found";
    r.summary.spheres.termination = Termination::kNoResult;
    r.summary.spheres.message = "no sphere found";
    r.summary.spheres.no_sphere_reason = fallback_why;
    r.summary.roi_source = source;
    r.summary.frame_reads = frames.Reads();
    r.summary.roi_s = roi_s;
    r.summary.width = calibration.left.width, r.summary.height = calibration.left.height;
    return r;
  }
  const bool windowed = !(windows.left == full.left && windows.right == full.right);
  // The frames are needed again only for a fall-back to the full frame.
  const bool last_use = !windowed || !roi.fall_back_to_full;
  const ScanOptions& pass_options = windowed ? windowed_options : options;
  ScanResult result =
      ScanWindowsOfFrames(m, calibration, frames, last_use, full_scale, windows, pass_options, calibration_path);
  if (windowed && result.summary.termination == Termination::kNoResult && roi.fall_back_to_full) {
    fallback_why = "the windowed scan found no sphere" + (result.summary.spheres.no_sphere_reason.empty()
                                                              ? std::string()
                                                              : ": " + result.summary.spheres.no_sphere_reason);
    const double windowed_s =
        result.summary.decode_s + result.summary.match_s + result.summary.triangulate_s + result.summary.fit_s;
    result = ScanWindowsOfFrames(m, calibration, frames, true, full_scale, full, options, calibration_path);
    result.summary.roi_s = roi_s + windowed_s;
  } else {
    result.summary.roi_s = roi_s;
  }
  if (!fallback_why.empty()) {
    source += "; fell back to the full frame: " + fallback_why;
    RAMTK_LOG(kWarning) << "scan --roi: " << fallback_why << "; scanned the full frame";
  }
  result.summary.roi_source = source;
  result.summary.frame_reads = frames.Reads();
  return result;
}

}  // namespace

ScanResult ScanFrames(const FringeManifest& m, const StereoCalibration& calibration,
                      const std::vector<cv::Mat>& left_frames, const std::vector<cv::Mat>& right_frames,
                      double full_scale, const ScanOptions& options, const std::string& calibration_path) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  for (const auto* frames : {&left_frames, &right_frames}) {
    const CameraIntrinsics& k = frames == &left_frames ? calibration.left : calibration.right;
    for (const cv::Mat& f : *frames)
      if (f.cols != k.width || f.rows != k.height)
        throw InputError({calibration_path, 0, "image_size"},
                         "a frame is " + std::to_string(f.cols) + "x" + std::to_string(f.rows) +
                             ", the calibration's " + (frames == &left_frames ? "left" : "right") + " camera " +
                             std::to_string(k.width) + "x" + std::to_string(k.height));
  }
  return ScanFramesReleasing(m, calibration, SetFrames(left_frames, right_frames), full_scale, options,
                             calibration_path);
}

ScanResult ScanFringeSet(const std::string& manifest_path, const ScanOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  const bool reference_decode = detail::CurrentDecodeTestHooks().reference_path;
  const FringeManifest m = ReadFringeManifest(manifest_path);
  if (!m.projector_calibration.empty()) return ScanMonocularSet(m, options);
  for (const std::string& cam : {options.left_camera, options.right_camera})
    if (!m.cameras.count(cam))
      throw InputError({manifest_path, 0, "cameras." + cam}, "the set has no camera '" + cam + "'");
  std::string calib_path = options.calibration_path;
  if (calib_path.empty()) {
    if (m.calibration.empty())
      throw InputError({manifest_path, 0, "calibration"}, "the set names no calibration file; pass one (--calib)");
    calib_path = m.Resolve(m.calibration);
  }
  const StereoCalibration calibration = ReadStereoCalibration(calib_path);
  // A camera's frame `path` against the calibration's image size.
  auto check_size = [&](const std::string& cam, const std::string& path, const cv::Size& size) {
    const CameraIntrinsics& k = cam == options.left_camera ? calibration.left : calibration.right;
    if (size.width != k.width || size.height != k.height)
      throw InputError({calib_path, 0, "image_size"},
                       "the calibration's " + std::string(cam == options.left_camera ? "left" : "right") +
                           " camera is " + std::to_string(k.width) + "x" + std::to_string(k.height) + " but " + path +
                           " is " + std::to_string(size.width) + "x" + std::to_string(size.height));
  };
  // One camera's frames, checked against the calibration's image size.
  auto load = [&](const std::string& cam) {
    std::vector<std::string> paths;
    for (const std::string& f : m.cameras.at(cam)) paths.push_back(m.Resolve(f));
    // The fused decode reads 8/16-bit grey files as stored; the reference decode (a test hook) as float.
    ImageStack stack = LoadImageStack(paths, options.decode.dark_fraction, !reference_decode);
    check_size(cam, paths.front(), stack.frames.front().size());
    return stack;
  };
  // One camera's frames opened for reading by rows (image::FrameRows), checked against the
  // calibration's image size; empty if one of them cannot be read that way (it is then loaded whole).
  auto open_rows = [&](const std::string& cam) {
    const std::vector<std::string>& files = m.cameras.at(cam);
    std::vector<image::FrameRows> rows(files.size());
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string path = m.Resolve(files[i]);
      if (!rows[i].Open(path)) return std::vector<image::FrameRows>();
      check_size(cam, path, cv::Size(rows[i].width(), rows[i].height()));
    }
    return rows;
  };
  auto check_bits = [&](const ImageStack& left, const ImageStack& right) {
    if (left.bits_per_sample != right.bits_per_sample)
      throw InputError({manifest_path, 0, "cameras." + options.right_camera},
                       std::to_string(right.bits_per_sample) + "-bit images beside " +
                           std::to_string(left.bits_per_sample) + "-bit ones of camera " + options.left_camera);
  };
  ScanResult result;
  double load_s = 0;
  if (options.roi.mode == ScanRoiOptions::Mode::kFull) {
    // The whole frames: one camera at a time, loaded, decoded and dropped before the other is
    // loaded, so the set's samples are never all in memory at once (peak memory).
    auto t0 = std::chrono::steady_clock::now();
    ImageStack left_stack = load(options.left_camera);
    load_s = Seconds(t0);
    DecodeOptions dopt = options.decode;
    dopt.progress = {};
    t0 = std::chrono::steady_clock::now();
    DecodedCamera left = DecodeFrames(m, left_stack.frames, left_stack.full_scale, dopt, options.left_camera);
    std::vector<cv::Mat>().swap(left_stack.frames);
    double decode_s = Seconds(t0);
    if (!Report(options, "decode " + options.left_camera, 1, 5)) return Cancelled();
    t0 = std::chrono::steady_clock::now();
    ImageStack right_stack = load(options.right_camera);
    check_bits(left_stack, right_stack);
    load_s += Seconds(t0);
    t0 = std::chrono::steady_clock::now();
    DecodedCamera right = DecodeFrames(m, right_stack.frames, right_stack.full_scale, dopt, options.right_camera);
    std::vector<cv::Mat>().swap(right_stack.frames);
    decode_s += Seconds(t0);
    if (!Report(options, "decode " + options.right_camera, 2, 5)) return Cancelled();
    const double period = left.summary.period_px;
    result = ScanDecodedReleasing(calibration, std::move(left), std::move(right), period, options, calib_path);
    result.summary.decode_s = decode_s;
    result.summary.roi_source = "full";
  } else {
    // Windows: uncompressed 8-bit grey frames are read by rows as the passes need them, others
    // loaded whole.
    auto t0 = std::chrono::steady_clock::now();
    std::vector<image::FrameRows> left_rows, right_rows;
    if (options.read_rows_on_demand && !reference_decode) {
      left_rows = open_rows(options.left_camera);
      if (!left_rows.empty()) right_rows = open_rows(options.right_camera);
    }
    if (!right_rows.empty()) {
      load_s = Seconds(t0);
      result = ScanFramesReleasing(m, calibration, SetFrames(std::move(left_rows), std::move(right_rows)), 255.0,
                                   options, calib_path);
    } else {
      ImageStack left_stack = load(options.left_camera), right_stack = load(options.right_camera);
      check_bits(left_stack, right_stack);
      load_s = Seconds(t0);
      result =
          ScanFramesReleasing(m, calibration, SetFrames(std::move(left_stack.frames), std::move(right_stack.frames)),
                              left_stack.full_scale, options, calib_path);
    }
  }
  result.summary.set = manifest_path;
  if (result.summary.frame_reads.empty()) result.summary.frame_reads = "whole";
  result.summary.load_s = load_s;
  return result;
}

std::string ScanSummaryToJson(const ScanSummary& s) {
  using nlohmann::json;
  json j;
  j["format"] = "ramtk-scan-summary";
  j["version"] = 1;
  j["set"] = s.set;
  j["calibration"] = s.calibration;
  if (std::isfinite(s.calibration_rms_px)) j["calibration_rms_px"] = s.calibration_rms_px;
  if (!s.calibration_parameter_std.empty()) {
    j["calibration_parameter_std"] = s.calibration_parameter_std;
    if (s.calibration_parameter_std.size() == 24)
      j["calibration_parameter_std_order"] = camera::kCalibParameterStdOrder;
  }
  j["frame"] = kScanFrame;
  j["termination"] = s.message;
  j["image_size"] = {s.width, s.height};
  j["decode"] = {{"left", s.left.BriefReport()}, {"right", s.right.BriefReport()}};
  j["match"] = {{"left_valid", s.match.left_valid},
                {"matched", s.match.matched},
                {"rejected_noisy", s.match.rejected_noisy},
                {"rejected_no_match", s.match.rejected_no_match},
                {"rejected_left_right", s.match.rejected_lr},
                {"rejected_no_back_match", s.match.rejected_no_back_match},
                {"back_pass", s.match.back_pass},
                {"median_sigma_px", s.match.median_sigma_px}};
  j["points"] = s.triangulation.points;
  j["median_point_sigma_mm"] = s.triangulation.median_sigma_mm;
  j["depth_range_mm"] = {s.triangulation.depth_min_mm, s.triangulation.depth_max_mm};
  j["spheres"] = json::parse(SphereFitToJson(s.spheres, kScanFrame, -1));
  j["roi"] = {{"source", s.roi_source},
              {"frame_reads", s.frame_reads},
              {"left", {s.windows.left.x, s.windows.left.y, s.windows.left.width, s.windows.left.height}},
              {"right", {s.windows.right.x, s.windows.right.y, s.windows.right.width, s.windows.right.height}}};
  j["seconds"] = {{"load", s.load_s},
                  {"roi", s.roi_s},
                  {"decode", s.decode_s},
                  {"match", s.match_s},
                  {"triangulate", s.triangulate_s},
                  {"fit", s.fit_s}};
  if (s.mode != "stereo") {
    // One camera against the projector: no right camera, no stereo match.
    j["mode"] = s.mode;
    j["decode"] = {{"camera", s.left.BriefReport()}};
    j.erase("match");
    j["projector_triangulation"] = {{"coded_pixels", s.projector.coded_pixels},
                                    {"points", s.projector.points},
                                    {"rejected_geometry", s.projector.rejected_geometry},
                                    {"rejected_residual", s.projector.rejected_residual}};
  }
  j["report"] = s.BriefReport();
  return j.dump(2) + "\n";
}

std::vector<Sphere> ReadTruthSpheres(const std::string& path) {
  nlohmann::json j = ParseJsonText(ReadTextFile(path), path);
  if (!j.contains("spheres") || !j["spheres"].is_array())
    throw InputError({path, 0, "spheres"}, "missing (expected the truth.json of ramtk simulate fringe)");
  std::vector<Sphere> out;
  for (std::size_t i = 0; i < j["spheres"].size(); ++i) {
    const auto& e = j["spheres"][i];
    const std::string field = "spheres[" + std::to_string(i) + "]";
    try {
      Sphere s;
      s.name = e.value("name", "sphere" + std::to_string(i));
      const auto& c = e.at("centre_in_left_mm");
      s.centre_in_left = Vec3(c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>());
      s.radius = e.at("radius_mm").get<double>();
      out.push_back(s);
    } catch (const nlohmann::json::exception& ex) {
      throw InputError({path, 0, field}, std::string("expected centre_in_left_mm [x,y,z] and radius_mm: ") + ex.what());
    }
  }
  return out;
}

std::vector<int> MatchTruthSpheres(const SphereFitSummary& fitted, const std::vector<Sphere>& truth) {
  std::vector<int> idx;
  for (const SphereResult& r : fitted.spheres) {
    int best = -1;
    double best_d = 1e300;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const double d = (truth[k].centre_in_left - r.centre_mm).norm();
      if (d < best_d) best_d = d, best = static_cast<int>(k);
    }
    idx.push_back(best);
  }
  return idx;
}

}  // namespace ramtk::vision
