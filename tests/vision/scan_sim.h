#pragma once
// Test helper: render a simulated stereo fringe set in memory and decode both cameras, keeping
// the simulator's ground truth beside the decoded maps.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision::testing {

// The decoder's manifest for a simulator configuration (no files: frames come from memory).
inline FringeManifest ManifestForConfig(const FringeSimulationConfig& c) {
  FringeManifest m;
  m.projector_width = c.projector.intrinsics.width;
  m.projector_height = c.projector.intrinsics.height;
  m.direction = c.direction;
  m.sequence = c.sequence;
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

#if defined(RAMTK_SHARED_DIR) && defined(RAMTK_DATASETS_DIR)
// The real SLMaster capture's manifest (datasets/vision/slmaster_binocular.json) with its images
// and calibration pointed at RAMTK_SHARED_DIR. False if the capture is not there (skip the test).
inline bool SlmasterManifest(FringeManifest* m) {
  const std::string shared = RAMTK_SHARED_DIR;
  if (!std::filesystem::exists(shared + "/data/slmaster-binocular/L/0.bmp")) return false;
  *m = ReadFringeManifest(std::string(RAMTK_DATASETS_DIR) + "/vision/slmaster_binocular.json");
  const std::string rel = "../../../shared";
  for (auto& [name, files] : m->cameras)
    for (std::string& f : files)
      if (f.rfind(rel, 0) == 0) f = shared + f.substr(rel.size());
  m->calibration = shared + "/data/slmaster-binocular/caliInfo.yml";
  m->path = "";
  return true;
}
#endif

}  // namespace ramtk::vision::testing
