// The scan pipeline: decode -> match -> triangulate -> sphere fit (scan.h).
#include "ramtk/vision/scan/scan.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <unistd.h>

#include <algorithm>
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
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/projector/tri_view.h"
#include "ramtk/vision/scan/scan_monocular.h"
#include "ramtk/vision/stereo/cloud_noise.h"
#include "scan_fit.h"
#include "scan_frames.h"
#include "scan_pass.h"

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
  if (tri_view && roi.mode != ScanRoiOptions::Mode::kFull)
    return "tri_view: the projector fills the whole frame's pixels (roi must be full)";
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
  if (tri_view) s << " (" << stereo_points << " stereo + " << projector_points << " projector)";
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
      << sig.y() * 1000 << ", " << sig.z() * 1000 << ") um";
    const Eigen::Vector3d& bound = r.crlb_centre_sigma_mm;
    if (bound.minCoeff() > 0)
      s << " (CRLB " << bound.x() * 1000 << ", " << bound.y() * 1000 << ", " << bound.z() * 1000 << " um)";
    s << ", radius " << r.radius_mm << " mm, rms " << r.rms_mm * 1000 << " um, " << r.num_points << " pts";
  }
  return s.str();
}

namespace {

using detail::ScanPass;
using detail::ScanStageOptions;
using detail::StageOptionsOf;

// `r` (by default empty) marked cancelled.
ScanResult Cancelled(ScanResult r = ScanResult()) {
  r.summary.termination = Termination::kCancelled;
  r.summary.message = "cancelled";
  return r;
}

// ScanDecoded on cameras it may release: each map is dropped as soon as no later stage reads it
// (the right camera after matching, the left one but its modulation before triangulation, the
// rest and the matches after it), so the sphere fit does not run beside them. Memory is
// returned only where the caller holds no other reference to the maps (cv::Mat counts them).
// Tri-view: the left pixels without a stereo point triangulated against the projector (`projector`
// = the left camera and the projector, `direction` the coded axis), appended to the result.
void AddTriViewPoints(const ProjectorCalibration& projector, FringeDirection direction, const DecodedCamera& left,
                      const ScanOptions& options, ScanResult* result) {
  ScanSummary& sum = result->summary;
  ProjectorTriangulationOptions to = options.projector;
  to.min_depth_mm = std::max(to.min_depth_mm, options.match.min_depth_mm);
  to.max_depth_mm = std::min(to.max_depth_mm, options.match.max_depth_mm);
  const TriViewSummary tv = AddProjectorPoints(projector, direction, left, to, &result->cloud, &result->depth);
  sum.tri_view = true;
  sum.stereo_points = tv.stereo_points;
  sum.projector_points = tv.projector_points;
  sum.projector = tv.projector;
  sum.triangulation.points = static_cast<long>(result->cloud.size());
  std::vector<float> sigma = result->cloud.sigma_mm;
  if (!sigma.empty()) {
    auto mid = sigma.begin() + static_cast<std::ptrdiff_t>(sigma.size() / 2);
    std::nth_element(sigma.begin(), mid, sigma.end());
    sum.triangulation.median_sigma_mm = *mid;
  }
  if (tv.projector_points > 0) {
    sum.triangulation.depth_min_mm = std::min(sum.triangulation.depth_min_mm, tv.projector.depth_min_mm);
    sum.triangulation.depth_max_mm = std::max(sum.triangulation.depth_max_mm, tv.projector.depth_max_mm);
    if (tv.stereo_points == 0) {
      sum.triangulation.depth_min_mm = tv.projector.depth_min_mm;
      sum.triangulation.depth_max_mm = tv.projector.depth_max_mm;
    }
  }
  RAMTK_LOG(kDebug) << "tri-view: " << tv.stereo_points << " stereo + " << tv.projector_points
                    << " projector points; " << tv.projector.BriefReport();
}

ScanResult ScanDecodedReleasing(const StereoCalibration& calibration, DecodedCamera left, DecodedCamera right,
                                double period, const ScanOptions& options,
                                const ProjectorCalibration* projector = nullptr,
                                FringeDirection direction = FringeDirection::kVertical) {
  const ScanStageOptions stages = StageOptionsOf(options);
  ScanResult result;
  ScanSummary& sum = result.summary;
  sum.calibration = calibration.source_path;
  sum.calibration_rms_px = calibration.rms_px;
  sum.calibration_parameter_std = calibration.parameter_std;
  sum.left = left.summary;
  sum.right = right.summary;
  sum.width = left.coordinate.cols;
  sum.height = left.coordinate.rows;
  sum.windows = FullFrameWindows(calibration);

  auto t0 = std::chrono::steady_clock::now();
  StereoMatch match = MatchStereo(calibration, left, right, period, stages.match);
  right = DecodedCamera();
  sum.match = match.summary;
  sum.match_s = Seconds(t0);
  if (!Report(options, "match", 3, 5)) return Cancelled(std::move(result));

  t0 = std::chrono::steady_clock::now();
  // Triangulation reads only the left modulation (the points' quality) and summary: the other
  // left maps go first (~74 MB on a thesis frame, the peak being the cloud beside the matches);
  // tri-view keeps them for the camera–projector triangulation after it.
  if (projector == nullptr) {
    DecodedCamera kept;
    kept.summary = left.summary;
    kept.modulation = left.modulation;
    left = std::move(kept);
  }
  result.cloud = TriangulateMatches(calibration, left, match, stages.triangulation, &sum.triangulation, &result.depth);
  match = StereoMatch();
  if (projector != nullptr) AddTriViewPoints(*projector, direction, left, options, &result);
  left = DecodedCamera();
  sum.triangulate_s = Seconds(t0);
  if (!Report(options, "triangulate", 4, 5)) return Cancelled(std::move(result));

  FitSpheresBesideCloud(result, options);
  RAMTK_LOG(kDebug) << sum.match.BriefReport();
  RAMTK_LOG(kDebug) << sum.triangulation.BriefReport();
  return result;
}

}  // namespace

