// A scan's output folder (scan.h): cloud.ply, depth.png, spheres.json, summary.json and the
// report, staged in a temporary folder and moved into place as a unit; the depth picture.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <filesystem>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/image/image_file.h"
#include "ramtk/report/gnuplot.h"
#include "ramtk/vision/scan.h"
#include "ramtk/vision/scan_report.h"

namespace ramtk::vision {

namespace fs = std::filesystem;

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
  const fs::path& tmp = impl_->staged.path();
  impl_->cloud_points = -1;
  // cloud.ply (on a thesis frame 128 MB for the kernel to copy, ~0.2 s) and the depth picture
  // are independent files: written side by side.
  tbb::parallel_invoke([&] { WritePly((tmp / "cloud.ply").string(), cloud, impl_->comment); },
                       [&] {
                         if (depth.empty()) return;
                         const std::vector<unsigned char> png = DepthPreviewPng(depth);
                         WriteFileAtomically((tmp / "depth.png").string(), [&](std::ostream& out) {
                           out.write(reinterpret_cast<const char*>(png.data()),
                                     static_cast<std::streamsize>(png.size()));
                         });
                       });
  impl_->cloud_points = static_cast<long>(cloud.size());
}

void ScanOutputWriter::Finish(const ScanResult& result, bool html_report) {
  const fs::path& tmp = impl_->staged.path();
  if (impl_->cloud_points != static_cast<long>(result.cloud.size())) {
    // With windows (--roi) the picture shows the left window only: the rest holds no point.
    const cv::Rect w = result.summary.windows.left;
    const bool windowed = !result.depth.empty() && w.area() > 0 &&
                          (w & cv::Rect(0, 0, result.depth.cols, result.depth.rows)) == w &&
                          w.size() != result.depth.size();
    WriteCloud(result.cloud, windowed ? result.depth(w) : result.depth);
  }
  const Provenance& provenance = impl_->provenance;
  // spheres.json is the folder's science payload, the same bytes however the set was scanned (one
  // run, a batch, a shard); the folder's provenance is in summary.json beside it.
  WriteSphereFitJson((tmp / "spheres.json").string(), result.summary.spheres, kScanFrame);
  WriteFileAtomically((tmp / "summary.json").string(), WithProvenance(ScanSummaryToJson(result.summary), provenance));
  if (html_report) {
    for (size_t k = 0; k < result.summary.spheres.spheres.size(); ++k) {
      const report::Figure f = SphereResidualFigure(result, static_cast<int>(k));
      if (!report::FindGnuplot().empty()) report::WritePng(f, (tmp / (f.id + ".png")).string());
    }
    report::HtmlReport page = ScanReport(result, result.depth.empty() ? "" : (tmp / "depth.png").string());
    page.AddProvenance(provenance);
    page.Write((tmp / "report.html").string());
  }
  impl_->staged.Commit();
}

void WriteScanOutputs(const std::string& out_dir, const ScanResult& result, bool overwrite, bool html_report,
                      const Provenance& provenance) {
  ScanOutputWriter writer(out_dir, overwrite, result.summary.set);
  writer.SetProvenance(provenance);
  writer.Finish(result, html_report);
}

}  // namespace ramtk::vision
