#pragma once
// The scan's passes over a set's frames (scan.cpp): what one pass reads (ScanPass), the options
// every stage and pass runs with, rewritten from the scan's in one place (scan_pass_options.cpp),
// and the sphere fit with its gates (scan_fit.cpp).

#include <string>
#include <vector>

#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/scan/scan.h"
#include "scan_frames.h"

namespace ramtk::vision::detail {

// The options each stage runs with, derived from the scan's: no progress callback of their own
// (the scan reports per stage), and a match that keeps only what the cloud reads.
struct ScanStageOptions {
  DecodeOptions decode;
  StereoMatchOptions match;
  TriangulationOptions triangulation;
  SphereFitOptions sphere;
};
ScanStageOptions StageOptionsOf(const ScanOptions& options);

// The options of roi auto's coarse pass: the whole pipeline, fit included, without the steps a
// centre known to a fraction of a millimetre does not need (nonlinearity correction, left-right
// check, variance gate) and with a lower point count for the sphere.
ScanOptions CoarsePassOptions(const ScanOptions& options);

// The options for a windowed pass: the match's depth ranges (left and right camera frames)
// narrowed to the spheres' depth +- (radius + margin_mm + depth_margin_mm), inside the match's
// own range. Unchanged without spheres, with depth_margin_mm < 0, or if the window would be empty.
ScanOptions WindowedPassOptions(const ScanOptions& options, const StereoCalibration& calibration,
                                const std::vector<Sphere>& spheres);

// One pass over a set's frames: the windows of both cameras decoded, then matched, triangulated
// and fitted (RunScanPass in scan.cpp).
struct ScanPass {
  const FringeManifest* manifest = nullptr;
  const StereoCalibration* calibration = nullptr;  // the whole frame's
  SetFrames* frames = nullptr;                     // the frames at the calibration's size
  ScanWindows windows;                             // the windows read (FullFrameWindows: the whole frame)
  bool last_use = true;                            // each camera's frames are released once read
  const ScanOptions* options = nullptr;            // the pass's options
  // Tri-view (ScanOptions::tri_view, whole frame): the left camera and the projector; nullptr = off.
  const ProjectorCalibration* projector = nullptr;
};

// The sphere fit on the scan's cloud with the stage's options `so` and the gates (a sphere that
// does not fit its points at their noise level, or whose radius is off the prior, is not
// reported), each kept sphere's covariance inflated for neighbouring pixels' correlated noise
// (the image size from sum->width, height); fills sum->spheres, sum->fit_s and, without a
// sphere, sum's termination.
void FitScanSpheres(const PointCloud& cloud, const ScanOptions& options, const SphereFitOptions& so, ScanSummary* sum);

}  // namespace ramtk::vision::detail
