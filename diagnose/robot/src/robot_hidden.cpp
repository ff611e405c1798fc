#include "ramtk/diagnose/robot/robot_hidden.h"

#include <Eigen/Geometry>
#include <random>

#include "ramtk/calib/robot_calibration_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/tracker_io.h"
#include "ramtk/thermal/simulator.h"
#include "robot_linear.h"

namespace ramtk::diagnose {
namespace {

using kinematics::ParamIndex;
using kinematics::ParamKind;

std::string Fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}

}  // namespace

std::string HiddenRobotOptions::Validate() const {
  if (cycles < 4) return "cycles must be >= 4";
  if (poses < 8) return "poses must be >= 8";
  if (!(cycle_period_s > 0)) return "cycle_period_s must be > 0";
  if (!(none_probability >= 0 && none_probability <= 1)) return "none_probability must be in [0, 1]";
  return "";
}

HiddenRobotDraw DrawHiddenRobotEffect(const kinematics::RobotModel& model, std::uint64_t seed,
                                      const HiddenRobotOptions& options) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw InputError({"", 0, "HiddenRobotOptions"}, problem);
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 17);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto uniform = [&](double a, double b) { return a + (b - a) * u01(rng); };
  auto sign = [&]() { return u01(rng) < 0.5 ? -1.0 : 1.0; };
  auto pick = [&](int n) { return std::min(n - 1, static_cast<int>(u01(rng) * n)); };
  auto unit = [&]() {
    std::normal_distribution<double> n01;
    Eigen::Vector3d v(n01(rng), n01(rng), n01(rng));
    return Eigen::Vector3d(v.normalized());
  };
  static const char* effects[7] = {"joint_offset",        "link_length_error", "thermal_length_drift",
                                   "thermal_angle_drift", "joint_compliance",  "sensor_frame_drift",
                                   "tool_offset_change"};
  HiddenRobotDraw draw;
  draw.seed = seed;
  draw.effect = u01(rng) < options.none_probability ? kNoEffect : effects[pick(7)];

  thermal::ThermalSimOptions o = thermal::ThesisPreset(seed);
  const std::vector<thermal::ParamDrift> preset_drifts = o.drifts;
  o.drifts.clear();
  o.cycles = options.cycles;
  o.ball_poses = options.poses;
  o.cycle_period_s = options.cycle_period_s;
  o.monitoring_points = 1;
  kinematics::RobotModel truth = model;
  std::string& what = draw.description;

  if (draw.effect == "joint_offset") {
    const int j = 1 + pick(4);  // θ2..θ5: θ1 turns like the sensor frame, θ6 like the ball offset
    const double delta = sign() * uniform(0.004, 0.03);
    truth.links[j].theta0 += DegToRad(delta);
    draw.truth["theta" + std::to_string(j + 1) + "_offset_deg"] = delta;
    what = "theta" + std::to_string(j + 1) + " zero off by " + Fmt(delta) + " deg";
  } else if (draw.effect == "link_length_error") {
    static const int params[4] = {ParamIndex(ParamKind::kA, 0), ParamIndex(ParamKind::kA, 1),
                                  ParamIndex(ParamKind::kA, 2), ParamIndex(ParamKind::kD, 3)};
    const int p = params[pick(4)];
    const double delta = sign() * uniform(0.1, 1.0);
    kinematics::ParamVector x = truth.Params();
    x[p] += delta;
    truth.SetParams(x);
    draw.truth[kinematics::ParamName(p) + "_error_mm"] = delta;
    what = kinematics::ParamName(p) + " off by " + Fmt(delta) + " mm";
  } else if (draw.effect == "thermal_length_drift" || draw.effect == "thermal_angle_drift") {
    const bool angles = draw.effect == "thermal_angle_drift";
    for (const auto& d : preset_drifts) {
      if (kinematics::IsAngleParam(d.param)) continue;
      thermal::ParamDrift scaled = d;
      const double f = angles ? uniform(0.5, 1.5) : uniform(0.5, 2.0);
      for (double& k : scaled.per_kelvin) k *= f;
      o.drifts.push_back(scaled);
    }
    what = "length drift (thesis d4 d6 a1 a2 a3, scaled)";
    if (angles) {
      static const int pool[10] = {ParamIndex(ParamKind::kTheta, 1), ParamIndex(ParamKind::kTheta, 2),
                                   ParamIndex(ParamKind::kTheta, 3), ParamIndex(ParamKind::kTheta, 4),
                                   ParamIndex(ParamKind::kAlpha, 0), ParamIndex(ParamKind::kAlpha, 1),
                                   ParamIndex(ParamKind::kAlpha, 2), ParamIndex(ParamKind::kAlpha, 3),
                                   ParamIndex(ParamKind::kAlpha, 4), ParamIndex(ParamKind::kBeta, 1)};
      const int count = 1 + pick(2);
      std::vector<int> chosen;
      while (static_cast<int>(chosen.size()) < count) {
        const int p = pool[pick(10)];
        if (std::find(chosen.begin(), chosen.end(), p) == chosen.end()) chosen.push_back(p);
      }
      for (int p : chosen) {
        thermal::ParamDrift d;
        d.param = p;
        d.per_kelvin.assign(6, 0.0);
        const int joint = 1 + pick(3);  // heated by joint 2, 3 or 4
        const double k = sign() * uniform(4e-6, 15e-6);
        d.per_kelvin[joint] = k;
        o.drifts.push_back(d);
        draw.truth[kinematics::ParamName(p) + "_urad_per_K"] = k * 1e6;
        what += " + " + kinematics::ParamName(p) + " " + Fmt(k * 1e6) + " µrad/K of joint " + std::to_string(joint + 1);
      }
    }
  }
  thermal::ThermalSimResult sim = thermal::SimulateThermal(truth, o);
  const Isometry3& sensor_from_base = sim.setup.sensor_from_base;
  const Eigen::Vector3d& ball = sim.setup.ball_in_flange;
  double t0 = sim.ball.rows.empty() ? 0.0 : sim.ball.rows[0].time_s;

  if (draw.effect == "joint_compliance") {
    const double c2 = uniform(30, 150), c3 = uniform(30, 150);  // µrad per kN·m
    draw.truth["joint2_compliance_urad_per_kNm"] = c2;
    draw.truth["joint3_compliance_urad_per_kNm"] = c3;
    what = "gravity compliance of joints 2, 3: " + Fmt(c2) + ", " + Fmt(c3) + " µrad/(kN·m)";
    for (auto& m : sim.ball.rows) {
      const Eigen::Matrix<double, 6, 1> tau = robot_detail::GravityTorques(model, m.q_controller, ball) / 1000.0;
      kinematics::RobotModel bent = model;
      bent.links[1].theta0 += c2 * 1e-6 * tau[1];
      bent.links[2].theta0 += c3 * 1e-6 * tau[2];
      m.position_mm += sensor_from_base.linear() * (kinematics::BaseFromFlange(bent, m.q_controller) * ball -
                                                    kinematics::BaseFromFlange(model, m.q_controller) * ball);
    }
  } else if (draw.effect == "sensor_frame_drift") {
    const Eigen::Vector3d w = unit() * uniform(30, 150) * 1e-6, v = unit() * uniform(0.05, 0.3);  // per hour
    draw.truth["rotation_urad_per_h"] = w.norm() * 1e6;
    draw.truth["translation_mm_per_h"] = v.norm();
    what = "sensor drifts " + Fmt(w.norm() * 1e6) + " µrad/h and " + Fmt(v.norm()) + " mm/h";
    for (auto& m : sim.ball.rows) {
      const double t = (m.time_s - t0) / 3600.0;
      m.position_mm = Eigen::AngleAxisd(w.norm() * t, w.normalized()) * m.position_mm + v * t;
    }
  } else if (draw.effect == "tool_offset_change") {
    const Eigen::Vector3d shift = unit() * uniform(0.05, 0.3);
    const int from = options.cycles / 4 + pick(options.cycles / 2);
    draw.truth["shift_mm"] = shift.norm();
    draw.truth["from_cycle"] = from;
    what = "ball moves " + Fmt(shift.norm()) + " mm on the flange at cycle " + std::to_string(from);
    for (auto& m : sim.ball.rows)
      if (m.cycle >= from)
        m.position_mm += sensor_from_base.linear() * kinematics::BaseFromFlange(model, m.q_controller).linear() * shift;
  }
  if (draw.effect == kNoEffect) what = "nothing hidden";

  draw.input.model = model;
  draw.input.model_label = model.name;
  draw.input.setup = sim.setup;
  draw.input.has_setup = true;
  draw.input.ball = std::move(sim.ball);
  draw.input.ball_path = "hidden-effect draw " + std::to_string(seed);
  return draw;
}

