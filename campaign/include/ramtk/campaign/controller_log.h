#pragma once
// The robot controller's log of a measurement campaign (docs/formats.md "Controller log"): one
// row per capture with the joints the controller reported when the sensor took it.
//   set,time_s,cycle,pose,q1,...,q6[,temp_j1,...]
// `set` (optional) names the capture: the fringe set's folder name or its manifest path
// (relative to the log). Without it, captures are matched by time. Joints in degrees.

#include <map>
#include <string>
#include <vector>

#include "ramtk/kinematics/robot_model.h"

namespace ramtk::campaign {

struct ControllerLogRow {
  std::string set;  // "" when the log has no set column
  double time_s = 0.0;
  int cycle = 0;
  int pose = 0;
  kinematics::JointVector q_controller = kinematics::JointVector::Zero();  // rad
  std::map<std::string, double> extra;  // further numeric columns (temperatures), by name
  int line = 0;                         // 1-based line in the file
};

struct ControllerLog {
  std::string path;  // the file (for messages; `set` paths are relative to its folder)
  bool has_set = false;
  std::vector<std::string> extra_columns;  // in file order
  std::vector<ControllerLogRow> rows;
};

// Reads the log. InputError names file:line and the column of a malformed row, a missing
// column, an empty `set` cell, or a repeated (cycle, pose).
ControllerLog ReadControllerLog(const std::string& path);
// The text of a log (what the campaign simulator writes); joints with 9 decimals.
std::string FormatControllerLog(const ControllerLog& log);

}  // namespace ramtk::campaign
