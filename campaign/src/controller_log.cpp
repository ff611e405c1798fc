// The controller log (controller_log.h).
#include "ramtk/campaign/controller_log.h"

#include <cstdio>
#include <set>
#include <utility>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/measurements_io.h"

namespace ramtk::campaign {
ControllerLog ReadControllerLog(const std::string& path) {
  const CsvTable t = ReadCsv(path);
  ControllerLog log;
  log.path = path;
  const int set_col = t.Column("set", false);
  log.has_set = set_col >= 0;
  const int time_col = t.Column("time_s");
  const int cycle_col = t.Column("cycle");
  const int pose_col = t.Column("pose");
  int q_col[kinematics::kNumJoints];
  for (int i = 0; i < kinematics::kNumJoints; ++i) q_col[i] = t.Column("q" + std::to_string(i + 1));
  std::vector<int> known = {set_col, time_col, cycle_col, pose_col};
  known.insert(known.end(), q_col, q_col + kinematics::kNumJoints);
  std::vector<int> extra_cols;
  for (int c = 0; c < static_cast<int>(t.header.size()); ++c) {
    bool is_known = false;
    for (int k : known) is_known |= (k == c);
    if (!is_known) {
      extra_cols.push_back(c);
      log.extra_columns.push_back(t.header[c]);
    }
  }
  std::set<std::pair<int, int>> seen;
  std::set<std::string> seen_sets;
  for (std::size_t r = 0; r < t.size(); ++r) {
    ControllerLogRow row;
    row.line = t.line_numbers[r];
    if (set_col >= 0) {
      row.set = t.Text(r, set_col);
      if (row.set.empty()) throw InputError({path, row.line, "set"}, "empty (every row needs the capture's id)");
      if (!seen_sets.insert(row.set).second) {
        throw InputError({path, row.line, "set"}, "capture '" + row.set + "' is listed twice");
      }
    }
    row.time_s = t.Bounded(r, time_col, kinematics::kMaxAbsTimeS, "kMaxAbsTimeS");
    // Captures are matched to rows by time: a clock that steps back would match the wrong pose.
    if (!log.rows.empty() && row.time_s < log.rows.back().time_s) {
      throw InputError({path, row.line, "time_s"}, "the time goes backwards: " + FormatFixed(row.time_s, 3) +
                                                       " s after " + FormatFixed(log.rows.back().time_s, 3) +
                                                       " s on line " + std::to_string(log.rows.back().line) +
                                                       " (the controller's rows must be in time order)");
    }
    row.cycle = static_cast<int>(t.Integer(r, cycle_col));
    row.pose = static_cast<int>(t.Integer(r, pose_col));
    for (int i = 0; i < kinematics::kNumJoints; ++i)
      row.q_controller[i] = DegToRad(t.Bounded(r, q_col[i], kinematics::kMaxAbsJointDeg, "kMaxAbsJointDeg"));
    for (int c : extra_cols) row.extra[t.header[c]] = t.Number(r, c);
    if (!seen.insert({row.cycle, row.pose}).second) {
      throw InputError({path, row.line, "cycle,pose"},
                       "cycle " + std::to_string(row.cycle) + " pose " + std::to_string(row.pose) + " is logged twice");
    }
    log.rows.push_back(std::move(row));
  }
  if (log.rows.empty()) throw InputError({path, 0, ""}, "the controller log has no rows");
  return log;
}

std::string FormatControllerLog(const ControllerLog& log) {
  std::vector<std::string> header;
  if (log.has_set) header.push_back("set");
  header.insert(header.end(), {"time_s", "cycle", "pose"});
  for (int i = 0; i < kinematics::kNumJoints; ++i) header.push_back("q" + std::to_string(i + 1));
  header.insert(header.end(), log.extra_columns.begin(), log.extra_columns.end());
  std::vector<std::vector<std::string>> rows;
  for (const ControllerLogRow& r : log.rows) {
    std::vector<std::string> cells;
    if (log.has_set) cells.push_back(r.set);
    cells.insert(cells.end(), {FormatFixed(r.time_s, 3), std::to_string(r.cycle), std::to_string(r.pose)});
    for (int i = 0; i < kinematics::kNumJoints; ++i) cells.push_back(FormatFixed(RadToDeg(r.q_controller[i]), 9));
    for (const std::string& name : log.extra_columns) {
      const auto it = r.extra.find(name);
      cells.push_back(it == r.extra.end() ? "nan" : FormatFixed(it->second, 6));
    }
    rows.push_back(std::move(cells));
  }
  return FormatCsv(header, rows);
}

}  // namespace ramtk::campaign
