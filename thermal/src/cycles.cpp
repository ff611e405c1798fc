#include "ramtk/thermal/cycles.h"

#include <algorithm>
#include <set>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::thermal {

std::string CycleOptions::Validate() const {
  if (!(joint_tolerance_deg >= 0.0)) return "joint_tolerance_deg must be >= 0";
  return "";
}

int CycleSeries::Find(int cycle) const {
  for (int i = 0; i < NumCycles(); ++i) {
    if (cycles[i].cycle == cycle) return i;
  }
  return -1;
}

Eigen::MatrixXd CycleSeries::DifferencesFromReference(const std::vector<int>& pose_subset) const {
  std::vector<int> poses = pose_subset;
  if (poses.empty()) {
    for (int i = 0; i < NumPoses(); ++i) poses.push_back(i);
  }
  Eigen::MatrixXd y(3 * poses.size(), NumCycles());
  for (int c = 0; c < NumCycles(); ++c) {
    for (std::size_t k = 0; k < poses.size(); ++k) {
      y.block<3, 1>(3 * k, c) = cycles[c].position_mm[poses[k]] - cycles[0].position_mm[poses[k]];
    }
  }
  return y;
}

std::vector<std::vector<Mat3>> CycleSeries::DifferenceCovariances(double robot_noise_mm) const {
  std::vector<std::vector<Mat3>> out;
  if (!has_covariance || cycles.empty()) return out;
  for (const Cycle& c : cycles) {
    std::vector<Mat3> per_pose(c.covariance_mm2.size());
    for (std::size_t k = 0; k < per_pose.size(); ++k) per_pose[k] = c.covariance_mm2[k] + cycles[0].covariance_mm2[k] +
                    2.0 * robot_noise_mm * robot_noise_mm * Mat3::Identity();
    out.push_back(std::move(per_pose));
  }
  return out;
}

CycleSeries GroupCycles(const kinematics::RobotMeasurementSet& set, const std::string& path,
                        const CycleOptions& options) {
  ThrowIfInvalid(options.Validate(), "CycleOptions");
  const char* index_name = set.kind == kinematics::MeasurementKind::kBall ? "pose" : "point";
  CycleSeries series;
  series.path = path;
  series.extra_columns = set.extra_columns;
  series.has_covariance = kinematics::HasCentreCovariance(set, path);

  std::map<int, std::vector<const kinematics::RobotMeasurement*>> by_cycle;
  for (const auto& row : set.rows) by_cycle[row.cycle].push_back(&row);
  const auto ref_it = by_cycle.find(options.reference_cycle);
  if (ref_it == by_cycle.end()) {
    throw InputError({path, 0, "cycle"}, "the cold reference cycle " + std::to_string(options.reference_cycle) +
                                             " is missing (every drift is measured against it)");
  }
  std::map<int, JointVector> reference;
  for (const auto* row : ref_it->second) {
    if (!reference.emplace(row->index, row->q_controller).second) {
      throw InputError({path, row->line, index_name}, std::string(index_name) + " " + std::to_string(row->index) +
                                                          " appears twice in cycle " + std::to_string(row->cycle));
    }
  }
  for (const auto& [id, q] : reference) {
    series.ids.push_back(id);
    series.taught.push_back(q);
  }
  const double tol = DegToRad(options.joint_tolerance_deg);
  for (const auto& [cycle_number, rows] : by_cycle) {
    if (cycle_number < options.reference_cycle) continue;
    Cycle cycle;
    cycle.cycle = cycle_number;
    cycle.position_mm.assign(series.ids.size(), Vec3::Zero());
    cycle.q_controller.assign(series.ids.size(), JointVector::Zero());
    cycle.pose_time_s.assign(series.ids.size(), 0.0);
    if (series.has_covariance) cycle.covariance_mm2.assign(series.ids.size(), Mat3::Zero());
    std::vector<bool> seen(series.ids.size(), false);
    double time_sum = 0.0;
    for (const auto* row : rows) {
      const auto it = std::lower_bound(series.ids.begin(), series.ids.end(), row->index);
      if (it == series.ids.end() || *it != row->index) {
        throw InputError({path, row->line, index_name},
                         std::string(index_name) + " " + std::to_string(row->index) + " of cycle " +
                             std::to_string(cycle_number) + " is not in the reference cycle " +
                             std::to_string(options.reference_cycle) + " (pose sets differ between cycles)");
      }
      const std::size_t k = static_cast<std::size_t>(it - series.ids.begin());
      if (seen[k]) {
        throw InputError({path, row->line, index_name}, std::string(index_name) + " " + std::to_string(row->index) +
                                                            " appears twice in cycle " + std::to_string(cycle_number));
      }
      seen[k] = true;
      const double dq = (row->q_controller - series.taught[k]).cwiseAbs().maxCoeff();
      if (dq > tol) {
        throw InputError({path, row->line, "q1..q6"},
                         std::string(index_name) + " " + std::to_string(row->index) + " of cycle " +
                             std::to_string(cycle_number) + " has joints " + std::to_string(RadToDeg(dq)) +
                             " deg away from the reference cycle's (pose sets differ between cycles)");
      }
      cycle.position_mm[k] = row->position_mm;
      cycle.q_controller[k] = row->q_controller;
      if (series.has_covariance) cycle.covariance_mm2[k] = kinematics::CentreCovariance(*row, path);
      cycle.pose_time_s[k] = row->time_s;
      time_sum += row->time_s;
      for (const auto& [name, value] : row->extra) cycle.extra[name] += value / static_cast<double>(rows.size());
    }
    for (std::size_t k = 0; k < seen.size(); ++k) {
      if (!seen[k]) {
        throw InputError({path, rows.front()->line, index_name}, "cycle " + std::to_string(cycle_number) + " lacks " +
                                                                     index_name + " " + std::to_string(series.ids[k]) +
                                                                     " (pose sets differ between cycles)");
      }
    }
    cycle.time_s = time_sum / static_cast<double>(rows.size());
    series.cycles.push_back(std::move(cycle));
  }
  return series;
}

}  // namespace ramtk::thermal