ScanResult ScanDecoded(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
                       double period, const ScanOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  return ScanDecodedReleasing(calibration, left, right, period, options);
}

namespace {

// The depth map of a window as a full-frame map (NaN outside the window), its rows filled in
// parallel: on a thesis frame it is 33 MB of fresh pages, whose first touch cost ~20 ms on one
// thread.
cv::Mat FullFrameDepth(const cv::Mat& window_depth, const cv::Rect& w, const cv::Size& frame) {
  cv::Mat depth(frame, CV_32F);
  tbb::parallel_for(tbb::blocked_range<int>(0, depth.rows, 64), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      float* row = depth.ptr<float>(y);
      std::fill_n(row, depth.cols, std::numeric_limits<float>::quiet_NaN());
      if (y >= w.y && y < w.y + w.height) std::copy_n(window_depth.ptr<float>(y - w.y), w.width, row + w.x);
    }
  });
  return depth;
}

// Decodes the pass's windows of both cameras' frames and runs the rest of the pipeline on them;
// the cloud's pixels and the depth image are returned in full-frame pixels. With `last_use`,
// each camera's frames are released once read (SetFrames::Release), so they are dropped once
// decoded.
ScanResult RunScanPass(const ScanPass& pass) {
  const StereoCalibration& calibration = *pass.calibration;
  const ScanOptions& options = *pass.options;
  const ScanWindows& windows = pass.windows;
  const ScanWindows full = FullFrameWindows(calibration);
  const bool whole = windows.left == full.left && windows.right == full.right;
  const StereoCalibration cropped = whole ? calibration : CropCalibration(calibration, windows);
  const DecodeOptions dopt = StageOptionsOf(options).decode;
  const double load0 = pass.frames->LoadSeconds();
  auto t0 = std::chrono::steady_clock::now();
  auto decode = [&](int camera, const cv::Rect& window, const std::string& name) {
    const std::vector<cv::Mat> f = pass.frames->Read(camera, window, 1);
    if (pass.last_use) pass.frames->Release(camera);
    return DecodeFrames(*pass.manifest, f, pass.frames->FullScale(), dopt, name);
  };
  DecodedCamera left = decode(0, windows.left, options.left_camera);
  if (!Report(options, "decode " + options.left_camera, 1, 5)) return Cancelled();
  DecodedCamera right = decode(1, windows.right, options.right_camera);
  const double decode_s = Seconds(t0) - (pass.frames->LoadSeconds() - load0);
  if (!Report(options, "decode " + options.right_camera, 2, 5)) return Cancelled();
  const double period = left.summary.period_px;
  ScanResult result = ScanDecodedReleasing(cropped, std::move(left), std::move(right), period, options,
                                           pass.projector, pass.manifest->direction);
  result.summary.decode_s = decode_s;
  result.summary.windows = windows;
  if (!whole) {
    const Eigen::Vector2f shift(static_cast<float>(windows.left.x), static_cast<float>(windows.left.y));
    for (Eigen::Vector2f& px : result.cloud.left_pixels) px += shift;
    if (!result.depth.empty())
      result.depth =
          FullFrameDepth(result.depth, windows.left, cv::Size(calibration.left.width, calibration.left.height));
    result.summary.width = calibration.left.width;
    result.summary.height = calibration.left.height;
  }
  return result;
}

