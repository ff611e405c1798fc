#pragma once
// The files of a scan's output folder as one table (ScanOutputFormats): each row names its file,
// says what it holds and writes it. ScanOutputWriter (scan.h) writes the rows; `ramtk scan`
// names them from it; docs/formats.md's table and the tests read it. Adding a format:
// docs/architecture.md, "Where to add things".

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/core/provenance.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace ramtk::vision {

// When a row is written: with the cloud (ScanOutputWriter::WriteCloud, beside the sphere fit;
// these rows are written side by side) or with the whole result (ScanOutputWriter::Finish, after
// the cloud's rows, one after the other in the table's order).
enum class ScanOutputStage { kCloud, kResult };

// What a row's writer gets.
struct ScanOutputContext {
  std::string folder;                      // the folder being written (moved into place as a unit)
  const PointCloud* cloud = nullptr;       // the cloud (both stages)
  const cv::Mat* depth = nullptr;          // the scanned window's depth map, mm; may be empty (kCloud)
  const ScanResult* result = nullptr;      // the whole result (kResult only)
  const Provenance* provenance = nullptr;  // the run's provenance (kResult only)
  std::string comment;                     // one line naming the frame and the set
  // `file` inside the folder.
  std::string PathOf(const std::string& file) const { return folder + "/" + file; }
};

struct ScanOutputFormat {
  std::string name;  // stable name of the row
  std::string file;  // its file name in the output folder
  std::string kind;  // file type as docs/formats.md names it: PLY, PNG, JSON, HTML, ...
  std::string help;  // what the file holds, one sentence (docs/formats.md's table, `ramtk scan --help`)
  ScanOutputStage stage = ScanOutputStage::kResult;     // when it is written
  bool report_only = false;                             // written only with --report
  std::function<void(const ScanOutputContext&)> write;  // writes the file (or, for no data, nothing)
};

// The table: the built-in rows, then any registered ones.
const std::vector<ScanOutputFormat>& ScanOutputFormats();
// The row named `name`; std::out_of_range if there is none.
const ScanOutputFormat& ScanOutputFormatNamed(const std::string& name);
// Appends a row (a format of one's own; tests). std::invalid_argument if its name or file is
// taken or it has no writer. The table is not guarded: register before scanning.
void RegisterScanOutputFormat(ScanOutputFormat format);
// Removes a registered row (no-op if there is none).
void RemoveScanOutputFormat(const std::string& name);

// The files, comma-separated in the table's order; with `report` also the --report ones.
std::string ScanOutputFileList(bool report);
// The table as docs/formats.md shows it (a Markdown table: file, type, written, what it holds).
std::string ScanOutputFormatsMarkdown();

}  // namespace ramtk::vision
