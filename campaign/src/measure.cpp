// Joining scan centres with the controller log (measure.h).
#include "ramtk/campaign/measure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "ramtk/campaign/controller_log.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/log.h"
#include "ramtk/core/parse.h"

namespace ramtk::campaign {
namespace fs = std::filesystem;
namespace {

std::string NormalPath(const std::string& p) {
  std::error_code ec;
  const fs::path abs = fs::absolute(fs::path(p), ec);
  return (ec ? fs::path(p) : abs).lexically_normal().string();
}

// A path written by the scan batch: as given (absolute, or relative to where the batch ran) when
// it exists, otherwise relative to the results file's folder.
// A relative path in results.csv is relative to the CSV's folder; results.csv files whose paths
// are relative to where the batch ran (older runs) are still found.
std::string ResolveBatchPath(const std::string& p, const fs::path& base) {
  std::error_code ec;
  if (fs::path(p).is_absolute()) return p;
  const fs::path near = base / p;
  if (fs::exists(near, ec) || !fs::exists(p, ec)) return near.string();
  return p;
}

std::string SetId(const std::string& manifest) { return fs::path(manifest).parent_path().filename().string(); }

bool CovarianceFromSpheresJson(const std::string& path, Mat3* cov) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return false;
  nlohmann::json j = ParseJsonText(ReadTextFile(path), path);
  const nlohmann::json* c = nullptr;
  if (j.contains("spheres") && j["spheres"].is_array() && !j["spheres"].empty()) {
    c = &j["spheres"][0];
  }
  if (c == nullptr || !c->contains("centre_covariance_mm2")) {
    throw InputError({path, 0, "spheres[0].centre_covariance_mm2"}, "missing");
  }
  const auto& m = (*c)["centre_covariance_mm2"];
  if (!m.is_array() || m.size() != 3) throw InputError({path, 0, "spheres[0].centre_covariance_mm2"}, "expected 3×3");
  for (int r = 0; r < 3; ++r) {
    if (!m[r].is_array() || m[r].size() != 3) {
      throw InputError({path, 0, "spheres[0].centre_covariance_mm2"}, "expected 3×3");
    }
    for (int k = 0; k < 3; ++k) {
      if (!m[r][k].is_number()) throw InputError({path, 0, "spheres[0].centre_covariance_mm2"}, "expected numbers");
      (*cov)(r, k) = m[r][k].get<double>();
    }
  }
  return true;
}

}  // namespace

bool ReadCaptureTime(const std::string& manifest_path, double* time_s) {
  nlohmann::json j = ParseJsonText(ReadTextFile(manifest_path), manifest_path);
  if (!j.is_object() || !j.contains("capture_time_s")) return false;
  if (!j["capture_time_s"].is_number() || !std::isfinite(j["capture_time_s"].get<double>())) {
    throw InputError({manifest_path, 0, "capture_time_s"}, "expected a number of seconds");
  }
  *time_s = j["capture_time_s"].get<double>();
  return true;
}

