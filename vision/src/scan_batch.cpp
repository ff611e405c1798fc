// Batch scans in parallel (scan_batch.h).
#include "ramtk/vision/scan_batch.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace ramtk::vision {
namespace fs = std::filesystem;
namespace {

std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

}  // namespace

std::vector<std::string> ReadScanBatchList(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::vector<std::string> sets;
  const fs::path base = fs::path(path).parent_path();
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    line = line.substr(start);
    sets.push_back(fs::path(line).is_absolute() ? line : (base / line).lexically_normal().string());
  }
  if (sets.empty()) throw InputError({path, 0, "--batch"}, "the list names no fringe set");
  return sets;
}

std::vector<ScanBatchRow> RunScanBatch(const std::vector<std::string>& sets, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress) {
  options.Validate();
  if (parallel_sets < 1) throw InputError({"", 0, "--jobs"}, "must be >= 1");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (!fs::is_directory(out_dir, ec)) throw InputError({out_dir, 0, "--out"}, "cannot create the output folder");
  std::vector<ScanBatchRow> rows(sets.size());
  std::mutex mutex;
  std::size_t done = 0;
  tbb::task_arena arena(parallel_sets);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, sets.size(), std::size_t{1}, [&](std::size_t i) {
      const auto t0 = std::chrono::steady_clock::now();
      ScanBatchRow& row = rows[i];
      row.set = sets[i];
      char prefix[16];
      std::snprintf(prefix, sizeof prefix, "%03zu_", i);
      const std::string name = fs::path(sets[i]).parent_path().filename().string();
      const std::string dir = (fs::path(out_dir) / (prefix + (name.empty() ? std::string("set") : name))).string();
      try {
        ScanOptions o = options;
        o.progress = {};
        const ScanResult r = ScanFringeSet(sets[i], o);
        WriteScanOutputs(dir, r, overwrite);
        row.out_dir = dir;
        row.points = r.summary.triangulation.points;
        row.status = r.summary.termination;
        row.message = r.summary.spheres.no_sphere_reason;
        if (!r.summary.spheres.spheres.empty()) {
          row.has_sphere = true;
          row.sphere = r.summary.spheres.spheres.front();
          row.sphere.inlier_indices.clear();
        }
      } catch (const InputError& e) {
        row.status = "error";
        row.message = e.what();
      }
      row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (progress) progress({"scan", done, sets.size()});
    });
  });
  return rows;
}

std::string ScanBatchCsv(const std::vector<ScanBatchRow>& rows) {
  std::ostringstream s;
  s.precision(10);
  s << "set,status,points,x_mm,y_mm,z_mm,radius_mm,sigma_x_mm,sigma_y_mm,sigma_z_mm,rms_mm,num_points,"
       "num_outliers,seconds,out_dir,message\n";
  for (const ScanBatchRow& r : rows) {
    s << CsvField(r.set) << "," << r.status << "," << r.points << ",";
    if (r.has_sphere) {
      const Eigen::Vector3d sig = r.sphere.CentreSigma();
      s << r.sphere.centre_mm.x() << "," << r.sphere.centre_mm.y() << "," << r.sphere.centre_mm.z() << ","
        << r.sphere.radius_mm << "," << sig.x() << "," << sig.y() << "," << sig.z() << "," << r.sphere.rms_mm << ","
        << r.sphere.num_points << "," << r.sphere.num_outliers << ",";
    } else {
      s << ",,,,,,,,,,";
    }
    s << r.seconds << "," << CsvField(r.out_dir) << "," << CsvField(r.message) << "\n";
  }
  return s.str();
}

}  // namespace ramtk::vision
