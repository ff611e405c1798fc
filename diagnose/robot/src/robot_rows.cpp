#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/jacobian.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/tracker_io.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/diagnose/robot/detail/robot_linear.h"

namespace ramtk::diagnose {
std::string ResolveRobotModelPath(const std::string& name_or_path) {
  static const std::map<std::string, std::string> bundled = {
      {"kr150", "kuka_kr150_r3100.yaml"}, {"bx200l", "kawasaki_bx200l.yaml"}, {"ur10", "ur10.yaml"}};
  const auto it = bundled.find(name_or_path);
  if (it == bundled.end() || std::filesystem::exists(name_or_path)) return name_or_path;
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("RAMTK_ROBOTS_DIR")) dirs.push_back(env);
    // Installed data first, so an installed ramtk never reads a developer's checkout; the source
    // tree's datasets/robots last, for the build tree.
#ifdef RAMTK_DIAGNOSE_INSTALLED_ROBOTS_DIR
  dirs.push_back(RAMTK_DIAGNOSE_INSTALLED_ROBOTS_DIR);
#endif
#ifdef RAMTK_DIAGNOSE_ROBOTS_DIR
  dirs.push_back(RAMTK_DIAGNOSE_ROBOTS_DIR);
#endif
  for (const std::string& d : dirs) {
    const std::filesystem::path p = std::filesystem::path(d) / it->second;
    if (std::filesystem::exists(p)) return p.string();
  }
  throw InputError({"", 0, "--model"}, "bundled robot '" + name_or_path + "' (" + it->second +
                                           ") not found; set RAMTK_ROBOTS_DIR or pass the YAML path");
}

RobotDiagnoseInput ReadRobotDiagnoseInput(const DiagnoseOptions& options) {
  RobotDiagnoseInput in;
  const std::string model_path = ResolveRobotModelPath(options.model.empty() ? "kr150" : options.model);
  in.model = kinematics::ReadRobotModel(model_path);
  in.chain = kinematics::ReadRobotChain(model_path);
  in.model_label = std::filesystem::path(model_path).filename().string();
  in.ball_path = options.data;
  std::string format_path;
  for (const std::string& w : options.with) {
    const std::string ext = std::filesystem::path(w).extension().string();
    if (ext == ".yaml" || ext == ".yml") format_path = w;
  }
  in.ball = format_path.empty() ? kinematics::ReadRobotMeasurements(options.data)
                                : kinematics::BallSetFromTracker(
                                      kinematics::ReadTrackerMeasurements(options.data,
                                                                          kinematics::ReadTrackerFormat(format_path)),
                                      options.data);
  if (in.ball.kind != kinematics::MeasurementKind::kBall)
    throw InputError({options.data, 1, "pose"},
                     "diagnose needs ball measurements (a `pose` column), not monitoring points");
  for (const std::string& w : options.with) {
    const std::string ext = std::filesystem::path(w).extension().string();
    if (w.rfind("thermal=", 0) == 0) {
      const std::string value = w.substr(8);
      in.thermal_label = value;
      if (value != "none") in.thermal_params = thermal::ParseParamList(value, in.model, "--with thermal");
      if (value == "none") in.thermal_label.clear();
    } else if (ext == ".yaml" || ext == ".yml") {
      continue;  // the tracker format of the data, read above
    } else if (ext == ".json") {
      in.setup = thermal::ReadThermalSetup(w);
      in.has_setup = true;
    } else if (ext == ".csv") {
      in.monitoring = kinematics::ReadRobotMeasurements(w);
      if (in.monitoring.kind != kinematics::MeasurementKind::kMonitoring)
        throw InputError({w, 1, "point"}, "--with CSV must hold monitoring points (a `point` column)");
      in.monitoring_path = w;
      in.has_monitoring = true;
    } else {
      throw InputError({"", 0, "--with"},
                       "'" + w + "' is none of: set-up JSON, monitoring CSV, thermal=traditional|<params>|none");
    }
  }
  return in;
}

