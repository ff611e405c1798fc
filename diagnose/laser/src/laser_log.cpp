// Laser device log against the ideal device, for the tool fitted to the log.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "ramtk/diagnose/laser/detail/laser_fit.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/diagnose/laser/laser.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/diagnose/engine/statistics.h"
#include "ramtk/tcf/geometry.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::diagnose {
namespace {

using laser_detail::CandidateOutcome;
using laser_detail::CandidateSpec;
using laser_detail::ResidualModel;

// Tool (tip in the flange, axis tilt) then the effects' parameters.
// Largest plausible tilt of the beam plane against the motion plane (deg).
constexpr double kMaxPlaneTiltDeg = 2.0;

enum Param {
  kTx,
  kTy,
  kTz,
  kAx,
  kAy,  // nuisance: the tool
  kBeta,
  kOffset,
  kWidth,
  kLatency,
  kSpeed,
  kTiltX,
  kTiltY,
  kNumParams
};

struct UsedEvent {
  tcf::BeamEvent event;
  int segment = 0;     // index into circles, then lines
  bool circle = true;  // on a circle (else a straight move)
  int direction = 0;   // +1 ccw, −1 cw, 0 straight move
  double start = 0.0;  // segment start (s)
};

Isometry3 ProgrammedPose(const tcf::ProgrammedMotion& m, const UsedEvent& u, double time_s) {
  const int nc = static_cast<int>(m.circles.size());
  return u.segment < nc ? m.circles[u.segment].BaseFromFlange(time_s) : m.lines[u.segment - nc].BaseFromFlange(time_s);
}

struct LogModel {
  const tcf::ProgrammedMotion* motion;
  Isometry3 frame;  // calibrated base_from_lasersensor
  std::vector<UsedEvent> used;

