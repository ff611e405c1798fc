#include "ramtk/calib/sensor_robot_io.h"

#include <nlohmann/json.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

nlohmann::json Vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<BallObservation> ReadBallObservations(const std::string& path) {
  return BallObservationsFromMeasurements(kinematics::ReadRobotMeasurements(path), path);
}

std::string SensorRobotResultJson(const SensorRobotCalibration& c, const SensorRobotSummary& s,
                                  const std::vector<BallObservation>& obs) {
  nlohmann::json j;
  j["method"] = s.method;
  j["sensor_from_base"] = PoseToJson(c.sensor_from_base);
  j["sensor_from_base"]["orthonormality_error"] = c.orthonormality_error;
  j["ball_in_flange_mm"] = Vec(c.ball_in_flange);
  if (c.has_covariance) {
    j["std"]["rotation_arcsec"] = Vec(c.RotationStdArcsec());
    j["std"]["translation_mm"] = Vec(c.TranslationStdMm());
    j["std"]["ball_in_flange_mm"] = Vec(c.BallStdMm());
    // Rows/columns: rotation vector φ (deg; R = Exp(φ)·R̂, sensor frame), t_s (mm), P_e (mm).
    Eigen::Matrix<double, 9, 9> scale = Eigen::Matrix<double, 9, 9>::Identity();
    scale.topLeftCorner<3, 3>() *= kDegPerRad;
    const Eigen::Matrix<double, 9, 9> cov = scale * c.covariance * scale;
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 9; ++r) {
      nlohmann::json row = nlohmann::json::array();
      for (int k = 0; k < 9; ++k) row.push_back(cov(r, k));
      rows.push_back(row);
    }
    j["covariance"]["order"] = {"phi_x_deg", "phi_y_deg", "phi_z_deg", "tx_mm",    "ty_mm",
                                "tz_mm",     "ball_x_mm", "ball_y_mm", "ball_z_mm"};
    j["covariance"]["matrix"] = rows;
  } else {
    j["covariance"] = nullptr;
  }
  nlohmann::json res = nlohmann::json::array();
  for (std::size_t i = 0; i < c.residuals_mm.size(); ++i) {
    nlohmann::json r;
    r["pose"] = i < obs.size() ? obs[i].pose : static_cast<int>(i);
    r["line"] = i < obs.size() ? obs[i].line : 0;
    r["residual_mm"] = Vec(c.residuals_mm[i]);
    r["norm_mm"] = c.residuals_mm[i].norm();
    res.push_back(r);
  }
  j["residuals"] = res;
  j["rms_mm"] = c.rms_mm;
  j["max_residual_mm"] = c.max_residual_mm;
  nlohmann::json sj;
  sj["termination"] = SensorRobotTerminationText(s.termination);
  sj["iterations"] = s.iterations;
  sj["initial_cost"] = s.initial_cost;
  sj["final_cost"] = s.final_cost;
  sj["worst_pose_index"] = s.worst_pose;
  sj["outliers"] = s.outliers;
  sj["num_poses"] = s.diagnostics.num_poses;
  sj["rotation_spread_deg"] = s.diagnostics.rotation_spread_deg;
  sj["min_axis_spread_deg"] = s.diagnostics.min_axis_spread_deg;
  sj["condition_number"] = s.diagnostics.condition_number;
  sj["warnings"] = s.warnings;
  sj["weighted_by_centre_covariance"] = s.weighted;
  sj["held_out_rms_mm"] = s.held_out_rms_mm;
  sj["jackknife_ratio"] = s.jackknife_ratio;
  sj["covariance_source"] = s.covariance_source;
  sj["brief"] = s.BriefReport();
  j["summary"] = sj;
  return j.dump(2) + "\n";
}

void WriteSensorRobotResult(const std::string& path, const SensorRobotCalibration& calibration,
                            const SensorRobotSummary& summary, const std::vector<BallObservation>& obs) {
  WriteFileAtomically(path, SensorRobotResultJson(calibration, summary, obs));
}

}  // namespace ramtk::calib
