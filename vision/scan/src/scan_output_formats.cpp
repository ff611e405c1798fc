// The scan's output files, one row each (scan_output_formats.h).
#include "ramtk/vision/scan/scan_output_formats.h"

#include <sstream>
#include <stdexcept>

#include "ramtk/core/file_io.h"
#include "ramtk/report/gnuplot.h"
#include "ramtk/vision/scan/scan_report.h"

namespace ramtk::vision {
namespace {

void WriteCloudPly(const ScanOutputContext& c) { WritePly(c.PathOf("cloud.ply"), *c.cloud, c.comment); }

void WriteDepthPng(const ScanOutputContext& c) {
  if (c.depth->empty()) return;
  const std::vector<unsigned char> png = DepthPreviewPng(*c.depth);
  WriteFileAtomically(c.PathOf("depth.png"), [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

void WriteSpheresJson(const ScanOutputContext& c) {
  WriteSphereFitJson(c.PathOf("spheres.json"), c.result->summary.spheres, kScanFrame);
}

void WriteSummaryJson(const ScanOutputContext& c) {
  WriteFileAtomically(c.PathOf("summary.json"), WithProvenance(ScanSummaryToJson(c.result->summary), *c.provenance));
}

// report.html and, with gnuplot, each sphere's residual figure as PNG beside it.
void WriteReportHtml(const ScanOutputContext& c) {
  const ScanResult& result = *c.result;
  for (size_t k = 0; k < result.summary.spheres.spheres.size(); ++k) {
    const report::Figure f = SphereResidualFigure(result, static_cast<int>(k));
    if (!report::FindGnuplot().empty()) report::WritePng(f, c.PathOf(f.id + ".png"));
  }
  report::HtmlReport page = ScanReport(result, result.depth.empty() ? "" : c.PathOf("depth.png"));
  page.AddProvenance(*c.provenance);
  page.Write(c.PathOf("report.html"));
}

std::vector<ScanOutputFormat> BuiltIn() {
  using S = ScanOutputStage;
  // spheres.json is the folder's science payload, the same bytes however the set was scanned (one
  // run, a batch, a shard); the folder's provenance is in summary.json beside it.
  return {
      {"cloud", "cloud.ply", "PLY",
       "the point cloud: x, y, z (mm, left-camera frame), each point's sigma along its ray and its quality", S::kCloud,
       false, WriteCloudPly},
      {"spheres", "spheres.json", "JSON", "the fitted spheres (ball_in_left_camera), their covariance and fit figures",
       S::kResult, false, WriteSpheresJson},
      {"depth", "depth.png", "PNG",
       "z preview: a palette picture of the depth over the points' range (of the left window with --roi)", S::kCloud,
       false, WriteDepthPng},
      {"summary", "summary.json", "JSON",
       "decode and match counts, windows, stage seconds, the one-line report and the provenance", S::kResult, false,
       WriteSummaryJson},
      {"report", "report.html", "HTML",
       "one self-contained page (summary, sphere table, 3D view of the points around the sphere with its fit, residual "
       "and depth pictures)",
       S::kResult, true, WriteReportHtml},
  };
}

std::vector<ScanOutputFormat>& Table() {
  static std::vector<ScanOutputFormat> table = BuiltIn();
  return table;
}

}  // namespace

const std::vector<ScanOutputFormat>& ScanOutputFormats() { return Table(); }

const ScanOutputFormat& ScanOutputFormatNamed(const std::string& name) {
  for (const ScanOutputFormat& f : Table())
    if (f.name == name) return f;
  throw std::out_of_range("no scan output format named '" + name + "'");
}

void RegisterScanOutputFormat(ScanOutputFormat format) {
  if (!format.write) throw std::invalid_argument("scan output format '" + format.name + "' has no writer");
  for (const ScanOutputFormat& f : Table())
    if (f.name == format.name || f.file == format.file)
      throw std::invalid_argument("scan output format '" + format.name + "' (" + format.file + ") is taken");
  Table().push_back(std::move(format));
}

void RemoveScanOutputFormat(const std::string& name) {
  std::vector<ScanOutputFormat>& t = Table();
  for (auto it = t.begin(); it != t.end(); ++it)
    if (it->name == name) {
      t.erase(it);
      return;
    }
}

std::string ScanOutputFileList(bool report) {
  std::string list;
  for (const ScanOutputFormat& f : Table())
    if (report || !f.report_only) list += (list.empty() ? "" : ", ") + f.file;
  return list;
}

std::string ScanOutputFormatsMarkdown() {
  std::ostringstream s;
  s << "| file | type | written | what it holds |\n|---|---|---|---|\n";
  for (const ScanOutputFormat& f : Table())
    s << "| `" << f.file << "` | " << f.kind << " | " << (f.report_only ? "with `--report`" : "always") << " | "
      << f.help << " |\n";
  return s.str();
}

}  // namespace ramtk::vision