HiddenRobotDraw DrawHiddenGeometricErrors(const kinematics::RobotModel& model, std::uint64_t seed, int poses) {
  if (poses < 30) throw InputError({"", 0, "poses"}, "at least 30 poses");
  std::mt19937_64 rng(seed * 0xD1B54A32D192ED03ull + 29);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto uniform = [&](double a, double b) { return a + (b - a) * u01(rng); };
  auto sign = [&]() { return u01(rng) < 0.5 ? -1.0 : 1.0; };
  auto pick = [&](int n) { return std::min(n - 1, static_cast<int>(u01(rng) * n)); };
  HiddenRobotDraw draw;
  draw.seed = seed;
  draw.effect = "joint_offset+link_length_error+axis_misalignment";
  kinematics::RobotModel truth = model;
  kinematics::ParamVector x = truth.Params();
  // One joint zero (θ2..θ5), one length (a1 a2 a3 d4), one twist (α2..α4): none aliased with the set-up.
  const int offset = ParamIndex(ParamKind::kTheta, 1 + pick(4));
  static const int lengths[4] = {ParamIndex(ParamKind::kA, 0), ParamIndex(ParamKind::kA, 1),
                                 ParamIndex(ParamKind::kA, 2), ParamIndex(ParamKind::kD, 3)};
  const int length = lengths[pick(4)];
  const int twist = ParamIndex(ParamKind::kAlpha, 1 + pick(3));
  const double d_offset = sign() * uniform(0.01, 0.03), d_length = sign() * uniform(0.3, 1.0),
               d_twist = sign() * uniform(0.01, 0.03);
  x[offset] += DegToRad(d_offset);
  x[length] += d_length;
  x[twist] += DegToRad(d_twist);
  truth.SetParams(x);
  draw.truth[kinematics::ParamName(offset) + "_offset_deg"] = d_offset;
  draw.truth[kinematics::ParamName(length) + "_error_mm"] = d_length;
  draw.truth[kinematics::ParamName(twist) + "_twist_deg"] = d_twist;
  draw.description = kinematics::ParamName(offset) + " off by " + Fmt(d_offset) + " deg, " +
                     kinematics::ParamName(length) + " by " + Fmt(d_length) + " mm, " + kinematics::ParamName(twist) +
                     " by " + Fmt(d_twist) + " deg";
  // A tracker session over the workspace (calib/robot_calibration_sim.h), the truth's links.
  calib::RobotCalibrationSimOptions so;
  so.num_poses = poses;
  so.length_error_mm = 0.0;
  so.angle_error_deg = 0.0;
  so.position_noise_mm = 0.01;
  so.seed = seed;
  so.noise_seed = seed;
  const calib::RobotCalibrationSimulation sim = calib::SimulateRobotCalibration(kinematics::ChainFromRobotModel(truth), so);
  draw.input.model = model;
  draw.input.model_label = model.name;
  draw.input.setup.sensor_from_base = so.tracker_from_base;
  draw.input.setup.ball_in_flange = so.targets_in_flange.front();
  draw.input.has_setup = true;
  draw.input.ball = kinematics::BallSetFromTracker(sim.data, "hidden geometric errors");
  for (auto& m : draw.input.ball.rows) m.time_s = 20.0 * m.index;
  draw.input.ball_path = "hidden geometric errors, tracker session " + std::to_string(seed);
  return draw;
}

}  // namespace ramtk::diagnose
