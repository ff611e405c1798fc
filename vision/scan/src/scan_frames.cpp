// A set's frames as the scan's passes read them (scan_frames.h).
#include "scan_frames.h"

#include <tbb/parallel_for.h>

#include <chrono>

#include "ramtk/vision/scan/scan_roi.h"

namespace ramtk::vision::detail {

std::vector<cv::Mat> SetFrames::Read(int camera, const cv::Rect& window, int stride) const {
  const auto& files = files_[camera];
  if (load_ && !load_done_[camera]) {
    const auto t0 = std::chrono::steady_clock::now();
    loaded_[camera] = load_(camera, &full_scale_);
    load_done_[camera] = true;
    load_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (files.empty()) {
    const std::vector<cv::Mat>& f = loaded_[camera];
    const bool whole = !f.empty() && window == cv::Rect(0, 0, f[0].cols, f[0].rows);
    const std::vector<cv::Mat> cut = whole ? f : CropFrames(f, window);
    return stride == 1 ? cut : SubsampleFrames(cut, stride);
  }
  std::vector<cv::Mat> out(files.size());
  tbb::parallel_for(std::size_t{0}, files.size(), [&](std::size_t i) { out[i] = files[i].Read(window, stride); });
  return out;
}

void SetFrames::LoadWhole() {
  for (int camera : {0, 1}) {
    if (files_[camera].empty()) continue;
    const image::FrameRows& first = files_[camera].front();
    loaded_[camera] = Read(camera, cv::Rect(0, 0, first.width(), first.height()), 1);
    files_[camera].clear();
  }
}

}  // namespace ramtk::vision::detail
