// Batch scans in parallel (scan_batch.h).
#include "ramtk/vision/scan_batch.h"

#include <sys/resource.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <sstream>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/parse.h"

namespace ramtk::vision {
namespace fs = std::filesystem;
std::vector<ScanBatchEntry> ReadScanBatchEntries(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::vector<ScanBatchEntry> entries;
  const fs::path base = fs::path(path).parent_path();
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    line = line.substr(start);
    ScanBatchEntry e;
    // A last whitespace-separated word with commas is the predicted centre.
    const std::size_t gap = line.find_last_of(" \t");
    if (gap != std::string::npos && line.find(',', gap) != std::string::npos) {
      const std::vector<double> c =
          ParseDoubleList(line.substr(gap + 1), {path, number, "predicted centre X,Y,Z (mm)"}, 3);
      e.predicted_centre_in_left_mm = Vec3(c[0], c[1], c[2]);
      line = line.substr(0, line.find_last_not_of(" \t", gap) + 1);
    }
    e.set = fs::path(line).is_absolute() ? line : (base / line).lexically_normal().string();
    entries.push_back(e);
  }
  if (entries.empty()) throw InputError({path, 0, "--batch"}, "the list names no fringe set");
  return entries;
}

std::vector<std::string> ReadScanBatchList(const std::string& path) {
  std::vector<std::string> sets;
  for (const ScanBatchEntry& e : ReadScanBatchEntries(path)) sets.push_back(e.set);
  return sets;
}

std::vector<std::size_t> ShardPositions(std::size_t num_sets, const ScanShard& shard) {
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw InputError({"", 0, "--shard"}, "expected K/N with 1 <= K <= N, got " + std::to_string(shard.index) + "/" +
                                             std::to_string(shard.count));
  }
  std::vector<std::size_t> out;
  for (std::size_t i = static_cast<std::size_t>(shard.index - 1); i < num_sets;
       i += static_cast<std::size_t>(shard.count))
    out.push_back(i);
  return out;
}

ScanShard ParseScanShard(const std::string& text) {
  ScanShard s;
  const std::size_t slash = text.find('/');
  char* end = nullptr;
  bool ok = slash != std::string::npos;
  if (ok) {
    s.index = static_cast<int>(std::strtol(text.c_str(), &end, 10));
    ok = end == text.c_str() + slash;
  }
  if (ok) {
    s.count = static_cast<int>(std::strtol(text.c_str() + slash + 1, &end, 10));
    ok = *end == '\0' && slash + 1 < text.size();
  }
  if (!ok || s.count < 1 || s.index < 1 || s.index > s.count)
    throw InputError({"", 0, "--shard"}, "expected K/N with 1 <= K <= N (e.g. 2/4), got '" + text + "'");
  return s;
}

std::string ShardResultsName(const ScanShard& shard) {
  return "results.shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".csv";
}

std::vector<ScanBatchRow> RunScanBatch(const std::vector<std::string>& all_sets, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress, const std::vector<std::size_t>& positions) {
  std::vector<ScanBatchEntry> entries;
  for (const std::string& s : all_sets) entries.push_back({s, std::nullopt});
  return RunScanBatch(entries, options, out_dir, parallel_sets, overwrite, progress, positions);
}

