#include "ramtk/calib/robot_calibration_io.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "ramtk/core/csv.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

nlohmann::json StatsJson(const ResidualStats& s) {
  return {{"poses", s.poses},
          {"rms_per_coordinate_mm", s.rms_per_coordinate_mm},
          {"rms_3d_mm", s.rms_3d_mm},
          {"max_3d_mm", s.max_3d_mm},
          {"rms_rotation_deg", s.rms_rotation_deg}};
}

}  // namespace

std::string RobotCalibrationJson(const RobotCalibration& c, const RobotCalibrationSummary& s) {
  nlohmann::json j;
  j["termination"] = TerminationName(s.termination);
  j["message"] = s.message;
  j["poses"] = s.num_poses;
  j["targets"] = s.num_targets;
  j["used_rotation"] = s.used_rotation;
  j["weights"] = {{"position_sigma_mm", s.position_sigma_mm}, {"rotation_sigma_deg", s.rotation_sigma_deg}};
  j["before"] = StatsJson(s.before);
  j["after"] = StatsJson(s.after);
  j["held_out"] = StatsJson(s.held_out);
  j["held_out_geometric"] = StatsJson(s.held_out_geometric);
  j["predicted_held_out_mm"] = s.predicted_held_out_mm;
  j["reduced_chi2"] = s.reduced_chi2;
  j["identifiability"] = {{"identified", s.num_identified},
                          {"eliminated", s.num_eliminated},
                          {"condition_number", s.condition_number},
                          {"observability_index", s.observability_index},
                          {"noise_amplification_index", s.noise_amplification_index}};
  j["terms_kept"] = s.terms_kept;
  j["warnings"] = s.warnings;
  j["tracker_from_base"] = PoseToJson(c.tracker_from_base);
  nlohmann::json targets = nlohmann::json::array();
  for (const Vec3& t : c.targets_in_flange) targets.push_back(Vec3ToJson(t));
  j["targets_in_flange_mm"] = targets;
  if (c.flange_from_tool_rotation) {
    Isometry3 tool = Isometry3::Identity();
    tool.linear() = *c.flange_from_tool_rotation;
    tool.translation() = c.targets_in_flange.front();
    j["flange_from_tool"] = PoseToJson(tool);
  }
  nlohmann::json unknowns = nlohmann::json::array();
  for (const CalibrationUnknown& u : c.unknowns) {
    nlohmann::json e = {{"name", u.name}, {"unit", u.unit}, {"status", u.status}, {"nominal", u.nominal},
                        {"value", u.value}, {"sigma", u.sigma}};
    if (!u.combination.empty()) {
      e["independence"] = u.independence;
      e["combination"] = u.combination;
    }
    unknowns.push_back(e);
  }
  j["unknowns"] = unknowns;
  // Covariance of the identified unknowns in their order (internal units: mm and rad).
  nlohmann::json names = nlohmann::json::array();
  int k = 0;
  for (const CalibrationUnknown& u : c.unknowns) {
    if (u.status == "identified") names.push_back(u.name), ++k;
  }
  nlohmann::json cov = nlohmann::json::array();
  for (int r = 0; r < c.covariance.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int col = 0; col < c.covariance.cols(); ++col) row.push_back(c.covariance(r, col));
    cov.push_back(row);
  }
  j["covariance"] = {{"unknowns", names}, {"units", "mm and rad"}, {"matrix", cov}};
  return j.dump(2) + "\n";
}

std::string RobotCalibrationResidualsCsv(const kinematics::TrackerMeasurements& data, const RobotCalibrationSummary& s) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < data.poses.size() && i < s.residuals_after.size(); ++i) {
    std::vector<std::string> row = {std::to_string(i), std::to_string(data.poses[i].line),
                                    FormatFixed(data.poses[i].time_s, 3)};
    for (const auto* list : {&s.residuals_before, &s.residuals_after, &s.residuals_held_out}) {
      for (int a = 0; a < 3; ++a) row.push_back(i < list->size() ? FormatFixed((*list)[i][a], 6) : "");
    }
    rows.push_back(row);
  }
  return FormatCsv({"pose", "line", "time_s", "before_x", "before_y", "before_z", "after_x", "after_y", "after_z",
                    "held_out_x", "held_out_y", "held_out_z"},
                   rows, "predicted minus measured position of the first target (mm, tracker frame)");
}

std::string RobotCalibrationTable(const RobotCalibration& c) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-14s %-17s %12s %12s %10s  %s\n", "unknown", "status", "nominal", "value", "sigma",
                "note");
  out += line;
  for (const CalibrationUnknown& u : c.unknowns) {
    if (u.status == "fixed") continue;
    std::snprintf(line, sizeof line, "%-14s %-17s %12.5f %12.5f %10.5f  %s %s\n", u.name.c_str(), u.status.c_str(),
                  u.nominal, u.value, u.sigma, u.unit.c_str(), u.combination.c_str());
    out += line;
  }
  return out;
}

}  // namespace ramtk::calib