  // Clearance (mm) the model predicts at each logged instant: 0 for a perfect model.
  Eigen::VectorXd Residuals(const Eigen::VectorXd& q) const {
    const Mat3 r = frame.linear() * RotX(DegToRad(q(kTiltX))) * RotY(DegToRad(q(kTiltY)));
    const double beta = DegToRad(q(kBeta));
    const Vec3 point[2] = {frame.translation() + 0.5 * q(kOffset) * r.col(2),
                           frame.translation() - 0.5 * q(kOffset) * r.col(2)};
    const Vec3 dir[2] = {r.col(0), std::cos(beta) * r.col(0) + std::sin(beta) * r.col(1)};
    const Vec3 tcp(q(kTx), q(kTy), q(kTz));
    const Vec3 axis = Vec3(q(kAx), q(kAy), 1.0).normalized();
    const double radius = motion->tool_radius_mm;
    Eigen::VectorXd out(used.size());
    for (size_t i = 0; i < used.size(); ++i) {
      const UsedEvent& u = used[i];
      const double t = u.event.time_s - 1e-3 * q(kLatency);
      const double executed = u.start + (1.0 + 0.01 * q(kSpeed)) * (t - u.start);
      const Isometry3 f = ProgrammedPose(*motion, u, executed);
      const Vec3 a = f.linear() * axis;
      const Vec3 centre = f * tcp - radius * a;
      const int b = static_cast<int>(u.event.beam);
      out(i) = tcf::LineToRayDistance(point[b], dir[b], centre, -a) - radius - 0.5 * q(kWidth);
    }
    return out;
  }
};

// Events inside a programmed segment (a small margin after its end for a late receiver).
std::vector<UsedEvent> UsedEvents(const std::vector<tcf::BeamEvent>& events, const tcf::ProgrammedMotion& m) {
  std::vector<UsedEvent> out;
  const int nc = static_cast<int>(m.circles.size());
  for (const tcf::BeamEvent& e : events) {
    for (int s = 0; s < nc + static_cast<int>(m.lines.size()); ++s) {
      const double start = s < nc ? m.circles[s].start_time_s : m.lines[s - nc].start_time_s;
      const double dur = s < nc ? m.circles[s].duration_s : m.lines[s - nc].duration_s;
      if (e.time_s >= start && e.time_s <= start + dur + 0.03) {
        UsedEvent u;
        u.event = e;
        u.segment = s;
        u.circle = s < nc;
        u.direction = s < nc ? m.circles[s].direction : 0;
        u.start = start;
        out.push_back(u);
        break;
      }
    }
  }
  return out;
}

// The device-log model: residual of every used event, its cross-validation groups (one crossing,
// a blocked event and the clear event after it on the same segment and beam, per group), parameter
// names, steps and plausibility bounds. The residuals read `lm`, which must outlive the model.
ResidualModel MakeModel(const LogModel& lm, const Eigen::VectorXd& q0) {
  ResidualModel model;
  std::map<std::pair<int, int>, int> open;
  for (const UsedEvent& u : lm.used) {
    const std::pair<int, int> key(u.segment, static_cast<int>(u.event.beam));
    auto it = open.find(key);
    if (u.event.state == tcf::BeamState::kClear && it != open.end()) {
      model.group.push_back(it->second);
      open.erase(it);
    } else {
      model.group.push_back(model.num_groups);
      if (u.event.state == tcf::BeamState::kBlocked) open[key] = model.num_groups;
      ++model.num_groups;
    }
  }
  model.names = {"tcp_x_mm",   "tcp_y_mm",  "tcp_z_mm", "axis_x",     "axis_y",
                 "beta_deg",   "offset_mm", "width_mm", "latency_ms", "speed_error_percent",
                 "tilt_x_deg", "tilt_y_deg"};
  model.initial = q0;
  model.step = Eigen::VectorXd::Constant(kNumParams, 1e-4);
  model.step(kAx) = model.step(kAy) = 1e-6;
  model.residuals = [&lm](const Eigen::VectorXd& q) { return lm.Residuals(q); };
  // Plausibility bounds of the effects (the tool is free): a device mounted and checked by eye is
  // not tilted by degrees (docs/tcf.md: a 0.3° plane tilt is undetectable in these logs, so a fitted
  // tilt of several degrees stands for something else), beams are not 10° off square or mm apart,
  // a receiver answers within 50 ms and not before the event, a robot keeps its speed within 10 %.
  model.lower = Eigen::VectorXd::Constant(kNumParams, -INFINITY);
  model.upper = Eigen::VectorXd::Constant(kNumParams, INFINITY);
  model.lower(kBeta) = 80.0, model.upper(kBeta) = 100.0;
  model.lower(kOffset) = -3.0, model.upper(kOffset) = 3.0;
  model.lower(kWidth) = -0.1, model.upper(kWidth) = 5.0;
  model.lower(kLatency) = -1.0, model.upper(kLatency) = 50.0;
  model.lower(kSpeed) = -10.0, model.upper(kSpeed) = 10.0;
  model.lower(kTiltX) = model.lower(kTiltY) = -kMaxPlaneTiltDeg;
  model.upper(kTiltX) = model.upper(kTiltY) = kMaxPlaneTiltDeg;
  return model;
}

// Starting tool: the TCF solver's (ideal settings); the programme's nominal tool if it fails (with
// a note saying so).
Eigen::VectorXd StartingTool(const std::vector<tcf::BeamEvent>& events, const tcf::ProgrammedMotion& motion,
                             const tcf::SensorFrame& sensor, const DiagnoseOptions& options, std::string* start_note) {
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(kNumParams);
  q0(kBeta) = 90.0;
  q0(kTz) = 150.0;
  try {
    tcf::TcfSolverOptions so;
    so.self_calibrate_latency = so.self_calibrate_beam_offset = so.self_calibrate_speed = false;
    so.timing_sigma_s = so.repeatability_sigma_mm = 0.0;
    const tcf::TcfSummary s = tcf::SolveTcf(events, motion, sensor, so, options.data);
    q0.head<3>() = s.solution.tcp_in_flange;
    if (std::abs(s.solution.axis_in_flange.z()) > 0.1) {
      const Vec3 a = s.solution.axis_in_flange / s.solution.axis_in_flange.z();
      q0(kAx) = a.x();
      q0(kAy) = a.y();
    }
  } catch (const InputError&) {
    throw;  // bad files are the user's to fix, not a reason to guess a tool
  } catch (const std::exception& e) {
    *start_note = std::string("the TCF solver did not give a starting tool (") + e.what() +
                  "); the fit starts from the programme's nominal tool";
  }
  return q0;
}

// Structure tests of the ideal model's residual `r0` (scaled for the fitted tool) against the noise.
std::vector<TestResult> TestStructure(const LogModel& lm, const tcf::ProgrammedMotion& motion, const Eigen::VectorXd& r0,
                                      int num_base, double sigma) {
  const int n = static_cast<int>(lm.used.size());
  const double dof_scale = std::sqrt(static_cast<double>(n) / (n - static_cast<double>(num_base)));
  std::vector<double> scaled(n), state(n), beam(n), direction, circle_resid, circle_angle, elapsed(n);
  for (int i = 0; i < n; ++i) {
    const UsedEvent& u = lm.used[i];
    scaled[i] = r0(i) * dof_scale;
    state[i] = u.event.state == tcf::BeamState::kBlocked ? 1.0 : -1.0;
    beam[i] = u.event.beam == tcf::Beam::kX ? 1.0 : -1.0;
    elapsed[i] = u.event.time_s - u.start;
    if (u.circle) {
      direction.push_back(u.direction), circle_resid.push_back(scaled[i]);
      const tcf::CircleSegment& c = motion.circles[u.segment];
      circle_angle.push_back(c.AngleAt(u.event.time_s) - c.start_angle_rad);
    }
  }
  std::vector<TestResult> tests = {VarianceTest(scaled, {sigma}), TrendTest(scaled, {sigma}, state, 1, "state"),
                                   TrendTest(scaled, {sigma}, beam, 1, "beam"),
                                   TrendTest(scaled, {sigma}, elapsed, 1, "time in segment")};
  if (!circle_resid.empty()) tests.push_back(TrendTest(circle_resid, {sigma}, direction, 1, "direction cw/ccw"));
  // A speed that varies along the circle (servo ripple) shifts the crossings periodically in the
  // angle travelled: once and twice per turn.
  if (circle_resid.size() > 8)
    tests.push_back(HarmonicTrendTest(circle_resid, {sigma}, circle_angle, 2, "angle along the circle"));
  return tests;
}

// The held-out residual pictures before and after the chosen extension into `folder`.
void WriteLaserPictures(const LogModel& lm, const tcf::ProgrammedMotion& motion, const CandidateOutcome& ideal,
                        const CandidateOutcome& final_outcome, double sigma, const std::string& folder,
                        Diagnosis* out) {
  Diagnosis& d = *out;
  const int n = static_cast<int>(lm.used.size());
  std::filesystem::create_directories(folder);
  const Eigen::VectorXd before = ideal.heldout_resid, after = final_outcome.heldout_resid;
  const Eigen::VectorXd fitted_tool = ideal.full.params;
  auto series = [](const char* label) {
    report::Series s;
    s.label = label;
    return s;
  };
  report::Series ccw = series("ccw circles"), cw = series("cw circles"), fixed = series("after the extension");
  report::Series xs = series("x beam"), ys = series("y beam");
  report::Series circ = series("circles"), lines = series("straight moves");
  report::Series blocked = series("blocked"), clear = series("clear");
  for (int i = 0; i < n; ++i) {
    const UsedEvent& u = lm.used[i];
    const double y = before(i);
    if (u.circle) {
      const tcf::CircleSegment& c = motion.circles[u.segment];
      double ang = std::fmod(RadToDeg(c.AngleAt(u.event.time_s)), 360.0);
      if (ang < 0) ang += 360.0;
      (u.direction > 0 ? ccw : cw).x.push_back(ang);
      (u.direction > 0 ? ccw : cw).y.push_back(y);
      fixed.x.push_back(ang);
      fixed.y.push_back(after(i));
    }
    report::Series& by_beam = u.event.beam == tcf::Beam::kX ? xs : ys;
    by_beam.x.push_back(u.segment + 1 +
                        0.6 * (u.event.time_s - u.start) /
                            (u.circle ? motion.circles[u.segment].duration_s
                                      : motion.lines[u.segment - motion.circles.size()].duration_s));
    by_beam.y.push_back(y);
    // Height of the fitted tip above the beam plane at the event.
    const Isometry3 f = ProgrammedPose(motion, u, u.event.time_s);
    const Vec3 tip = lm.frame.inverse() * (f * Vec3(fitted_tool(kTx), fitted_tool(kTy), fitted_tool(kTz)));
    (u.circle ? circ : lines).x.push_back(-tip.z());
    (u.circle ? circ : lines).y.push_back(y);
    (u.event.state == tcf::BeamState::kBlocked ? blocked : clear).x.push_back(u.event.time_s - u.start);
    (u.event.state == tcf::BeamState::kBlocked ? blocked : clear).y.push_back(y);
  }
  const std::string y_label = "clearance at the logged instant, held out (mm)";
  AddFigure(OnePanel("residual_vs_angle",
                     "Held-out residual of the circle events against the crossing angle, ccw and cw circles, "
                     "and after the chosen extension",
                     "Residual vs crossing angle, ccw vs cw (and after " + d.cause + ")",
                     "programmed circle angle at the event (deg)", y_label, {ccw, cw, fixed}, sigma),
            folder, &d.pictures);
  AddFigure(OnePanel("residual_by_circle", "Held-out residual per circle and straight move, by beam",
                     "Residual by segment (circles first, then straight moves)",
                     "segment number + fraction of the segment elapsed", y_label, {xs, ys}, sigma),
            folder, &d.pictures);
  AddFigure(OnePanel("residual_vs_height", "Held-out residual against the height of the tool in the beams",
                     "Residual vs height of the fitted tip below the beam plane",
                     "tip height below the beam plane (mm)", y_label, {circ, lines}, sigma),
            folder, &d.pictures);
  AddFigure(OnePanel("residual_vs_time",
                     "Held-out residual against the time within its segment, blocking and clearing events",
                     "Residual vs time in the segment, blocked vs clear events", "time since the segment started (s)",
                     y_label, {blocked, clear}, sigma),
            folder, &d.pictures);
}

}  // namespace

