#pragma once
// Projector pattern generation for the sequences a fringe manifest describes (phase convention
// in manifest.h). Patterns are single-channel images of the projector's resolution.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/fringe/gray_code.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk {
struct Provenance;  // ramtk/core/provenance.h
}  // namespace ramtk

namespace ramtk::vision {

// Ideal projector intensity in [0, 1] for every pattern of the manifest's sequence, in order
// (CV_32FC1, projector_height x projector_width).
std::vector<cv::Mat> GeneratePatterns(const FringeManifest& manifest);

// The patterns quantised to `bits` (8 or 16): CV_8UC1 or CV_16UC1.
std::vector<cv::Mat> QuantisePatterns(const std::vector<cv::Mat>& patterns, int bits);

// Phase (radians, not wrapped) of a phase_shift/heterodyne frequency with `cycles` across
// `extent` projector pixels at pixel coordinate u.
double PatternPhase(double u, double cycles, int extent, double phase_at_origin_rad);

// Writes pattern_00.png ... and manifest.json (camera "projector" lists the pattern files) into
// the folder `out_dir`, as a unit (core/outputs.h StagedFolder): an existing non-empty folder is
// replaced only with `overwrite`, and only once the new set is complete. Nothing is written if
// generation fails.
// With `provenance`, the folder also gets provenance.json (core/provenance.h WriteFolderProvenance).
void WritePatternSet(const std::string& out_dir, FringeManifest manifest, int bits, bool overwrite = false,
                     const Provenance* provenance = nullptr);

}  // namespace ramtk::vision
