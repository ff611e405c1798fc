// The camera–projector scan (scan_monocular.h).
#include "ramtk/vision/scan/scan_monocular.h"

#include <algorithm>
#include <chrono>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/projector/projector_triangulate.h"
#include "scan_fit.h"

namespace ramtk::vision {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

bool Report(const ScanOptions& o, const std::string& stage, std::size_t done) {
  return !o.progress || o.progress({stage, done, 5});
}

ScanResult Cancelled(ScanResult r) {
  r.summary.termination = Termination::kCancelled;
  r.summary.message = "cancelled";
  return r;
}

void CheckFrameSize(const cv::Mat& frame, const CameraIntrinsics& camera, const std::string& calibration_path,
                    const std::string& frame_name) {
  if (frame.cols != camera.width || frame.rows != camera.height)
    throw InputError({calibration_path, 0, "image_size"},
                     "the calibration's camera is " + std::to_string(camera.width) + "x" +
                         std::to_string(camera.height) + " but " + frame_name + " is " + std::to_string(frame.cols) +
                         "x" + std::to_string(frame.rows));
}

DecodedCamera Decode(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                     const ScanOptions& options, const std::string& camera) {
  DecodeOptions dopt = options.decode;
  dopt.progress = {};
  return DecodeFrames(m, frames, full_scale, dopt, camera);
}

}  // namespace

ScanResult ScanMonocularDecoded(const ProjectorCalibration& calibration, FringeDirection direction,
                                const DecodedCamera& camera, const ScanOptions& options,
                                const std::string& calibration_path, const DecodedCamera* cross) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  ScanResult result;
  ScanSummary& sum = result.summary;
  sum.mode = "monocular";
  sum.calibration = calibration_path;
  sum.calibration_rms_px = calibration.rms_px;
  sum.calibration_parameter_std = calibration.parameter_std;
  sum.left = camera.summary;
  sum.width = camera.coordinate.cols;
  sum.height = camera.coordinate.rows;
  sum.windows.left = cv::Rect(0, 0, sum.width, sum.height);
  sum.match.left_valid = camera.summary.valid_pixels;

  const auto t0 = std::chrono::steady_clock::now();
  ProjectorTriangulationOptions to = options.projector;
  to.min_depth_mm = std::max(to.min_depth_mm, options.match.min_depth_mm);
  to.max_depth_mm = std::min(to.max_depth_mm, options.match.max_depth_mm);
  if (cross && !options.projector_ray_plane) {
    const bool vertical = direction == FringeDirection::kVertical;
    result.cloud = TriangulateProjectorPixels(calibration, vertical ? camera : *cross, vertical ? *cross : camera, to,
                                              &sum.projector, &result.depth);
    sum.projector_triangulation = "ray-ray";
  } else {
    result.cloud = TriangulateProjectorPlanes(calibration, direction, camera, to, &sum.projector, &result.depth);
    sum.projector_triangulation = "ray-plane";
  }
  sum.triangulation.points = sum.projector.points;
  sum.triangulation.rejected_gap = sum.projector.rejected_geometry;
  sum.triangulation.median_sigma_mm = sum.projector.median_sigma_mm;
  sum.triangulation.depth_min_mm = sum.projector.depth_min_mm;
  sum.triangulation.depth_max_mm = sum.projector.depth_max_mm;
  sum.match.matched = sum.projector.points;
  sum.triangulate_s = Seconds(t0);
  if (!Report(options, "triangulate", 4)) return Cancelled(std::move(result));
  FitSpheresBesideCloud(result, options);
  RAMTK_LOG(kDebug) << sum.projector.BriefReport();
  return result;
}

ScanResult ScanMonocularFrames(const FringeManifest& manifest, const ProjectorCalibration& calibration,
                               const std::vector<cv::Mat>& frames, double full_scale, const ScanOptions& options,
                               const std::string& calibration_path) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  for (std::size_t i = 0; i < frames.size(); ++i)
    CheckFrameSize(frames[i], calibration.camera, calibration_path, "frame " + std::to_string(i));
  const auto t0 = std::chrono::steady_clock::now();
  const DecodedCamera camera = Decode(manifest, frames, full_scale, options, options.left_camera);
  const double decode_s = Seconds(t0);
  if (!Report(options, "decode " + options.left_camera, 1)) return Cancelled(ScanResult());
  ScanResult result = ScanMonocularDecoded(calibration, manifest.direction, camera, options, calibration_path);
  result.summary.decode_s = decode_s;
  return result;
}