Diagnosis DiagnoseLaserLog(const std::vector<tcf::BeamEvent>& events, const tcf::ProgrammedMotion& motion,
                           const tcf::SensorFrame& sensor, const DiagnoseOptions& options) {
  LogModel lm;
  lm.motion = &motion;
  lm.frame = sensor.base_from_lasersensor;
  lm.used = UsedEvents(events, motion);
  const int n = static_cast<int>(lm.used.size());
  if (n < 12) throw InputError({options.data, 0, "events"}, "fewer than 12 events inside the programmed segments");
  std::string start_note;
  const ResidualModel model = MakeModel(lm, StartingTool(events, motion, sensor, options, &start_note));

  Diagnosis d;
  d.kind = DataKind::kLaser;
  d.data = options.data;
  d.unit = "mm";
  d.model = "ideal device (perpendicular crossing line beams, no latency, programmed speed)";
  const double sigma = options.noise > 0 ? options.noise : kLaserLogNoiseMm;
  d.noise_floor_rms = sigma;
  d.num_residuals = n;

  const std::vector<int> base = {kTx, kTy, kTz, kAx, kAy};
  // The current model, then every row of the laser cause table the log can show, in table order.
  std::vector<CandidateSpec> specs = {{kNoEffect, {}}};
#define RAMTK_UNPAREN(...) __VA_ARGS__
#define RAMTK_LASER_CAUSE(name, drawn, fitted, parameters, plausible, help) \
  if (!std::vector<int>{RAMTK_UNPAREN fitted}.empty()) specs.push_back({#name, {RAMTK_UNPAREN fitted}});
#include "ramtk/diagnose/engine/laser_causes.def"
#undef RAMTK_UNPAREN
  std::vector<CandidateOutcome> outcomes;
  for (size_t i = 0; i < specs.size(); ++i) {
    if (options.progress) options.progress({"candidates", i, specs.size()});
    outcomes.push_back(laser_detail::EvaluateCandidate(model, base, specs[i], options.folds));
  }
  if (options.progress) options.progress({"candidates", specs.size(), specs.size()});

  // Structure of the ideal model's residual (scaled for the fitted tool) against the noise.
  const Eigen::VectorXd r0 = model.residuals(outcomes[0].full.params);
  const std::vector<TestResult> tests = TestStructure(lm, motion, r0, static_cast<int>(base.size()), sigma);
  std::vector<double> p;
  for (const TestResult& t : tests) p.push_back(t.p_value);
  const std::vector<double> holm = HolmCorrection(p);
  d.structure_p_value = *std::min_element(holm.begin(), holm.end());
  d.structure_found = d.structure_p_value < options.alpha;
  d.residual_rms = laser_detail::Rms(r0);
  if (!start_note.empty()) d.findings.push_back(start_note);
  for (const TestResult& t : tests) d.findings.push_back(t.Describe());
  d.findings.push_back(
      "tool_axis_rotation not fitted: turning a rotationally symmetric tool about its own axis changes no event");

  const int chosen = laser_detail::Conclude(outcomes, 10.0, &d);
  if (d.cause == kUnexplained) {
    // The measured variable whose trend test is most significant (the variance test names none).
    size_t best = 0;
    for (size_t i = 1; i < tests.size(); ++i)
      if (best == 0 || tests[i].p_value < tests[best].p_value) best = i;
    d.explaining_variable = "none of the tested variables";
    if (best > 0 && holm[best] < options.alpha) {
      std::string name = tests[best].name;  // "trend(variable)"
      const size_t open_paren = name.find('(');
      if (open_paren != std::string::npos && name.back() == ')')
        name = name.substr(open_paren + 1, name.size() - open_paren - 2);
      d.explaining_variable = name;
    }
  }
  const CandidateOutcome final_outcome =
      laser_detail::AddFurtherEffects(model, base, specs, outcomes, chosen, options.folds, 10.0, "held-out RMS", &d);
  if (!options.output_folder.empty())
    WriteLaserPictures(lm, motion, outcomes[0], final_outcome, sigma, options.output_folder, &d);
  return d;
}

}  // namespace ramtk::diagnose
