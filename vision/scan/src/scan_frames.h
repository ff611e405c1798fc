#pragma once
// A set's frames as the scan's passes read them (scan.cpp): stacks loaded whole and cut in
// memory (given, or loaded on a camera's first read), or files read by rows (image::FrameRows),
// of which only the rows a pass reads are ever read: a coarse pass every stride-th row, a window
// its rows.

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/image/frame_rows.h"

namespace ramtk::vision::detail {

class SetFrames {
 public:
  // Loads camera 0 (left) or 1 (right) whole and gives its frames' full scale (2^bits - 1).
  using Loader = std::function<std::vector<cv::Mat>(int camera, double* full_scale)>;

  SetFrames(std::vector<cv::Mat> left, std::vector<cv::Mat> right, double full_scale)
      : loaded_{std::move(left), std::move(right)}, full_scale_(full_scale) {}
  // 8-bit grey files read by rows.
  SetFrames(std::vector<image::FrameRows> left, std::vector<image::FrameRows> right)
      : files_{std::move(left), std::move(right)}, by_rows_(true) {}
  // Each camera loaded whole on its first Read, so a camera released (Release) before the other
  // is read is never in memory beside it.
  explicit SetFrames(Loader load) : load_(std::move(load)) {}

  // Every stride-th pixel of `window` of each frame of camera 0 (left) or 1 (right): views of
  // loaded frames for stride 1, copies otherwise.
  std::vector<cv::Mat> Read(int camera, const cv::Rect& window, int stride) const;
  // Camera `camera`'s frames are not read again: loaded ones are dropped (views handed out by
  // Read keep theirs alive until they go).
  void Release(int camera) { std::vector<cv::Mat>().swap(loaded_[camera]); }
  // Files are read whole now, once (when more passes will read most of their rows).
  void LoadWhole();
  // How the frames were read, for ScanSummary::frame_reads: "rows" while files are read by rows,
  // "rows, then whole" after LoadWhole, "" for frames given in memory.
  std::string Reads() const { return by_rows_ ? (files_[0].empty() ? "rows, then whole" : "rows") : ""; }
  // The frames' full scale (2^bits - 1; for a Loader, known once a camera was read).
  double FullScale() const { return full_scale_; }
  // Seconds the Loader took so far.
  double LoadSeconds() const { return load_s_; }

 private:
  mutable std::vector<cv::Mat> loaded_[2];
  std::vector<image::FrameRows> files_[2];
  bool by_rows_ = false;
  Loader load_;
  mutable bool load_done_[2] = {false, false};
  mutable double full_scale_ = 255.0;
  mutable double load_s_ = 0;
};

}  // namespace ramtk::vision::detail