// The coarse pass of roi auto: every stride-th pixel of the whole frame (`whole`) through the
// whole pipeline; the spheres it finds (empty, with the reason in *why, if none).
std::vector<Sphere> CoarseSpheres(const ScanPass& whole, int stride, std::string* why) {
  const StereoCalibration coarse = SubsampleCalibration(*whole.calibration, stride);
  const ScanOptions o = detail::CoarsePassOptions(*whole.options);
  const ScanWindows full = FullFrameWindows(*whole.calibration);
  std::vector<cv::Mat> left = whole.frames->Read(0, full.left, stride);
  std::vector<cv::Mat> right = whole.frames->Read(1, full.right, stride);
  SetFrames subsampled(std::move(left), std::move(right), whole.frames->FullScale());
  ScanPass pass;
  pass.manifest = whole.manifest;
  pass.calibration = &coarse;
  pass.frames = &subsampled;
  pass.windows = FullFrameWindows(coarse);
  pass.options = &o;
  const ScanResult r = RunScanPass(pass);
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

// The windows of roi auto or predicted (the whole frame for roi full, or when the coarse pass
// finds no sphere: *fallback_why says why), the spheres they are built around and the roi
// source for the summary.
struct RoiWindows {
  ScanWindows windows;
  std::vector<Sphere> around;
  std::string source = "full", fallback_why;
};

RoiWindows FindWindows(const ScanPass& whole) {
  const ScanRoiOptions& roi = whole.options->roi;
  const StereoCalibration& calibration = *whole.calibration;
  RoiWindows w;
  w.windows = FullFrameWindows(calibration);
  if (roi.mode == ScanRoiOptions::Mode::kAuto) {
    constexpr int kCoarseWidth = 350;
    const int stride = roi.coarse_stride > 0 ? roi.coarse_stride
                                             : std::max(2, (calibration.left.width + kCoarseWidth - 1) / kCoarseWidth);
    // A ball too small for this stride gives too few coarse points: halve the stride (down to 2)
    // before falling back to the full frame.
    std::vector<Sphere> found;
    for (int s = stride;; s /= 2) {
      w.fallback_why.clear();
      found = CoarseSpheres(whole, s, &w.fallback_why);
      w.source = "auto (coarse pass, stride " + std::to_string(s) + ")";
      if (!found.empty() || s / 2 < 2) break;
      RAMTK_LOG(kInfo) << "scan --roi auto: " << w.fallback_why << "; trying stride " << s / 2;
      whole.frames->LoadWhole();  // a finer coarse pass, perhaps the full frame after it
    }
    if (!found.empty()) {
      w.windows = WindowsAroundSpheres(calibration, found, roi.margin_mm, roi.margin_px);
      w.around = found;
    }
  } else if (roi.mode == ScanRoiOptions::Mode::kPredicted) {
    w.source = "predicted";
    std::vector<Sphere> predicted;
    for (const Vec3& c : roi.predicted_centres_in_left_mm) {
      Sphere s;
      s.centre_in_left = c;
      s.radius = whole.options->sphere.radius_mm > 0 ? whole.options->sphere.radius_mm : 19.05;
      predicted.push_back(s);
    }
    w.windows = WindowsAroundSpheres(calibration, predicted, roi.margin_mm, roi.margin_px);
    w.around = predicted;
  }
  return w;
}

// The result when roi auto found no window and may not fall back to the full frame.
ScanResult NoWindow(const RoiWindows& w, const SetFrames& frames, double roi_s, const StereoCalibration& calibration) {
  ScanResult r;
  r.summary.termination = Termination::kNoResult;
  r.summary.message = "no sphere found";
  r.summary.spheres.termination = Termination::kNoResult;
  r.summary.spheres.message = "no sphere found";
  r.summary.spheres.no_sphere_reason = w.fallback_why;
  r.summary.roi_source = w.source;
  r.summary.frame_reads = frames.Reads();
  r.summary.roi_s = roi_s;
  r.summary.width = calibration.left.width, r.summary.height = calibration.left.height;
  return r;
}

// ScanFrames on frames it may drop once they are no longer needed (RunScanPass); their sizes are
// the calibration's (the callers check). The one path of every scan of frames: the whole frame
// (roi full) is a pass whose windows are the whole frame.
ScanResult ScanFramesReleasing(const FringeManifest& m, const StereoCalibration& calibration, SetFrames frames,
                               const ScanOptions& options, const ProjectorCalibration* projector = nullptr) {
  const ScanRoiOptions& roi = options.roi;
  ScanPass whole;
  whole.projector = projector;
  whole.manifest = &m;
  whole.calibration = &calibration;
  whole.frames = &frames;
  whole.windows = FullFrameWindows(calibration);
  whole.options = &options;
  auto t0 = std::chrono::steady_clock::now();
  RoiWindows w = FindWindows(whole);
  const double roi_s = roi.mode == ScanRoiOptions::Mode::kFull ? 0.0 : Seconds(t0);  // no windows to find
  const ScanOptions windowed_options = detail::WindowedPassOptions(options, calibration, w.around);
  if (!w.fallback_why.empty() && !roi.fall_back_to_full) return NoWindow(w, frames, roi_s, calibration);
  const bool windowed = !(w.windows.left == whole.windows.left && w.windows.right == whole.windows.right);
  ScanPass pass = whole;
  pass.windows = w.windows;
  // The frames are needed again only for a fall-back to the full frame.
  pass.last_use = !windowed || !roi.fall_back_to_full;
  pass.options = windowed ? &windowed_options : &options;
  ScanResult result = RunScanPass(pass);
  if (windowed && result.summary.termination == Termination::kNoResult && roi.fall_back_to_full) {
    w.fallback_why = "the windowed scan found no sphere" + (result.summary.spheres.no_sphere_reason.empty()
                                                                ? std::string()
                                                                : ": " + result.summary.spheres.no_sphere_reason);
    const double windowed_s =
        result.summary.decode_s + result.summary.match_s + result.summary.triangulate_s + result.summary.fit_s;
    result = RunScanPass(whole);
    result.summary.roi_s = roi_s + windowed_s;
  } else {
    result.summary.roi_s = roi_s;
  }
  if (!w.fallback_why.empty()) {
    w.source += "; fell back to the full frame: " + w.fallback_why;
    RAMTK_LOG(kWarning) << "scan --roi: " << w.fallback_why << "; scanned the full frame";
  }
  result.summary.roi_source = w.source;
  result.summary.frame_reads = frames.Reads();
  result.summary.load_s = frames.LoadSeconds();
  return result;
}

}  // namespace

