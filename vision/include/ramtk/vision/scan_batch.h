#pragma once
// Many scans at once (`ramtk scan --batch LIST`): the sets run in parallel (TBB), each writes its
// own output folder, and each gives one result row (CSV).

#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/vision/scan.h"

namespace ramtk::vision {

struct ScanBatchRow {
  std::string set;          // manifest path as listed
  std::string out_dir;      // where its outputs were written ("" if none)
  std::string status;       // "ok", "no sphere found", or "error"
  std::string message;      // the error or the no-sphere reason
  long points = 0;          // cloud size
  bool has_sphere = false;  // the first (strongest) sphere below is valid
  SphereResult sphere;      // first sphere
  double seconds = 0;       // wall time of this set
};

// Reads a batch list: one manifest path per line, relative paths against the list's folder;
// blank lines and lines starting with '#' are skipped. InputError naming the list if it is
// empty or unreadable.
std::vector<std::string> ReadScanBatchList(const std::string& path);

// Scans every set, at most `parallel_sets` at a time, writing each into out_dir/NNN_<name>/
// (name = the manifest's folder name). Bad input in one set is recorded in its row; the others
// go on. `progress` is called (serialised) after each set with done/total sets.
std::vector<ScanBatchRow> RunScanBatch(const std::vector<std::string>& sets, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress = {});

// CSV text: header `set,status,points,x_mm,y_mm,z_mm,radius_mm,sigma_x_mm,sigma_y_mm,sigma_z_mm,
// rms_mm,num_points,num_outliers,seconds,out_dir,message` and one row per set.
std::string ScanBatchCsv(const std::vector<ScanBatchRow>& rows);

}  // namespace ramtk::vision