ScanResult ScanMonocularFramesBothDirections(const FringeManifest& manifest, const ProjectorCalibration& calibration,
                                             const std::vector<cv::Mat>& frames,
                                             const std::vector<cv::Mat>& cross_frames, double full_scale,
                                             const ScanOptions& options, const std::string& calibration_path) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  for (std::size_t i = 0; i < cross_frames.size(); ++i)
    CheckFrameSize(cross_frames[i], calibration.camera, calibration_path, "cross frame " + std::to_string(i));
  for (std::size_t i = 0; i < frames.size(); ++i)
    CheckFrameSize(frames[i], calibration.camera, calibration_path, "frame " + std::to_string(i));
  const auto t0 = std::chrono::steady_clock::now();
  const DecodedCamera camera = Decode(manifest, frames, full_scale, options, options.left_camera);
  FringeManifest crossed = manifest;
  crossed.direction =
      manifest.direction == FringeDirection::kVertical ? FringeDirection::kHorizontal : FringeDirection::kVertical;
  const DecodedCamera cross = Decode(crossed, cross_frames, full_scale, options, options.left_camera);
  const double decode_s = Seconds(t0);
  if (!Report(options, "decode " + options.left_camera, 1)) return Cancelled(ScanResult());
  ScanResult result =
      ScanMonocularDecoded(calibration, manifest.direction, camera, options, calibration_path, &cross);
  result.summary.decode_s = decode_s;
  return result;
}

ScanResult ScanMonocularSet(const FringeManifest& m, const ScanOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  if (options.roi.mode != ScanRoiOptions::Mode::kFull)
    throw InputError({m.path, 0, "roi"}, "a camera–projector set is scanned whole (windows need a stereo set)");
  std::string camera = options.left_camera;
  if (!m.cameras.count(camera)) {
    if (m.cameras.size() != 1)
      throw InputError({m.path, 0, "cameras." + camera},
                       "the set has no camera '" + camera + "' and more than one other to choose from");
    camera = m.cameras.begin()->first;
  }
  const std::string calib_path =
      options.calibration_path.empty() ? m.Resolve(m.projector_calibration) : options.calibration_path;
  const ProjectorCalibration calibration =
      ReadProjectorCalibration(calib_path, m.projector_width, m.projector_height);
  auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> paths;
  for (const std::string& f : m.cameras.at(camera)) paths.push_back(m.Resolve(f));
  ImageStack stack = LoadImageStack(paths, options.decode.dark_fraction, true);
  CheckFrameSize(stack.frames.front(), calibration.camera, calib_path, paths.front());
  const double load_s = Seconds(t0);
  t0 = std::chrono::steady_clock::now();
  DecodedCamera decoded = Decode(m, stack.frames, stack.full_scale, options, camera);
  std::vector<cv::Mat>().swap(stack.frames);
  // Both directions projected: the other one's frames decoded as the set in that direction.
  DecodedCamera cross;
  const bool both = m.cross_cameras.count(camera) && !options.projector_ray_plane;
  if (both) {
    const FringeManifest crossed = m.CrossDirection();
    std::vector<std::string> cross_paths;
    for (const std::string& f : crossed.cameras.at(camera)) cross_paths.push_back(crossed.Resolve(f));
    ImageStack cross_stack = LoadImageStack(cross_paths, options.decode.dark_fraction, true);
    CheckFrameSize(cross_stack.frames.front(), calibration.camera, calib_path, cross_paths.front());
    cross = Decode(crossed, cross_stack.frames, cross_stack.full_scale, options, camera);
  }
  const double decode_s = Seconds(t0);
  if (!Report(options, "decode " + camera, 1)) return Cancelled(ScanResult());
  ScanResult result =
      ScanMonocularDecoded(calibration, m.direction, decoded, options, calib_path, both ? &cross : nullptr);
  result.summary.set = m.path;
  result.summary.load_s = load_s;
  result.summary.decode_s = decode_s;
  result.summary.frame_reads = "whole";
  result.summary.roi_source = "full";
  return result;
}

}  // namespace ramtk::vision