ScanResult ScanFrames(const FringeManifest& m, const StereoCalibration& calibration,
                      const std::vector<cv::Mat>& left_frames, const std::vector<cv::Mat>& right_frames,
                      double full_scale, const ScanOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  for (const auto* frames : {&left_frames, &right_frames}) {
    const CameraIntrinsics& k = frames == &left_frames ? calibration.left : calibration.right;
    for (const cv::Mat& f : *frames)
      if (f.cols != k.width || f.rows != k.height)
        throw InputError({calibration.source_path, 0, "image_size"},
                         "a frame is " + std::to_string(f.cols) + "x" + std::to_string(f.rows) +
                             ", the calibration's " + (frames == &left_frames ? "left" : "right") + " camera " +
                             std::to_string(k.width) + "x" + std::to_string(k.height));
  }
  return ScanFramesReleasing(m, calibration, SetFrames(left_frames, right_frames, full_scale), options);
}

namespace {

// Tri-view's projector calibration: options.projector_calibration_path, else the manifest's
// projector_calibration, whose camera must be the stereo calibration's left camera (its size).
ProjectorCalibration ReadTriViewProjector(const FringeManifest& m, const ScanOptions& options,
                                          const StereoCalibration& stereo) {
  std::string path = options.projector_calibration_path;
  if (path.empty()) {
    if (m.projector_calibration.empty())
      throw InputError({m.path, 0, "projector_calibration"},
                       "tri-view needs the projector's calibration: the set names none (pass --projector-calib)");
    path = m.Resolve(m.projector_calibration);
  }
  ProjectorCalibration p = ReadProjectorCalibration(path, m.projector_width, m.projector_height);
  if (p.camera.width != stereo.left.width || p.camera.height != stereo.left.height)
    throw InputError({path, 0, "image_size"}, "the projector calibration's camera is " +
                                                  std::to_string(p.camera.width) + "x" +
                                                  std::to_string(p.camera.height) + ", the stereo left camera " +
                                                  std::to_string(stereo.left.width) + "x" +
                                                  std::to_string(stereo.left.height));
  return p;
}

}  // namespace

