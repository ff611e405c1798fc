// Candidate joint configurations for pose planning: read from files, sampled, written.
#include <algorithm>
#include <random>

#include "ramtk/calib/pose_planning.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {

namespace {

// True when the header row (first line not blank or a comment) names a q1 column and no x / x1:
// a file of joints alone.
bool IsJointOnlyCsv(const std::string& text) {
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    if (line.find(';') != std::string::npos) return false;  // a tracker dialect
    std::vector<std::string> cells = SplitCsvLine(line);
    for (std::string& c : cells) {
      c.erase(0, c.find_first_not_of(" \t"));
      c.erase(c.find_last_not_of(" \t") + 1);
    }
    auto has = [&](const char* name) { return std::find(cells.begin(), cells.end(), name) != cells.end(); };
    return has("q1") && !has("x") && !has("x1");
  }
  return false;
}

}  // namespace

std::vector<Eigen::VectorXd> ReadCandidateJoints(const std::string& path, const kinematics::TrackerFormat* format,
                                                 int num_joints) {
  std::vector<Eigen::VectorXd> out;
  if (format == nullptr) {
    const std::string text = ReadTextFile(path);
    if (IsJointOnlyCsv(text)) {
      const CsvTable t = ParseCsv(text, path);
      std::vector<int> cols;
      for (int j = 0; j < num_joints; ++j) cols.push_back(t.Column("q" + std::to_string(j + 1)));
      if (t.Column("q" + std::to_string(num_joints + 1), false) >= 0) {
        throw InputError({path, 0, "q" + std::to_string(num_joints + 1)},
                         "the robot has " + std::to_string(num_joints) + " joints");
      }
      for (std::size_t r = 0; r < t.size(); ++r) {
        Eigen::VectorXd q(num_joints);
        for (int j = 0; j < num_joints; ++j) {
          const double v = t.Number(r, cols[j]);
          if (std::abs(DegToRad(v)) > kinematics::kTrackerMaxAbsJointRad) {
            throw InputError({path, t.line_numbers[r], t.header[cols[j]]}, "joint value beyond three turns (deg)");
          }
          q[j] = DegToRad(v);
        }
        out.push_back(q);
      }
      if (out.empty()) throw InputError({path, 0, ""}, "no joint configurations");
      return out;
    }
  }
  const kinematics::TrackerMeasurements data =
      kinematics::ReadTrackerMeasurements(path, format != nullptr ? *format : kinematics::TrackerFormat{});
  if (data.num_joints != num_joints) {
    throw InputError({path, 0, "joints"}, "the file has " + std::to_string(data.num_joints) + " joints, the robot " +
                                              std::to_string(num_joints));
  }
  for (const kinematics::TrackerPose& p : data.poses) {
    out.push_back(Eigen::Map<const Eigen::VectorXd>(p.q_rad.data(), num_joints));
  }
  if (out.empty()) throw InputError({path, 0, ""}, "no joint configurations");
  return out;
}

std::vector<Eigen::VectorXd> SampleJointConfigurations(int count, const std::vector<double>& limits_deg,
                                                       int num_joints, std::uint64_t seed) {
  if (count < 1 || count > 10000000) throw InputError({"", 0, "count"}, "expected 1..1e7 configurations");
  if (limits_deg.size() != 1 && static_cast<int>(limits_deg.size()) != num_joints) {
    throw InputError({"", 0, "limits"}, "expected one limit or one per joint (" + std::to_string(num_joints) + ")");
  }
  for (double l : limits_deg) {
    if (!(l > 0.0 && l <= 360.0)) throw InputError({"", 0, "limits"}, "expected each limit in (0, 360] deg");
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> out;
  for (int i = 0; i < count; ++i) {
    Eigen::VectorXd q(num_joints);
    for (int j = 0; j < num_joints; ++j) q[j] = DegToRad(limits_deg[limits_deg.size() == 1 ? 0 : j]) * unit(rng);
    out.push_back(q);
  }
  return out;
}

std::string FormatJointCsv(const std::vector<Eigen::VectorXd>& joints_rad, const std::string& comment) {
  std::vector<std::string> header = {"pose"};
  const int n = joints_rad.empty() ? 0 : static_cast<int>(joints_rad[0].size());
  for (int j = 0; j < n; ++j) header.push_back("q" + std::to_string(j + 1));
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < joints_rad.size(); ++i) {
    std::vector<std::string> row = {std::to_string(i + 1)};
    for (int j = 0; j < n; ++j) row.push_back(FormatFixed(RadToDeg(joints_rad[i][j]), 6));
    rows.push_back(row);
  }
  return FormatCsv(header, rows, comment);
}

}  // namespace ramtk::calib
