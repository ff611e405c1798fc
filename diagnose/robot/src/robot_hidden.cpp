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
#include "robot_causes.h"

namespace ramtk::diagnose {
namespace {

using kinematics::ParamIndex;
using kinematics::ParamKind;
using robot_detail::Fmt;

// Moves every simulated measurement by the registered cause's displacement.
void PlantExtraCause(const RobotColumnCause& cause, robot_detail::PlantContext* p) {
  if (!cause.displacement) throw InputError({"", 0, "HiddenRobotOptions.effect"}, "cause '" + std::string(cause.info.name) + "' cannot be planted");
  p->draw->truth = cause.truth;
  p->draw->description = std::string(cause.info.name) + " planted";
  auto& rows = p->result->ball.rows;
  const double t0 = rows.empty() ? 0.0 : rows[0].time_s;
  for (auto& m : rows) {
    RobotPlantRow r;
    r.q = m.q_controller, r.time_h = (m.time_s - t0) / 3600.0, r.cycle = m.cycle, r.model = p->model;
    r.sensor_from_base = p->result->setup.sensor_from_base, r.ball_in_flange = p->result->setup.ball_in_flange;
    m.position_mm += r.sensor_from_base.linear() * cause.displacement(r);
  }
}

}  // namespace

std::vector<std::string> DrawnRobotEffects() {
  std::vector<std::string> out;
  for (const robot_detail::RobotCause& c : robot_detail::RobotCauses())
    if (c.code.plant_before != nullptr || c.code.plant_after != nullptr) out.push_back(c.name);
  return out;
}

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
  robot_detail::PlantContext plant;
  plant.random.rng = &rng;
  plant.options = &options;
  plant.model = &model;
  const std::vector<std::string> drawn = DrawnRobotEffects();
  HiddenRobotDraw draw;
  draw.seed = seed;
  plant.draw = &draw;
  const robot_detail::RobotCause* cause = nullptr;
  if (!options.effect.empty()) {
    for (const robot_detail::RobotCause& c : robot_detail::RobotCauses())
      if (c.name == options.effect) cause = &c;
    if (cause == nullptr) throw InputError({"", 0, "HiddenRobotOptions.effect"}, "unknown cause '" + options.effect + "'");
  } else if (!(plant.random.U01() < options.none_probability)) {
    const std::string& name = drawn[plant.random.Pick(static_cast<int>(drawn.size()))];
    for (const robot_detail::RobotCause& c : robot_detail::RobotCauses())
      if (c.name == name) cause = &c;
  }
  draw.effect = cause == nullptr ? kNoEffect : cause->name;

  thermal::ThermalSimOptions o = thermal::ThesisPreset(seed);
  plant.preset_drifts = o.drifts;
  o.drifts.clear();
  o.cycles = options.cycles;
  o.ball_poses = options.poses;
  o.cycle_period_s = options.cycle_period_s;
  o.monitoring_points = 1;
  kinematics::RobotModel truth = model;
  plant.truth = &truth;
  plant.sim = &o;
  if (cause != nullptr && cause->code.plant_before != nullptr) cause->code.plant_before(&plant);
  thermal::ThermalSimResult sim = thermal::SimulateThermal(truth, o);
  plant.result = &sim;
  if (cause != nullptr && cause->code.plant_after != nullptr) cause->code.plant_after(&plant);
  if (cause != nullptr && cause->extra) PlantExtraCause(*cause->extra, &plant);
  if (draw.effect == kNoEffect) draw.description = "nothing hidden";

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