ScanResult ScanFringeSet(const std::string& manifest_path, const ScanOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  const bool reference_decode = detail::CurrentDecodeTestHooks().reference_path;
  const FringeManifest m = ReadFringeManifest(manifest_path);
  if (!m.projector_calibration.empty() && !options.tri_view) return ScanMonocularSet(m, options);
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
  ProjectorCalibration projector;
  if (options.tri_view) projector = ReadTriViewProjector(m, options, calibration);
  const ProjectorCalibration* tri_view = options.tri_view ? &projector : nullptr;
  // A camera's frame `path` against the calibration's image size.
  auto check_size = [&](const std::string& cam, const std::string& path, const cv::Size& size) {
    const CameraIntrinsics& k = cam == options.left_camera ? calibration.left : calibration.right;
    if (size.width != k.width || size.height != k.height)
      throw InputError({calibration.source_path, 0, "image_size"},
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
  auto check_bits = [&](int left_bits, int right_bits) {
    if (left_bits != right_bits)
      throw InputError({manifest_path, 0, "cameras." + options.right_camera},
                       std::to_string(right_bits) + "-bit images beside " + std::to_string(left_bits) +
                           "-bit ones of camera " + options.left_camera);
  };
  ScanResult result;
  double load_s = 0;
  auto t0 = std::chrono::steady_clock::now();
  if (options.roi.mode == ScanRoiOptions::Mode::kFull) {
    // The whole frames: one camera at a time, loaded on its first read, decoded and dropped
    // before the other is loaded, so the set's samples are never all in memory at once (peak
    // memory).
    int left_bits = 0;
    SetFrames frames([&](int camera, double* full_scale) {
      ImageStack stack = load(camera == 0 ? options.left_camera : options.right_camera);
      if (camera == 0) left_bits = stack.bits_per_sample;
      if (camera == 1) check_bits(left_bits, stack.bits_per_sample);
      *full_scale = stack.full_scale;
      return std::move(stack.frames);
    });
    result = ScanFramesReleasing(m, calibration, std::move(frames), options, tri_view);
  } else {
    // Windows: uncompressed 8-bit grey frames are read by rows as the passes need them, others
    // loaded whole.
    std::vector<image::FrameRows> left_rows, right_rows;
    if (options.read_rows_on_demand && !reference_decode) {
      left_rows = open_rows(options.left_camera);
      if (!left_rows.empty()) right_rows = open_rows(options.right_camera);
    }
    if (!right_rows.empty()) {
      load_s = Seconds(t0);
      result = ScanFramesReleasing(m, calibration, SetFrames(std::move(left_rows), std::move(right_rows)), options);
    } else {
      ImageStack left_stack = load(options.left_camera), right_stack = load(options.right_camera);
      check_bits(left_stack.bits_per_sample, right_stack.bits_per_sample);
      load_s = Seconds(t0);
      result = ScanFramesReleasing(
          m, calibration, SetFrames(std::move(left_stack.frames), std::move(right_stack.frames), left_stack.full_scale),
          options);
    }
  }
  result.summary.set = manifest_path;
  if (result.summary.frame_reads.empty()) result.summary.frame_reads = "whole";
  result.summary.load_s += load_s;
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
                {"median_sigma_px", s.match.median_sigma_px},
                {"sampling_kernel",
                 {{"status", s.match.kernel.status},
                  {"applied", s.match.kernel.applied},
                  {"estimated_variance_px2", s.match.kernel.variance_px2},
                  {"estimated_sigma_px2", s.match.kernel.sigma_px2},
                  {"pixels", s.match.kernel.pixels},
                  {"leverage", s.match.kernel.leverage},
                  {"left_variance_px2", s.match.kernel.left_px2},
                  {"right_variance_px2", s.match.kernel.right_px2}}}};
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
    j["projector_triangulation"] = {{"method", s.projector_triangulation},
                                    {"coded_pixels", s.projector.coded_pixels},
                                    {"points", s.projector.points},
                                    {"rejected_geometry", s.projector.rejected_geometry},
                                    {"rejected_residual", s.projector.rejected_residual}};
  }
  if (s.tri_view)
    j["tri_view"] = {{"stereo_points", s.stereo_points},
                     {"projector_points", s.projector_points},
                     {"left_pixels_without_stereo_point", s.projector.coded_pixels},
                     {"projector_rejected_geometry", s.projector.rejected_geometry},
                     {"projector_median_sigma_mm", s.projector.median_sigma_mm}};
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
