#pragma once
// The scan pipeline (`ramtk scan`): a stereo fringe image set and its calibration -> decoded
// projector coordinates of both cameras -> stereo matches -> a point cloud in the left-camera
// frame with per-point sigma -> the sphere(s) in it (ball centres, ball_in_left_camera).

#include <functional>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/core/provenance.h"
#include "ramtk/core/termination.h"
#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/stereo/point_cloud.h"
#include "ramtk/vision/projector/projector_triangulate.h"
#include "ramtk/vision/scan/scan_roi.h"
#include "ramtk/vision/sim/scene.h"
#include "ramtk/vision/sphere/sphere_fit.h"
#include "ramtk/vision/stereo/stereo_match.h"
#include "ramtk/vision/stereo/triangulate.h"

namespace ramtk::vision {

// Frame name written into the sphere JSON: every 3-D result is in the left camera's frame.
inline constexpr const char* kScanFrame = "left_camera";

struct ScanOptions {
  // Stereo calibration file; "" = the manifest's "calibration" entry.
  std::string calibration_path;
  // Camera names in the manifest: the left one is the reference frame.
  std::string left_camera = "left";
  std::string right_camera = "right";
  DecodeOptions decode;                // phase decoding of each camera (its progress is ignored)
  StereoMatchOptions match;            // epipolar matching (its progress is ignored)
  TriangulationOptions triangulation;  // ray-gap gate
  // Camera–projector sets (a manifest naming projector_calibration, scan_monocular.h): depth
  // range and iterations of the camera–projector triangulation. Its depth range is narrowed to
  // match.min_depth_mm .. match.max_depth_mm too (`ramtk scan --min-depth/--max-depth`).
  ProjectorTriangulationOptions projector;
  // Camera–projector sets with both fringe directions (FringeManifest::cross_cameras): true
  // triangulates ray–plane from the manifest's direction alone; false (default) ray–ray, the
  // projector pixel from both.
  bool projector_ray_plane = false;
  // Tri-view on a stereo set (ScanFringeSet, whole frame only): the left pixels that decoded but
  // got no stereo point are triangulated against the projector (vision/projector/tri_view.h),
  // each with its sigma, and appended to the cloud and the depth map. Off: a manifest naming a
  // projector_calibration is scanned as a camera–projector set (scan_monocular.h).
  bool tri_view = false;
  // With tri_view: the projector calibration (camera = the left camera), "" = the manifest's
  // projector_calibration entry.
  std::string projector_calibration_path;
  // Fit spheres to the cloud (false: cloud only).
  bool fit_spheres = true;
  // Sphere search and fit. ScanOptions() sets the 38.1 mm ball's radius prior (19.05 mm) and the
  // noise model of triangulated points (sigma along the left camera's line of sight).
  SphereFitOptions sphere;
  // Sanity gates on each fitted sphere (a failing one is dropped and the reason reported, never
  // returned as a centre): its chi^2 / (n - p) against the points' own sigma must not exceed
  // this (16: the surface RMS is at most 4x the predicted noise), and with a radius prior its
  // radius must lie within sphere.radius_tolerance_mm of it.
  double max_sphere_variance_factor = 16.0;
  // Decode and match only windows around the ball (scan_roi.h; ScanFringeSet only): the whole
  // frame (default), a coarse pass first, or a predicted centre.
  ScanRoiOptions roi;
  // With a window (roi auto or predicted) and frames that are uncompressed 8-bit grey BMPs
  // (image/frame_rows.h), read from the files only the rows each pass reads: every stride-th
  // row for the coarse pass, then the windows' rows (ScanFringeSet only). The result is the same
  // as loading the frames whole (false), which PNG and other files always are.
  bool read_rows_on_demand = true;
  // Called once the cloud and the depth map exist (after triangulation), beside the sphere fit
  // (on another thread: the fit leaves a core idle most of its time), with the cloud and the
  // depth map of the scanned window (the whole frame without --roi). ScanOutputWriter::OnCloud
  // writes cloud.ply and depth.png there, off the scan's critical path. Not called by the --roi
  // coarse pass nor for a cancelled scan; called again by a windowed scan that falls back to the
  // whole frame. An exception thrown by it is rethrown by the scan.
  std::function<void(const PointCloud& cloud, const cv::Mat& depth)> on_cloud;
  // Called after each stage ("decode left", "decode right", "match", "triangulate", "fit");
  // returning false cancels (termination "cancelled", nothing else is computed).
  ProgressCallback progress;