std::vector<ScanBatchRow> RunScanBatch(const std::vector<ScanBatchEntry>& all_entries, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress, const std::vector<std::size_t>& positions) {
  // The sets of this run and their positions in the full list (the folder prefix NNN_ is the
  // position, so every shard writes the folder a single run would).
  std::vector<std::size_t> position = positions;
  if (position.empty()) {
    for (std::size_t i = 0; i < all_entries.size(); ++i) position.push_back(i);
  }
  std::vector<std::string> sets;
  std::vector<std::optional<Vec3>> predicted;
  for (std::size_t p : position) {
    if (p >= all_entries.size()) throw InputError({"", 0, "positions"}, "set position beyond the list");
    sets.push_back(all_entries[p].set);
    predicted.push_back(all_entries[p].predicted_centre_in_left_mm);
  }
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  if (parallel_sets < 1) throw InputError({"", 0, "--jobs"}, "must be >= 1");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (!fs::is_directory(out_dir, ec)) throw InputError({out_dir, 0, "--out"}, "cannot create the output folder");
  std::vector<ScanBatchRow> rows(sets.size());
  std::mutex mutex;
  std::size_t done = 0;
  bool cancelled = false;
  tbb::task_arena arena(parallel_sets);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, sets.size(), std::size_t{1}, [&](std::size_t i) {
      const auto t0 = std::chrono::steady_clock::now();
      ScanBatchRow& row = rows[i];
      row.set = sets[i];
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (cancelled) {
          row.status = "cancelled";
          row.message = "not scanned: the progress callback asked to stop";
          return;
        }
      }
      char prefix[16];
      std::snprintf(prefix, sizeof prefix, "%03zu_", position[i]);
      const std::string name = fs::path(sets[i]).parent_path().filename().string();
      const std::string dir = (fs::path(out_dir) / (prefix + (name.empty() ? std::string("set") : name))).string();
      try {
        ScanOptions o = options;
        o.progress = {};
        ScanOutputWriter writer(dir, overwrite, sets[i]);
        o.on_cloud = writer.OnCloud();  // cloud.ply and depth.png beside the sphere fit
        if (predicted[i]) {
          o.roi.mode = ScanRoiOptions::Mode::kPredicted;
          o.roi.predicted_centres_in_left_mm = {*predicted[i]};
        }
        const ScanResult r = ScanFringeSet(sets[i], o);
        writer.Finish(r);
        row.out_dir = dir;
        row.points = r.summary.triangulation.points;
        row.status = r.summary.message;
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
      if (progress && !progress({"scan", done, sets.size()})) cancelled = true;
    });
  });
  return rows;
}

ScanBatchSummary SummariseScanBatch(const std::vector<ScanBatchRow>& rows, double wall_seconds) {
  ScanBatchSummary s;
  s.sets = rows.size();
  for (const ScanBatchRow& r : rows) {
    if (r.status == "error")
      ++s.errors;
    else if (r.status == "cancelled")
      ++s.cancelled;
    else if (r.status == "no sphere found")
      ++s.no_sphere;
    else
      ++s.ok;
  }
  s.seconds = wall_seconds;
  s.sets_per_second = wall_seconds > 0 ? static_cast<double>(s.sets) / wall_seconds : 0.0;
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) == 0) s.peak_memory_mb = usage.ru_maxrss / 1024.0;  // KiB on Linux
  return s;
}

std::string ScanBatchSummary::BriefReport() const {
  std::ostringstream o;
  o << "scanned " << sets << " sets: " << ok << " ok, " << no_sphere << " without a sphere, " << errors
    << " with errors";
  if (cancelled) o << ", " << cancelled << " cancelled";
  o.setf(std::ios::fixed);
  o.precision(seconds < 10 ? 2 : 1);
  o << " in " << seconds << " s (";
  o.precision(sets_per_second < 10 ? 2 : 1);
  o << sets_per_second << " sets/s), peak memory ";
  o.precision(0);
  o << peak_memory_mb << " MB";
  return o.str();
}

