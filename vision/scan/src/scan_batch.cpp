// Batch scans in parallel (scan_batch.h).
#include "ramtk/vision/scan/scan_batch.h"

#include <sys/resource.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/parse.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {

std::string ScanResultSettings::ToString() const {
  std::ostringstream s;
  s.precision(12);  // finer than any option is given on a command line
  s << "calib=" << calib << ";radius=" << radius << ";fix_radius=" << fix_radius << ";spheres=" << spheres
    << ";depth=" << min_depth << ".." << max_depth << ";reference_decode=" << reference_decode
    << ";full_search=" << full_search << ";curve_back_pass=" << curve_back_pass
    << ";no_nonlinearity=" << no_nonlinearity << ";whole_residual_sigma=" << whole_residual_sigma
    << ";phase_filter=" << phase_filter << ";lr_sigma_factor=" << lr_sigma_factor << ";roi=" << roi
    << ";roi_margin=" << roi_margin << ";roi_stride=" << roi_stride;
  if (tri_view) s << ";tri_view=1;projector_calib=" << projector_calib;
  if (modulation_rule != "sigma") s << ";modulation_rule=" << modulation_rule;
  if (max_order_error != 1e-4) s << ";max_order_error=" << max_order_error;
  if (ray_plane) s << ";ray_plane=1";
  if (kernel_estimate != "off") s << ";kernel_estimate=" << kernel_estimate;
  if (no_noise_term) s << ";no_noise_term=1";
  return s.str();
}
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
  // More shards than sets would leave shares empty: a mistyped N (or one meant for another list)
  // is caught here rather than by a merge that finds shards of nothing.
  if (static_cast<std::size_t>(shard.count) > num_sets) {
    throw InputError({"", 0, "--shard"}, std::to_string(shard.count) + " shards for " + std::to_string(num_sets) +
                                             " sets in the list: N may not exceed the number of sets");
  }
  std::vector<std::size_t> out;
  for (std::size_t i = static_cast<std::size_t>(shard.index - 1); i < num_sets;
       i += static_cast<std::size_t>(shard.count))
    out.push_back(i);
  return out;
}

namespace {
// A positive decimal integer that fits an int, nothing else (no sign, no space, no wrap-around).
bool ParseShardNumber(const std::string& text, int* value) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  *value = std::stoi(text);
  return true;
}
}  // namespace

