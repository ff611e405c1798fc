// A scan's output folder (scan.h): the rows of the output table (scan_output_formats.h) written
// into a temporary folder and moved into place as a unit; the depth picture.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/image/image_file.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/scan/scan_output_formats.h"

namespace ramtk::vision {

DepthPicture DepthPictureOf(const cv::Mat& depth) {
  CV_Assert(depth.type() == CV_32F);
  // Row by row (in parallel, with no full-frame temporary: on a thesis frame a mask, a float copy
  // and a grey image, ~50 MB, cost more in first touches than the work).
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  std::mutex range_mutex;
  tbb::parallel_for(tbb::blocked_range<int>(0, depth.rows, 64), [&](const tbb::blocked_range<int>& rows) {
    float l = std::numeric_limits<float>::infinity(), h = -l;
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const float* z = depth.ptr<float>(y);
      for (int x = 0; x < depth.cols; ++x)
        if (z[x] == z[x]) l = std::min(l, z[x]), h = std::max(h, z[x]);
    }
    std::lock_guard<std::mutex> lock(range_mutex);
    lo = std::min(lo, l);
    hi = std::max(hi, h);
  });
  double zlo = lo, zhi = hi;
  if (!(zlo <= zhi)) zlo = 0, zhi = 1;  // no point at all
  if (!(zhi > zlo)) zhi = zlo + 1;
  DepthPicture picture;
  // Index k = 1 + round(254 (zhi - z) / (zhi - zlo)): near (zlo) 255, far (zhi) 1.
  const double scale = 254.0 / (zhi - zlo);
  picture.index.create(depth.size(), CV_8U);
  tbb::parallel_for(tbb::blocked_range<int>(0, depth.rows, 64), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const float* z = depth.ptr<float>(y);
      uchar* k = picture.index.ptr<uchar>(y);
      for (int x = 0; x < depth.cols; ++x)
        k[x] = z[x] == z[x] ? static_cast<uchar>(1 + static_cast<int>((zhi - z[x]) * scale + 0.5)) : 0;
    }
  });
  cv::Mat ramp(1, 255, CV_8U), turbo;
  for (int k = 1; k <= 255; ++k) ramp.at<uchar>(0, k - 1) = static_cast<uchar>((255 * (k - 1) + 127) / 254);
  cv::applyColorMap(ramp, turbo, cv::COLORMAP_TURBO);
  picture.palette_bgr.assign(256, cv::Vec3b(0, 0, 0));
  for (int k = 1; k <= 255; ++k) picture.palette_bgr[k] = turbo.at<cv::Vec3b>(0, k - 1);
  return picture;
}

cv::Mat DepthPreview(const cv::Mat& depth) {
  const DepthPicture picture = DepthPictureOf(depth);
  cv::Mat colour(depth.size(), CV_8UC3);
  for (int y = 0; y < depth.rows; ++y) {
    const uchar* k = picture.index.ptr<uchar>(y);
    cv::Vec3b* out = colour.ptr<cv::Vec3b>(y);
    for (int x = 0; x < depth.cols; ++x) out[x] = picture.palette_bgr[k[x]];
  }
  return colour;
}

std::vector<unsigned char> DepthPreviewPng(const cv::Mat& depth) {
  const DepthPicture picture = DepthPictureOf(depth);
  return image::EncodeIndexedPng(picture.index, picture.palette_bgr, "depth picture");
}

struct ScanOutputWriter::Impl {
  StagedFolder staged;
  std::string comment;
  long cloud_points = -1;  // the points of the cloud.ply WriteCloud wrote (-1: none)
  Provenance provenance;   // recorded in spheres.json, summary.json and the report
  Impl(const std::string& out_dir, bool overwrite) : staged(out_dir, overwrite, "--out") {}
};

ScanOutputWriter::ScanOutputWriter(const std::string& out_dir, bool overwrite, const std::string& set)
    : impl_(std::make_unique<Impl>(out_dir, overwrite)) {
  impl_->comment = std::string("frame ") + kScanFrame + "; set " + set;
}

ScanOutputWriter::~ScanOutputWriter() = default;

void ScanOutputWriter::SetProvenance(const Provenance& provenance) { impl_->provenance = provenance; }

std::function<void(const PointCloud&, const cv::Mat&)> ScanOutputWriter::OnCloud() {
  return [this](const PointCloud& cloud, const cv::Mat& depth) { WriteCloud(cloud, depth); };
}

void ScanOutputWriter::WriteCloud(const PointCloud& cloud, const cv::Mat& depth) {
  impl_->cloud_points = -1;
  ScanOutputContext c;
  c.folder = impl_->staged.path().string();
  c.cloud = &cloud;
  c.depth = &depth;
  c.comment = impl_->comment;
  // The cloud's files side by side (cloud.ply is, on a thesis frame, 128 MB for the kernel to
  // copy, ~0.2 s; the depth picture is independent of it).
  std::vector<const ScanOutputFormat*> rows;
  for (const ScanOutputFormat& f : ScanOutputFormats())
    if (f.stage == ScanOutputStage::kCloud) rows.push_back(&f);
  tbb::parallel_for(std::size_t{0}, rows.size(), [&](std::size_t i) { rows[i]->write(c); });
  impl_->cloud_points = static_cast<long>(cloud.size());
}

void ScanOutputWriter::Finish(const ScanResult& result, bool html_report) {
  if (impl_->cloud_points != static_cast<long>(result.cloud.size())) {
    // With windows (--roi) the picture shows the left window only: the rest holds no point.
    const cv::Rect w = result.summary.windows.left;
    const bool windowed = !result.depth.empty() && w.area() > 0 &&
                          (w & cv::Rect(0, 0, result.depth.cols, result.depth.rows)) == w &&
                          w.size() != result.depth.size();
    WriteCloud(result.cloud, windowed ? result.depth(w) : result.depth);
  }
  ScanOutputContext c;
  c.folder = impl_->staged.path().string();
  c.cloud = &result.cloud;
  c.depth = &result.depth;
  c.result = &result;
  c.provenance = &impl_->provenance;
  c.comment = impl_->comment;
  for (const ScanOutputFormat& f : ScanOutputFormats())
    if (f.stage == ScanOutputStage::kResult && (html_report || !f.report_only)) f.write(c);
  impl_->staged.Commit();
}

void WriteScanOutputs(const std::string& out_dir, const ScanResult& result, bool overwrite, bool html_report,
                      const Provenance& provenance) {
  ScanOutputWriter writer(out_dir, overwrite, result.summary.set);
  writer.SetProvenance(provenance);
  writer.Finish(result, html_report);
}

}  // namespace ramtk::vision