std::vector<CaptureCentre> CentresFromScanBatch(const std::vector<vision::ScanBatchRow>& rows) {
  std::vector<CaptureCentre> out;
  for (const vision::ScanBatchRow& r : rows) {
    CaptureCentre c;
    c.set = NormalPath(r.set);
    c.id = SetId(c.set);
    c.status = r.status;
    c.message = r.message;
    c.has_sphere = r.has_sphere;
    if (r.has_sphere) {
      c.centre_mm = r.sphere.centre_mm;
      c.covariance_mm2 = r.sphere.centre_covariance_mm2;
    }
    std::error_code ec;
    if (fs::exists(r.set, ec)) c.has_time = ReadCaptureTime(r.set, &c.time_s);
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<CaptureCentre> ReadScanResults(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::string line;
  int line_no = 0;
  std::map<std::string, int> col;
  std::vector<std::string> header;
  std::vector<CaptureCentre> out;
  const fs::path base = fs::path(path).parent_path();
  auto cell = [&](const std::vector<std::string>& cells, const char* name) -> const std::string& {
    const auto it = col.find(name);
    if (it == col.end()) throw InputError({path, 1, name}, "missing column (not a scan batch results.csv)");
    return cells[it->second];
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r" || line[0] == '#') continue;
    const std::vector<std::string> cells = SplitCsvLine(line);
    if (header.empty()) {
      header = cells;
      for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = static_cast<int>(i);
      for (const char* need : {"set", "status", "x_mm", "y_mm", "z_mm", "out_dir", "message"}) {
        if (col.count(need) == 0)
          throw InputError({path, line_no, need}, "missing column (not a scan batch results.csv)");
      }
      continue;
    }
    if (cells.size() != header.size()) {
      throw InputError({path, line_no, ""}, "expected " + std::to_string(header.size()) +
                                                " cells as in the header, got " + std::to_string(cells.size()));
    }
    CaptureCentre c;
    c.line = line_no;
    const std::string& set = cell(cells, "set");
    c.set = NormalPath(ResolveBatchPath(set, base));
    c.id = SetId(c.set);
    c.status = cell(cells, "status");
    c.message = cell(cells, "message");
    if (c.status == "ok") {
      c.has_sphere = true;
      c.centre_mm = Vec3(ParseDouble(cell(cells, "x_mm"), {path, line_no, "x_mm"}),
                         ParseDouble(cell(cells, "y_mm"), {path, line_no, "y_mm"}),
                         ParseDouble(cell(cells, "z_mm"), {path, line_no, "z_mm"}));
      std::string out_dir = cell(cells, "out_dir");
      if (!out_dir.empty()) out_dir = ResolveBatchPath(out_dir, base);
      if (out_dir.empty() ||
          !CovarianceFromSpheresJson((fs::path(out_dir) / "spheres.json").string(), &c.covariance_mm2)) {
        for (const char* s : {"sigma_x_mm", "sigma_y_mm", "sigma_z_mm"}) {
          if (col.count(s) == 0) throw InputError({path, line_no, s}, "missing column and no spheres.json in out_dir");
        }
        const Vec3 sig(ParseDouble(cell(cells, "sigma_x_mm"), {path, line_no, "sigma_x_mm"}),
                       ParseDouble(cell(cells, "sigma_y_mm"), {path, line_no, "sigma_y_mm"}),
                       ParseDouble(cell(cells, "sigma_z_mm"), {path, line_no, "sigma_z_mm"}));
        c.covariance_mm2 = sig.cwiseAbs2().asDiagonal();
        RAMTK_LOG(kWarning) << path << ":" << line_no << ": no spheres.json in '" << out_dir
                            << "': centre covariance taken as diagonal from the sigma columns";
      }
    } else if (c.status != "no sphere found" && c.status != "error") {
      throw InputError({path, line_no, "status"}, "expected ok, no sphere found or error, got '" + c.status + "'");
    }
    std::error_code ec;
    if (fs::exists(c.set, ec)) c.has_time = ReadCaptureTime(c.set, &c.time_s);
    out.push_back(std::move(c));
  }
  if (header.empty()) throw InputError({path, 0, ""}, "empty file: expected the scan batch header");
  if (out.empty()) throw InputError({path, 0, ""}, "no scanned sets in the file");
  return out;
}

std::string MeasureOptions::Validate() const {
  if (!(time_tolerance_s > 0.0) || !std::isfinite(time_tolerance_s)) return "time_tolerance_s must be > 0";
  return "";
}

std::string MeasureSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "measure: %d captures matched by %s, %d rows written, %zu left out (no centre), %d log rows "
                "without a capture",
                captures, match.c_str(), written, left_out.size(), unused_log_rows);
  std::string s = buf;
  if (match == "time") {
    std::snprintf(buf, sizeof(buf), ", worst time offset %.3f s", worst_time_offset_s);
    s += buf;
  }
  return s;
}

