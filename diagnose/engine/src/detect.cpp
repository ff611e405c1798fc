#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/diagnose/engine/diagnose.h"

namespace ramtk::diagnose {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool HasColumn(const std::string& header, const std::string& name) {
  std::string cell;
  for (char c : header + ",") {
    if (c == ',') {
      if (cell == name) return true;
      cell.clear();
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      cell += c;
    }
  }
  return false;
}

}  // namespace

std::string DiagnoseOptions::Validate() const {
  if (data.empty()) return "data: no data file given";
  if (folds < 2) return "folds: cross-validation needs at least 2 folds";
  if (noise < 0.0) return "noise: must be >= 0";
  if (!(alpha > 0.0 && alpha < 0.5)) return "alpha: must be in (0, 0.5)";
  return "";
}

DataKind DetectKind(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError({path, 0, ""}, "file does not exist");
  RequireRegularFile(path);  // a FIFO or a device would block or never end
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  if (ext == ".json") return DataKind::kFringe;
  std::ifstream in(path);
  std::string header;
  while (std::getline(in, header) && (header.empty() || header[0] == '#')) {
  }
  header = Lower(header);
  if (HasColumn(header, "beam") && HasColumn(header, "state")) return DataKind::kLaser;
  if (HasColumn(header, "label") && HasColumn(header, "x")) return DataKind::kLaser;
  if (HasColumn(header, "q1") && HasColumn(header, "x")) return DataKind::kRobot;
  throw InputError({path, 1, "header"},
                   "not a fringe manifest (.json), robot measurements (q1..q6,x,y,z), laser log "
                   "(time_s,beam,state) or sensor-frame points (label,x,y,z)");
}

}  // namespace ramtk::diagnose