ScanShard ParseScanShard(const std::string& text) {
  ScanShard s;
  const std::size_t slash = text.find('/');
  const bool ok = slash != std::string::npos && ParseShardNumber(text.substr(0, slash), &s.index) &&
                  ParseShardNumber(text.substr(slash + 1), &s.count);
  if (!ok || s.count < 1 || s.index < 1 || s.index > s.count)
    throw InputError({"", 0, "--shard"}, "expected K/N with 1 <= K <= N < 10^9 (e.g. 2/4), got '" + text + "'");
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

std::string ScanBatchSetFolder(const std::string& out_dir, std::size_t position, const std::string& set) {
  char prefix[24];
  std::snprintf(prefix, sizeof prefix, "%03zu_", position);
  const std::string name = fs::path(set).parent_path().filename().string();
  return (fs::path(out_dir) / (prefix + (name.empty() ? std::string("set") : name))).string();
}

namespace {

const std::vector<std::string>& CsvHeader() {
  static const std::vector<std::string> h = {
      "set",        "status",     "points", "x_mm",       "y_mm",         "z_mm",    "radius_mm", "sigma_x_mm",
      "sigma_y_mm", "sigma_z_mm", "rms_mm", "num_points", "num_outliers", "seconds", "out_dir",   "message"};
  return h;
}
constexpr std::size_t kSetCell = 0, kOutDirCell = 14;

std::vector<std::string> RowCells(const ScanBatchRow& r, const std::function<std::string(const std::string&)>& path) {
  std::vector<std::string> row = r.kept_cells;
  if (!row.empty()) {
    row[kSetCell] = path(r.set);
    row[kOutDirCell] = path(r.out_dir);
    return row;
  }
  auto number = [](double v) { return FormatSignificant(v, 10); };
  row = {path(r.set), r.status, std::to_string(r.points)};
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
  return row;
}

// `path` relative to `base` when it lies below it (text prefix "base/"), else as it is.
std::string RecordedPath(const std::string& path, const std::string& base) {
  if (base.empty()) return path;
  std::string prefix = base;
  while (prefix.size() > 1 && prefix.back() == '/') prefix.pop_back();
  prefix += '/';
  return path.compare(0, prefix.size(), prefix) == 0 ? path.substr(prefix.size()) : path;
}

// row.csv of a set folder: the batch row and the settings it was scanned with (paths as
// RecordedPath against `base`).
void WriteSetRow(const std::string& dir, const ScanBatchRow& row, const std::string& settings,
                 const std::string& base) {
  std::vector<std::string> header = CsvHeader(),
                           cells = RowCells(row, [&base](const std::string& p) { return RecordedPath(p, base); });
  header.push_back("settings");
  cells.push_back(settings);
  WriteFileAtomically(dir + "/row.csv", FormatCsv(header, {cells}));
}

bool SamePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  return fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal();
}

// The provenance of a set's folder: reuse.provenance's, with the set's input files hashed.
Provenance SetProvenance(const std::string& set, const std::string& dir, const ScanBatchReuse& reuse) {
  const std::string& base = reuse.paths_relative_to;
  Provenance p = reuse.provenance ? reuse.provenance(RecordedPath(set, base), RecordedPath(dir, base)) : Provenance{};
  for (const std::string& f : ReadFringeManifest(set).InputFiles()) AddProvenanceInput(&p, f, RecordedPath(f, base));
  return p;
}

// One set of a batch scanned into `dir` (or kept, with reuse.resume), its row filled.
void ScanBatchSet(const std::string& set, const std::optional<Vec3>& predicted, const std::string& dir,
                  const ScanOptions& options, const ScanBatchReuse& reuse, ScanBatchRow* row) {
  const auto t0 = std::chrono::steady_clock::now();
  row->set = set;
  if (reuse.resume) {
    if (std::optional<ScanBatchRow> kept = ReadFinishedSetRow(dir, set, reuse.settings)) {
      *row = *kept;
      return;
    }
  }
  try {
    ScanOptions o = options;
    o.progress = {};
    // With --resume, a folder without a finished row of these settings is no result of this batch.
    ScanOutputWriter writer(dir, reuse.overwrite || reuse.resume, RecordedPath(set, reuse.paths_relative_to));
    writer.SetProvenance(SetProvenance(set, dir, reuse));
    o.on_cloud = writer.OnCloud();  // cloud.ply and depth.png beside the sphere fit
    if (predicted) {
      o.roi.mode = ScanRoiOptions::Mode::kPredicted;
      o.roi.predicted_centres_in_left_mm = {*predicted};
    }
    ScanResult r = ScanFringeSet(set, o);
    r.summary.set = RecordedPath(r.summary.set, reuse.paths_relative_to);
    r.summary.calibration = RecordedPath(r.summary.calibration, reuse.paths_relative_to);
    writer.Finish(r);
    row->out_dir = dir;
    row->points = r.summary.triangulation.points;
    row->status = r.summary.message;
    row->message = r.summary.spheres.no_sphere_reason;
    if (!r.summary.spheres.spheres.empty()) {
      row->has_sphere = true;
      row->sphere = r.summary.spheres.spheres.front();
      row->sphere.inlier_indices.clear();
    }
    row->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    WriteSetRow(dir, *row, reuse.settings, reuse.paths_relative_to);
  } catch (const InputError& e) {
    row->status = "error";
    row->message = e.what();
    row->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
}

// The numbers of a kept row back into its fields, for the batch totals and report (the centre
// covariance as the diagonal of the recorded sigmas: the report shows their norm).
void FillKeptSphere(const std::vector<std::string>& cells, const std::string& file, ScanBatchRow* row) {
  auto number = [&](std::size_t i) { return ParseDouble(cells[i], {file, 2, CsvHeader()[i]}); };
  row->points = static_cast<long>(number(2));
  row->seconds = number(13);
  if (cells[3].empty()) return;
  SphereResult& s = row->sphere;
  s.centre_mm = Vec3(number(3), number(4), number(5));
  s.radius_mm = number(6);
  s.centre_covariance_mm2 = Vec3(number(7), number(8), number(9)).cwiseAbs2().asDiagonal();
  s.rms_mm = number(10);
  s.num_points = static_cast<int>(number(11));
  s.num_outliers = static_cast<int>(number(12));
  row->has_sphere = true;
}

}  // namespace

std::optional<ScanBatchRow> ReadFinishedSetRow(const std::string& folder, const std::string& set,
                                               const std::string& settings) {
  const std::string file = folder + "/row.csv";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  CsvTable t;
  try {
    t = ReadCsv(file);
  } catch (const InputError&) {
    return std::nullopt;  // damaged: the set is scanned again
  }
  std::vector<std::string> header = CsvHeader();
  header.push_back("settings");
  if (t.header != header || t.rows.size() != 1) return std::nullopt;
  std::vector<std::string> cells = t.rows.front();
  const std::string status = cells[1];
  if (!SamePath(cells[kSetCell], set) || cells.back() != settings || status == "error" || status == "cancelled")
    return std::nullopt;
  cells.pop_back();
  ScanBatchRow row;
  row.set = set;
  row.out_dir = folder;
  row.status = status;
  row.message = cells.back();
  row.kept_cells = cells;
  try {
    FillKeptSphere(cells, file, &row);
  } catch (const InputError&) {
    return std::nullopt;  // damaged: the set is scanned again
  }
  return row;
}

std::vector<ScanBatchRow> RunScanBatch(const std::vector<ScanBatchEntry>& all_entries, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, bool overwrite,
                                       const ProgressCallback& progress, const std::vector<std::size_t>& positions) {
  ScanBatchReuse reuse;
  reuse.overwrite = overwrite;
  return RunScanBatch(all_entries, options, out_dir, parallel_sets, reuse, progress, positions);
}

std::vector<ScanBatchRow> RunScanBatch(const std::vector<ScanBatchEntry>& all_entries, const ScanOptions& options,
                                       const std::string& out_dir, int parallel_sets, const ScanBatchReuse& reuse,
                                       const ProgressCallback& progress, const std::vector<std::size_t>& positions) {
  // The sets of this run and their positions in the full list (the folder prefix NNN_ is the
  // position, so every shard writes the folder a single run would).
  std::vector<std::size_t> position = positions;
  if (position.empty()) {
    for (std::size_t i = 0; i < all_entries.size(); ++i) position.push_back(i);
  }
  for (std::size_t p : position) {
    if (p >= all_entries.size()) throw InputError({"", 0, "positions"}, "set position beyond the list");
  }
  ThrowIfInvalid(options.Validate(), "ScanOptions");
  if (parallel_sets < 1) throw InputError({"", 0, "--jobs"}, "must be >= 1");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (!fs::is_directory(out_dir, ec)) throw InputError({out_dir, 0, "--out"}, "cannot create the output folder");
  std::vector<ScanBatchRow> rows(position.size());
  std::mutex mutex;
  std::size_t done = 0;
  bool cancelled = false;
  tbb::task_arena arena(parallel_sets);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, position.size(), std::size_t{1}, [&](std::size_t i) {
      const ScanBatchEntry& entry = all_entries[position[i]];
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (cancelled) {
          rows[i].set = entry.set;
          rows[i].status = "cancelled";
          rows[i].message = "not scanned: the progress callback asked to stop";
          return;
        }
      }
      ScanBatchSet(entry.set, entry.predicted_centre_in_left_mm, ScanBatchSetFolder(out_dir, position[i], entry.set),
                   options, reuse, &rows[i]);
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (progress && !progress({"scan", done, position.size()})) cancelled = true;
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
  auto path = [&](const std::string& p) {
    if (relative_to.empty() || p.empty()) return p;
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(p, ec), fs::absolute(relative_to, ec), ec);
    return ec || rel.empty() ? p : rel.generic_string();
  };
  for (const ScanBatchRow& r : rows) cells.push_back(RowCells(r, path));
  return FormatCsv(CsvHeader(), cells);
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

namespace {

// The column `name` of a shard header; InputError naming the file when it is absent.
std::size_t HeaderColumn(const std::vector<std::string>& header, const std::string& name, const std::string& file) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  throw InputError({file, 1, name}, "no '" + name + "' column: not a scan results file");
}

// Refuses a row that is not a scan result (status error or cancelled) unless `allow_errors`.
void CheckRowStatus(const std::vector<std::string>& cells, std::size_t status, const std::string& file, int line_no,
                    bool allow_errors) {
  const std::string& s = cells[status];
  if (allow_errors || (s != "error" && s != "cancelled")) return;
  throw InputError({file, line_no, "status"}, "set '" + cells.front() + "' has status '" + s +
                                                  "': re-run its shard (scan --resume) or pass --allow-errors");
}

}  // namespace

std::string MergeScanShards(const std::vector<std::string>& sets, const std::vector<std::string>& shard_files,
                            bool allow_errors) {
  if (shard_files.empty()) throw InputError({"", 0, "shards"}, "no shard results given");
  std::string header;
  std::size_t columns = 0, status = 0;
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
      const std::vector<std::string> cells = SplitCsvLine(line);
      if (line_no == 1) {
        if (header.empty()) {
          header = line;
          columns = cells.size();
          HeaderColumn(cells, "set", file);
          status = HeaderColumn(cells, "status", file);
        }
        if (line != header) throw InputError({file, 1, ""}, "header differs from " + shard_files.front() + "'s");
        continue;
      }
      if (cells.size() != columns)
        throw InputError({file, line_no, ""}, std::to_string(cells.size()) + " cells, the header has " +
                                                  std::to_string(columns) + " (a truncated or damaged row)");
      CheckRowStatus(cells, status, file, line_no, allow_errors);
      rows[cells.front()].push_back({line, file + ":" + std::to_string(line_no)});
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
