#pragma once
// The scan of a camera–projector (monocular) fringe set: one camera's frames decoded, each coded
// pixel triangulated against the calibrated projector (vision/projector), then the same cloud,
// sphere fit, outputs and reports as the stereo scan (scan.h). ScanFringeSet runs it for every
// manifest that names a projector_calibration.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {

// The set of `manifest` (read from manifest.path): its camera is options.left_camera if the
// manifest lists it, else its only camera; the calibration is options.calibration_path if given,
// else the manifest's projector_calibration, with the manifest's projector resolution. The whole
// frame is scanned: options.roi other than full is an InputError (field roi). InputError naming
// the file and field for a missing camera or calibration, or frames of another size than the
// calibration's camera.
ScanResult ScanMonocularSet(const FringeManifest& manifest, const ScanOptions& options);

// The same on frames already in memory (8/16-bit as loaded, or CV_32F in DN), in the manifest's
// sequence order, at the calibration's camera image size.
ScanResult ScanMonocularFrames(const FringeManifest& manifest, const ProjectorCalibration& calibration,
                               const std::vector<cv::Mat>& frames, double full_scale, const ScanOptions& options,
                               const std::string& calibration_path = "");

// Both fringe directions: `frames` as projected in the manifest's direction, `cross_frames` in
// the other (FringeManifest::cross_cameras), both in the sequence order. Ray–ray (the projector
// pixel from both coordinates) unless options.projector_ray_plane.
ScanResult ScanMonocularFramesBothDirections(const FringeManifest& manifest, const ProjectorCalibration& calibration,
                                             const std::vector<cv::Mat>& frames,
                                             const std::vector<cv::Mat>& cross_frames, double full_scale,
                                             const ScanOptions& options, const std::string& calibration_path = "");

// The stages after decoding: triangulation against the projector and the sphere fit. `direction`
// is the coded projector axis (the manifest's); `cross` (optional) the decode of the other
// direction: then ray–ray unless options.projector_ray_plane.
ScanResult ScanMonocularDecoded(const ProjectorCalibration& calibration, FringeDirection direction,
                                const DecodedCamera& camera, const ScanOptions& options,
                                const std::string& calibration_path = "", const DecodedCamera* cross = nullptr);

}  // namespace ramtk::vision