kinematics::RobotMeasurementSet JoinCentresWithLog(const std::vector<CaptureCentre>& captures, const ControllerLog& log,
                                                   const MeasureOptions& options, MeasureSummary* summary) {
  const std::string bad = options.Validate();
  if (!bad.empty()) throw InputError({"", 0, "--time-tolerance"}, bad);
  MeasureSummary local;
  MeasureSummary& s = summary ? *summary : local;
  s = MeasureSummary{};
  s.captures = static_cast<int>(captures.size());
  const bool by_id = log.has_set && !options.by_time;
  s.match = by_id ? "id" : "time";
  const fs::path log_dir = fs::path(log.path).parent_path();

  // Log row of every capture (-1: none).
  std::vector<int> match(captures.size(), -1);
  std::vector<std::string> no_match(captures.size());
  if (by_id) {
    std::map<std::string, int> by_path, by_name;
    for (std::size_t r = 0; r < log.rows.size(); ++r) {
      const std::string& id = log.rows[r].set;
      const bool is_path = id.find('/') != std::string::npos || fs::path(id).extension() == ".json";
      if (is_path) {
        const std::string p = NormalPath(fs::path(id).is_absolute() ? id : (log_dir / id).string());
        by_path[fs::path(p).extension() == ".json" ? p : (fs::path(p) / "manifest.json").string()] =
            static_cast<int>(r);
        by_path[p] = static_cast<int>(r);
      } else {
        by_name[id] = static_cast<int>(r);
      }
    }
    std::map<std::string, std::size_t> seen_id;
    for (std::size_t i = 0; i < captures.size(); ++i) {
      const CaptureCentre& c = captures[i];
      auto it = by_path.find(c.set);
      if (it == by_path.end()) it = by_path.find(fs::path(c.set).parent_path().string());
      if (it != by_path.end()) {
        match[i] = it->second;
      } else {
        const auto n = by_name.find(c.id);
        if (n != by_name.end()) {
          const auto prev = seen_id.find(c.id);
          if (prev != seen_id.end()) {
            throw InputError({log.path, log.rows[n->second].line, "set"},
                             "'" + c.id + "' names two captures (" + captures[prev->second].set + " and " + c.set +
                                 "): use manifest paths in the set column");
          }
          seen_id[c.id] = i;
          match[i] = n->second;
        } else {
          no_match[i] = "no row of the controller log names it (set column)";
        }
      }
    }
  } else {
    for (std::size_t i = 0; i < captures.size(); ++i) {
      const CaptureCentre& c = captures[i];
      if (!c.has_time) {
        if (!c.has_sphere) {
          no_match[i] = "no capture_time_s in its manifest";
          continue;
        }
        throw InputError({c.set, 0, "capture_time_s"},
                         "missing: the controller log " + log.path +
                             " has no set column, so captures are matched by time and each manifest needs its "
                             "capture time");
      }
      int best = -1;
      double best_dt = std::numeric_limits<double>::infinity();
      for (std::size_t r = 0; r < log.rows.size(); ++r) {
        const double dt = std::abs(log.rows[r].time_s - c.time_s);
        if (dt < best_dt) {
          best_dt = dt;
          best = static_cast<int>(r);
        }
      }
      if (best_dt > options.time_tolerance_s) {
        char buf[200];
        std::snprintf(buf, sizeof(buf),
                      "no log row within %.3g s of the capture time %.3f s (nearest: line %d, %.3f s)",
                      options.time_tolerance_s, c.time_s, log.rows[best].line, log.rows[best].time_s);
        no_match[i] = buf;
        continue;
      }
      match[i] = best;
    }
  }

  std::vector<int> used_by(log.rows.size(), -1);
  kinematics::RobotMeasurementSet out;
  out.kind = kinematics::MeasurementKind::kBall;
  out.extra_columns = log.extra_columns;
  kinematics::AddCentreCovarianceColumns(&out);
  for (std::size_t i = 0; i < captures.size(); ++i) {
    const CaptureCentre& c = captures[i];
    if (match[i] < 0) {
      if (c.has_sphere) {
        throw InputError({log.path, 0, by_id ? "set" : "time_s"}, "capture " + c.set + ": " + no_match[i]);
      }
      s.left_out.push_back(
          {c.set, -1, -1, c.status + (c.message.empty() ? "" : ": " + c.message) + "; " + no_match[i]});
      continue;
    }
    const ControllerLogRow& row = log.rows[match[i]];
    if (used_by[match[i]] >= 0) {
      throw InputError({log.path, row.line, by_id ? "set" : "time_s"},
                       "two captures match this row: " + captures[used_by[match[i]]].set + " and " + c.set);
    }
    used_by[match[i]] = static_cast<int>(i);
    if (!by_id) s.worst_time_offset_s = std::max(s.worst_time_offset_s, std::abs(row.time_s - c.time_s));
    if (!c.has_sphere) {
      s.left_out.push_back({c.set, row.cycle, row.pose, c.status + (c.message.empty() ? "" : ": " + c.message)});
      RAMTK_LOG(kWarning) << "measure: cycle " << row.cycle << " pose " << row.pose << " (" << c.set
                          << ") has no centre and is left out: " << c.status << " " << c.message;
      continue;
    }
    kinematics::RobotMeasurement m;
    m.cycle = row.cycle;
    m.time_s = row.time_s;
    m.index = row.pose;
    m.q_controller = row.q_controller;
    m.position_mm = c.centre_mm;
    m.extra = row.extra;
    kinematics::SetCentreCovariance(c.covariance_mm2, &m);
    out.rows.push_back(std::move(m));
  }
  for (int u : used_by) s.unused_log_rows += u < 0 ? 1 : 0;
  if (s.unused_log_rows > 0) {
    s.warnings.push_back(std::to_string(s.unused_log_rows) + " controller log rows have no capture");
  }
  std::stable_sort(out.rows.begin(), out.rows.end(), [](const auto& a, const auto& b) {
    return a.cycle != b.cycle ? a.cycle < b.cycle : a.index < b.index;
  });
  s.written = static_cast<int>(out.rows.size());
  return out;
}

std::vector<int> PosesMissingInSomeCycle(const kinematics::RobotMeasurementSet& measured,
                                         const kinematics::RobotMeasurementSet& expected) {
  std::map<int, std::set<int>> cycles_of_pose;
  std::set<int> cycles;
  for (const auto& row : measured.rows) {
    cycles_of_pose[row.index].insert(row.cycle);
    cycles.insert(row.cycle);
  }
  std::set<int> missing;
  for (const auto& [pose, c] : cycles_of_pose)
    if (c.size() < cycles.size()) missing.insert(pose);
  for (const auto& row : expected.rows)
    if (cycles_of_pose.count(row.index) == 0) missing.insert(row.index);
  return {missing.begin(), missing.end()};
}

kinematics::RobotMeasurementSet DropPoses(const kinematics::RobotMeasurementSet& set, const std::vector<int>& poses) {
  kinematics::RobotMeasurementSet out = set;
  out.rows.clear();
  for (const auto& row : set.rows)
    if (std::find(poses.begin(), poses.end(), row.index) == poses.end()) out.rows.push_back(row);
  return out;
}

}  // namespace ramtk::campaign
