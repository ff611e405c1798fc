#pragma once
// Test helper: render a simulated stereo fringe set in memory and decode both cameras, keeping
// the simulator's ground truth beside the decoded maps.

#include <opencv2/core.hpp>
#include <vector>

#include "ramtk/vision/decode.h"
#include "ramtk/vision/fringe_simulator.h"
#include "ramtk/vision/manifest.h"

namespace ramtk::vision::testing {

// The decoder's manifest for a simulator configuration (no files: frames come from memory).
inline FringeManifest ManifestForConfig(const FringeSimulationConfig& c) {
  FringeManifest m;
  m.projector_width = c.projector.intrinsics.width;
  m.projector_height = c.projector.intrinsics.height;
  m.direction = c.direction == FringeOrientation::kVertical ? FringeDirection::kVertical : FringeDirection::kHorizontal;
  for (const PatternBlock& b : c.sequence) {
    SequenceBlock s;
    if (b.type == PatternBlock::Type::kPhaseShift) {
      s.type = BlockType::kPhaseShift;
      s.steps = b.steps;
      s.cycles = {b.cycles};
      s.phase_at_origin_rad = b.phase_at_origin_rad;
    } else {
      s.type = BlockType::kGrayCode;
      s.bits = b.bits;
      s.complementary = b.complementary;
    }
    m.sequence.push_back(s);
  }
  // Placeholder file names: the frames come from memory, but a manifest lists its images.
  std::vector<std::string> names(static_cast<std::size_t>(m.ImageCount()), "in-memory");
  m.cameras = {{"left", names}, {"right", names}};
  return m;
}

struct DecodedStereo {
  SimulatedCamera left_sim, right_sim;
  DecodedCamera left, right;
  double period = 0;  // projector px
};

inline DecodedCamera DecodeSimulated(const FringeSimulationConfig& c, const SimulatedCamera& sim,
                                     const DecodeOptions& options = {}) {
  std::vector<cv::Mat> frames;
  for (const cv::Mat& im : sim.images) {
    cv::Mat f;
    im.convertTo(f, CV_32F);
    frames.push_back(f);
  }
  return DecodeFrames(ManifestForConfig(c), frames, (1 << c.sensor.bits) - 1.0, options);
}

inline DecodedStereo SimulateAndDecode(const FringeSimulationConfig& c, const DecodeOptions& options = {}) {
  DecodedStereo s;
  s.left_sim = SimulateCamera(c, 0);
  s.right_sim = SimulateCamera(c, 1);
  s.left = DecodeSimulated(c, s.left_sim, options);
  s.right = DecodeSimulated(c, s.right_sim, options);
  s.period = s.left.summary.period_px;
  return s;
}

}  // namespace ramtk::vision::testing