std::string ScanBatchCsv(const std::vector<ScanBatchRow>& rows, const std::string& relative_to) {
  std::vector<std::vector<std::string>> cells;
  auto number = [](double v) { return FormatSignificant(v, 10); };
  auto path = [&](const std::string& p) {
    if (relative_to.empty() || p.empty()) return p;
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(p, ec), fs::absolute(relative_to, ec), ec);
    return ec || rel.empty() ? p : rel.generic_string();
  };
  for (const ScanBatchRow& r : rows) {
    std::vector<std::string> row = {path(r.set), r.status, std::to_string(r.points)};
    if (r.has_sphere) {
      const Eigen::Vector3d sig = r.sphere.CentreSigma();
      for (double v : {r.sphere.centre_mm.x(), r.sphere.centre_mm.y(), r.sphere.centre_mm.z(), r.sphere.radius_mm,
                       sig.x(), sig.y(), sig.z(), r.sphere.rms_mm})
        row.push_back(number(v));
      row.push_back(std::to_string(r.sphere.num_points));
      row.push_back(std::to_string(r.sphere.num_outliers));
    } else {
      row.resize(row.size() + 10);
    }
    for (const std::string& cell : {number(r.seconds), path(r.out_dir), r.message}) row.push_back(cell);
    cells.push_back(std::move(row));
  }
  return FormatCsv({"set", "status", "points", "x_mm", "y_mm", "z_mm", "radius_mm", "sigma_x_mm", "sigma_y_mm",
                    "sigma_z_mm", "rms_mm", "num_points", "num_outliers", "seconds", "out_dir", "message"},
                   cells);
}

std::vector<std::string> FindShardResults(const std::string& folder) {
  namespace fs = std::filesystem;
  std::map<int, std::string> files;
  int count = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    int k = 0, n = 0;
    char tail[8] = {0};
    if (std::sscanf(name.c_str(), "results.shard-%d-of-%d.%7s", &k, &n, tail) != 3 || std::string(tail) != "csv")
      continue;
    if (count != 0 && n != count)
      throw InputError({entry.path().string(), 0, "--out"},
                       "shards of " + std::to_string(count) + " and of " + std::to_string(n) + " in one folder");
    count = n;
    files[k] = entry.path().string();
  }
  if (ec) throw InputError({folder, 0, "--out"}, "cannot list the folder: " + ec.message());
  if (count == 0) throw InputError({folder, 0, "--out"}, "no results.shard-K-of-N.csv in the folder");
  std::vector<std::string> ordered;
  for (int k = 1; k <= count; ++k) {
    if (!files.count(k))
      throw InputError({folder + "/" + ShardResultsName({k, count}), 0, "--out"},
                       "shard " + std::to_string(k) + " of " + std::to_string(count) + " has no results");
    ordered.push_back(files[k]);
  }
  return ordered;
}

std::string MergeScanShards(const std::vector<std::string>& sets, const std::vector<std::string>& shard_files) {
  if (shard_files.empty()) throw InputError({"", 0, "shards"}, "no shard results given");
  std::string header;
  // Rows of every shard, by set path; a set listed twice appears twice (taken in order).
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> rows;  // set -> (line, file)
  for (const std::string& file : shard_files) {
    std::istringstream in(ReadTextFile(file));
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      if (line_no == 1) {
        if (header.empty()) header = line;
        if (line != header) throw InputError({file, 1, ""}, "header differs from " + shard_files.front() + "'s");
        continue;
      }
      rows[SplitCsvLine(line).front()].push_back({line, file + ":" + std::to_string(line_no)});
    }
    if (line_no == 0) throw InputError({file, 0, ""}, "empty shard results");
  }
  std::string out = header + "\n";
  std::map<std::string, std::size_t> used;
  for (const std::string& set : sets) {
    auto it = rows.find(set);
    std::size_t& k = used[set];
    if (it == rows.end() || k >= it->second.size()) {
      throw InputError({set, 0, "set"}, "missing from the shard results (" + std::to_string(shard_files.size()) +
                                            " files): a shard did not run or did not finish");
    }
    out += it->second[k++].first + "\n";
  }
  for (const auto& [set, lines] : rows) {
    const std::size_t listed = used.count(set) ? used[set] : 0;
    if (lines.size() > listed) {
      throw InputError({lines[listed].second, 0, "set"},
                       listed == 0 ? "set '" + set + "' is not in the batch list"
                                   : "set '" + set + "' appears more often than in the batch list (duplicated shard?)");
    }
  }
  return out;
}

}  // namespace ramtk::vision