  ScanOptions();
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct ScanSummary {
  Termination termination = Termination::kSuccess;  // kSuccess, kNoResult or kCancelled
  // "stereo" (two cameras matched) or "monocular" (one camera against the projector; `left` is
  // that camera's decode, `right` and `match` stay empty, `projector` holds the triangulation).
  std::string mode = "stereo";
  ProjectorTriangulationSummary projector;
  // Monocular: "ray-plane" (one fringe direction) or "ray-ray" (both); "" for a stereo scan.
  std::string projector_triangulation;
  // Tri-view (ScanOptions::tri_view): the points each pair gave, the stereo pair's and the left
  // camera and projector's (their sum is triangulation.points); `projector` holds the latter's
  // triangulation of the left pixels without a stereo point.
  bool tri_view = false;
  long stereo_points = 0, projector_points = 0;
  std::string message = "ok";                       // "ok", "no sphere found" or "cancelled"
  std::string set;                                  // manifest path ("" for in-memory sets)
  std::string calibration;                          // calibration path used
  // The calibration session's own figures, carried from the file when it has them (NaN / empty
  // otherwise): reprojection RMS and parameter standard deviations (stereo_calibration.h).
  double calibration_rms_px = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> calibration_parameter_std;
  int width = 0, height = 0;  // left image size
  // The windows decoded and matched (full-frame pixels; the whole frames without --roi) and how
  // they were chosen: "full", "auto (coarse pass, stride S)", "predicted", possibly followed by
  // "; fell back to the full frame: WHY".
  ScanWindows windows;
  std::string roi_source = "full";
  // How the frames were read (ScanFringeSet): "whole" (loaded whole), or "rows" (read by rows
  // on demand, ScanOptions::read_rows_on_demand; "rows, then whole" once a second coarse pass
  // or the whole frame needed most of them). "" for frames given in memory.
  std::string frame_reads;
  DecodeSummary left, right;
  StereoMatchSummary match;
  TriangulationSummary triangulation;
  SphereFitSummary spheres;
  // Wall time of each stage, seconds: loading the frames (ScanFringeSet), the coarse pass that
  // finds the windows (roi auto), decoding (both cameras), matching, triangulation, sphere fit.
  // Frames read on demand (ScanOptions::read_rows_on_demand) are read inside the stage that
  // reads them: load_s is then opening the files, roi_s holds the coarse rows, decode_s the windows.
  double load_s = 0, roi_s = 0, decode_s = 0, match_s = 0, triangulate_s = 0, fit_s = 0;
  // One line: points, sphere centre(s) with sigma, radius, RMS (or "no sphere found: why").
  std::string BriefReport() const;
};

struct ScanResult {
  PointCloud cloud;  // left-camera frame, mm, with sigma and quality
  cv::Mat depth;     // CV_32F z (mm) per left pixel, NaN where no point
  ScanSummary summary;
};

// Runs the pipeline on a fringe image set. InputError naming the file and field for a bad
// manifest, a missing calibration, a calibration whose image size differs from the images, a
// non-rotation R (from ReadStereoCalibration), or bad options.
// With options.roi, decodes and matches only windows around the ball (scan_roi.h): the cloud
// then holds the windows' points only, the depth image is NaN outside them, and the summary
// records the windows and how they were found.
ScanResult ScanFringeSet(const std::string& manifest_path, const ScanOptions& options);

// The pipeline on frames already in memory (8/16-bit as loaded, or CV_32F in DN; each camera's
// frames in the manifest's sequence order, at the calibration's image size), with options.roi.
// `manifest` gives the pattern sequence; its paths are not read.
ScanResult ScanFrames(const FringeManifest& manifest, const StereoCalibration& calibration,
                      const std::vector<cv::Mat>& left_frames, const std::vector<cv::Mat>& right_frames,
                      double full_scale, const ScanOptions& options);

// The stages after decoding, on cameras already decoded (tests, benchmarks). `period` is the
// finest fringe period in projector px.
ScanResult ScanDecoded(const StereoCalibration& calibration, const DecodedCamera& left, const DecodedCamera& right,
                       double period, const ScanOptions& options);

// The depth picture as palette indices: z over the points' range on 255 levels of the turbo
// colour ramp, near = index 255 (red end), far = index 1 (blue end); index 0 = no point (black).
struct DepthPicture {
  cv::Mat index;                       // CV_8UC1, the depth map's size
  std::vector<cv::Vec3b> palette_bgr;  // 256 colours; [0] black, [k] = turbo at level round(255 (k - 1) / 254)
};
DepthPicture DepthPictureOf(const cv::Mat& depth);

// Depth preview (CV_8UC3, BGR): DepthPictureOf with its palette applied.
cv::Mat DepthPreview(const cv::Mat& depth);

// PNG file bytes of DepthPictureOf: a palette PNG, whose encoding compresses a third of the bytes
// of the BGR picture (1.3 Mpx: 4.6 against 11.9 ms, and a third of the file).
std::vector<unsigned char> DepthPreviewPng(const cv::Mat& depth);

// JSON text of a scan summary (stage figures, sphere results, timings).
std::string ScanSummaryToJson(const ScanSummary& summary);

// Writes cloud.ply, spheres.json, depth.png (of the left window when the scan used --roi windows)
// and summary.json into `out_dir`: all into a
// temporary sibling folder first, then renamed into place, so a failure leaves nothing. An
// existing non-empty `out_dir` is an InputError unless `overwrite`. With `html_report`, also
// report.html (scan_report.h) and sphere<k>_residual.png (when gnuplot is installed).
// summary.json and report.html carry `provenance` (docs/formats.md#provenance).
void WriteScanOutputs(const std::string& out_dir, const ScanResult& result, bool overwrite = false,
                      bool html_report = false, const Provenance& provenance = {});

// The same folder, written while the scan runs: pass OnCloud() as ScanOptions::on_cloud, and
// cloud.ply and depth.png are written beside the sphere fit; Finish writes spheres.json and
// summary.json (and the report), then moves the folder into place. Everything goes to a temporary
// sibling folder first: a scan that throws, or a writer destroyed unfinished, leaves nothing.
class ScanOutputWriter {
 public:
  // InputError (naming --out) if `out_dir` exists and is not empty without `overwrite`, or its
  // parent does not exist: checked here, before the scan. `set` is named in cloud.ply's comment.
  ScanOutputWriter(const std::string& out_dir, bool overwrite, const std::string& set);
  ~ScanOutputWriter();
  ScanOutputWriter(const ScanOutputWriter&) = delete;
  ScanOutputWriter& operator=(const ScanOutputWriter&) = delete;

  // The provenance block Finish writes into summary.json and the report (default:
  // the version and commit only).
  void SetProvenance(const Provenance& provenance);
  // For ScanOptions::on_cloud (it refers to this writer, which must outlive the scan).
  std::function<void(const PointCloud&, const cv::Mat&)> OnCloud();
  // cloud.ply and the depth picture of `depth` (the scanned window) into the temporary folder.
  void WriteCloud(const PointCloud& cloud, const cv::Mat& depth);
  // The rest, then the folder into place. Writes cloud.ply and depth.png too unless WriteCloud
  // wrote this result's (the same number of points; a result scanned without OnCloud).
  void Finish(const ScanResult& result, bool html_report = false);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The true spheres of a simulated set (`truth/truth.json` of `ramtk simulate fringe`: name,
// centre_in_left_mm, radius_mm). InputError naming the file and field otherwise.
std::vector<Sphere> ReadTruthSpheres(const std::string& truth_json_path);

// Each fitted sphere's nearest true sphere: index into `truth` (-1 if none) per fitted sphere.
std::vector<int> MatchTruthSpheres(const SphereFitSummary& fitted, const std::vector<Sphere>& truth);

}  // namespace ramtk::vision
