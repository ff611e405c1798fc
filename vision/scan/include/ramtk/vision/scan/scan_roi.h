#pragma once
// Region of interest of a scan (`ramtk scan --roi`): the ball covers a few per cent of a
// full-frame capture, so decoding and matching only a window around it in each camera does the
// same work on the ball for a fraction of the time. A window is an exact crop: the cropped
// camera is the same pinhole camera with its principal point moved (distortion acts on
// normalised coordinates), so the points on the ball are those of the whole-frame scan up to
// the frame-wide estimates (intensity noise, projector nonlinearity) that now see only the
// window's pixels.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/sim/scene.h"

namespace ramtk::vision {

struct ScanRoiOptions {
  enum class Mode {
    kFull,       // every pixel (the default)
    kAuto,       // a coarse pass over every coarse_stride-th pixel finds the sphere(s) first
    kPredicted,  // windows around predicted_centres_in_left_mm (e.g. from the robot pose)
  };
  Mode mode = Mode::kFull;
  // kPredicted: predicted ball centres in the left-camera frame, mm.
  std::vector<Vec3> predicted_centres_in_left_mm;
  // kAuto: the coarse pass keeps every coarse_stride-th pixel in x and y (no averaging, so the
  // fringe modulation is kept). 0: the smallest stride >= 2 that makes the coarse left image
  // at most 350 px wide.
  int coarse_stride = 0;
  // Added to the ball radius before its silhouette is projected: covers the error of the
  // centre the window is built around (coarse pass: ~0.1 mm; a predicted centre: the robot's
  // and the set-up calibration's error, so give at least that).
  double margin_mm = 3.0;
  // Added on every side of each window, px (interpolation and code-edge neighbourhoods).
  int margin_px = 8;
  // The windowed match searches only depths within the spheres' radius + margin_mm + this of
  // their centres' depth (in each camera's frame), inside the match's own range: backdrop pixels
  // in a window, whose match lies outside the other camera's window, then cost a short search
  // instead of one over the whole range. < 0: the match's whole range.
  double depth_margin_mm = 10.0;
  // If the windowed scan finds no sphere (or the coarse pass finds none), scan the whole frame
  // instead (logged and recorded in ScanSummary::roi_source). false: report "no sphere found".
  bool fall_back_to_full = true;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// "full", "auto" or "X,Y,Z" (a predicted centre, mm) -> options; InputError (field --roi)
// otherwise.
ScanRoiOptions ParseScanRoi(const std::string& text);

// One window per camera, in that camera's full-frame pixels.
struct ScanWindows {
  cv::Rect left, right;
};

// The whole frames.
ScanWindows FullFrameWindows(const StereoCalibration& calibration);

// Windows that hold the silhouettes of the spheres grown by margin_mm, plus margin_px on each
// side, clipped to the frames (the union over the spheres in each camera). InputError if a
// sphere is not in front of both cameras or its window misses a frame entirely.
ScanWindows WindowsAroundSpheres(const StereoCalibration& calibration, const std::vector<Sphere>& spheres,
                                 double margin_mm, int margin_px);

// The calibration of the windows: principal points moved by the window origins, image sizes
// set to the window sizes; everything else unchanged.
StereoCalibration CropCalibration(const StereoCalibration& calibration, const ScanWindows& windows);

// The calibration of images that keep every stride-th pixel (pixel (i, j) of the subsampled
// image is pixel (stride i, stride j) of the full one): f, c divided by stride, sizes rounded up.
StereoCalibration SubsampleCalibration(const StereoCalibration& calibration, int stride);

// Every stride-th pixel of each frame in x and y (a copy; the same type).
std::vector<cv::Mat> SubsampleFrames(const std::vector<cv::Mat>& frames, int stride);

// Views of the window of each frame (no copy).
std::vector<cv::Mat> CropFrames(const std::vector<cv::Mat>& frames, const cv::Rect& window);

// "x,y,w,h" of a window.
std::string WindowText(const cv::Rect& window);

}  // namespace ramtk::vision
