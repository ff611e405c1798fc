#pragma once
// Internal interface of the fused decode path (decode_fast.cpp), used by decode.cpp.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode.h"

namespace ramtk::vision::detail {

struct FastDecodeInput {
  int width = 0, height = 0;
  // Phase-shift frames per frequency, finest first (all CV_8U, all CV_16U or all CV_32F).
  std::vector<std::vector<const cv::Mat*>> ps_frames;
  std::vector<int> steps;                          // N per frequency
  std::vector<std::vector<float>> sin_table, cos_table;  // sin/cos(2 pi k / N) per frequency
  std::vector<const cv::Mat*> gray_frames;         // Gray-code frames (empty: none)
  bool complementary = false;                      // the Gray code has the extra half-period bit
  bool heterodyne = false;                         // coordinate from several frequencies (after the pass)
  double phase_at_origin_rad = 0;
  double period = 0;                               // finest period, projector px
  int extent = 0;                                  // projector px along the coded direction
  float b_min = 0, saturation = 0, dark = 0;       // thresholds, DN
};

struct FastDecodeOutput {
  cv::Mat wrapped, background, modulation, fit_residual, coordinate, mask;
  std::vector<cv::Mat> coarse_wrapped;  // heterodyne: wrapped phase of frequencies 1.. (0 where masked)
};

struct FastDecodeCounts {
  long dark = 0, saturated = 0, low_modulation = 0, unwrap_rejected = 0, corrected = 0, valid = 0;
  double residual_ss = 0, phase_ss = 0, worst_residual = 0;  // over valid pixels (not for heterodyne)
};

// The fast path of DecodeFrames (arguments already validated; frames all CV_8UC1, CV_16UC1 or CV_32FC1).
DecodedCamera DecodeFramesFast(const FringeManifest& manifest, const std::vector<cv::Mat>& frames, double full_scale,
                               const DecodeOptions& options, const std::string& camera);

// LS phase atan2(-S, C) in [-pi, pi).
float WrappedPhase(float s, float c);

// The fused pass. Pixels masked by darkness, saturation or modulation get phase 0 and a NaN
// coordinate; for heterodyne sets the coordinate and the counts of valid pixels are left to the caller.
void DecodeFused(const FastDecodeInput& in, FastDecodeOutput* out, FastDecodeCounts* counts);

// MeasureHarmonicRatios over every `stride`-th pixel in x and y, on frames of any sample type.
std::vector<double> MeasureHarmonicRatiosFast(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                                              int stride);

}  // namespace ramtk::vision::detail