namespace robot_detail {

RowSet BuildRows(const RobotDiagnoseInput& in) {
  RowSet out;
  const auto& src = in.ball.rows;
  if (src.size() < 6)
    throw InputError({in.ball_path, 0, "rows"},
                     "needs at least 6 ball measurements, got " + std::to_string(src.size()));
  std::set<int> cycles, poses;
  for (const auto& m : src) cycles.insert(m.cycle), poses.insert(m.index);
  out.cycle_numbers.assign(cycles.begin(), cycles.end());
  out.pose_ids.assign(poses.begin(), poses.end());
  out.num_cycles = static_cast<int>(out.cycle_numbers.size());
  out.extra_columns = in.ball.extra_columns;
  if (in.has_setup) {
    out.setup = in.setup;
    out.setup_note = "set-up given";
  } else {
    std::vector<calib::BallObservation> obs;
    for (const auto& m : src)
      if (m.cycle == out.cycle_numbers[0]) obs.push_back({m.q_controller, m.position_mm, m.index, m.line});
    if (obs.size() < 5) {
      obs.clear();
      for (const auto& m : src) obs.push_back({m.q_controller, m.position_mm, m.index, m.line});
    }
    calib::SensorRobotSummary summary;
    const calib::SensorRobotCalibration cal = calib::CalibrateSensorRobot(in.model, obs, {}, &summary);
    out.setup.sensor_from_base = cal.sensor_from_base;
    out.setup.ball_in_flange = cal.ball_in_flange;
    out.setup_note = "set-up calibrated from cycle " + std::to_string(out.cycle_numbers[0]) + " (" +
                     std::to_string(obs.size()) + " poses, RMS " + std::to_string(summary.rms_mm) + " mm)";
  }
  const Eigen::Matrix3d r_s = out.setup.sensor_from_base.linear();
  double t0 = src[0].time_s;
  for (const auto& m : src) t0 = std::min(t0, m.time_s);
  std::map<int, int> cycle_pos;
  for (int i = 0; i < out.num_cycles; ++i) cycle_pos[out.cycle_numbers[i]] = i;
  out.rows.reserve(src.size());
  for (const auto& m : src) {
    Row r;
    r.cycle = m.cycle;
    r.cycle_pos = cycle_pos[m.cycle];
    r.pose = m.index;
    r.time_h = (m.time_s - t0) / 3600.0;
    r.q = m.q_controller;
    r.measured = m.position_mm;
    r.extra = m.extra;
    const Isometry3 base_from_flange = kinematics::BaseFromFlange(in.model, m.q_controller);
    r.predicted = out.setup.sensor_from_base * (base_from_flange * out.setup.ball_in_flange);
    r.residual = r.measured - r.predicted;
    r.j_param = r_s * kinematics::ComputePointParamJacobian(in.model, m.q_controller, out.setup.ball_in_flange);
    r.ball_dir = r_s * base_from_flange.linear();
    r.j_setup.block<3, 3>(0, 0) = -Skew(r.predicted);
    r.j_setup.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity();
    r.j_setup.block<3, 3>(0, 6) = r.ball_dir;
    if (!r.residual.allFinite())
      throw InputError({in.ball_path, m.line, "x"}, "measurement or prediction is not finite");
    out.rows.push_back(std::move(r));
  }
  return out;
}

double EstimateNoiseFromCycles(const std::vector<Row>& rows, int* pairs) {
  // Successive cycles of the same pose: the difference of the measurements holds two noise draws
  // and the (slow) drift over one cycle.
  std::map<int, std::vector<const Row*>> by_pose;
  for (const Row& r : rows) by_pose[r.pose].push_back(&r);
  std::vector<double> d;
  for (auto& [pose, list] : by_pose) {
    std::sort(list.begin(), list.end(), [](const Row* a, const Row* b) { return a->cycle_pos < b->cycle_pos; });
    for (size_t k = 1; k < list.size(); ++k) {
      if (list[k]->cycle_pos != list[k - 1]->cycle_pos + 1) continue;
      if ((list[k]->q - list[k - 1]->q).cwiseAbs().maxCoeff() > 1e-6) continue;
      const Eigen::Vector3d diff = list[k]->measured - list[k - 1]->measured;
      for (int a = 0; a < 3; ++a) d.push_back(diff[a]);
    }
  }
  *pairs = static_cast<int>(d.size() / 3);
  if (*pairs < 10) return 0.0;
  std::vector<double> abs_d(d.size());
  for (size_t i = 0; i < d.size(); ++i) abs_d[i] = std::abs(d[i]);
  std::nth_element(abs_d.begin(), abs_d.begin() + abs_d.size() / 2, abs_d.end());
  const double robust = 1.4826 * abs_d[abs_d.size() / 2];
  // Gaussian-efficient second pass: RMS of the differences within 4 robust σ (the trimmed share
  // of a Gaussian, 6e-5, biases σ by < 0.1 %).
  double ss = 0;
  int n = 0;
  for (double v : d)
    if (std::abs(v) <= 4.0 * robust) ss += v * v, ++n;
  return n > 0 ? std::sqrt(ss / n / 2.0) : robust / std::sqrt(2.0);
}

}  // namespace robot_detail
}  // namespace ramtk::diagnose
