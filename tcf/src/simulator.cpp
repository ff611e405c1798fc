// Cross-laser device simulator.
#include "ramtk/tcf/simulator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"
#include "ramtk/tcf/geometry.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::tcf {
namespace {

struct Tool {
  Vec3 tcp_in_flange, axis_in_flange;
  double radius;
};

// Distance from the line (p, unit d) to the tool solid (ball + cylinder upwards) at flange pose f,
// minus the blocking radius: < 0 means blocked.
double Clearance(const Vec3& p, const Vec3& d, double half_width, const Tool& tool, const Isometry3& f) {
  const Vec3 a = f.linear() * tool.axis_in_flange;
  const Vec3 c = f * tool.tcp_in_flange - tool.radius * a;  // ball centre
  return LineToRayDistance(p, d, c, -a) - tool.radius - half_width;
}

}  // namespace

bool DeviceEffects::Enable(const std::string& name) {
  if (name == "beam_non_perpendicular")
    beam_non_perpendicular = true;
  else if (name == "beam_offset")
    beam_offset = true;
  else if (name == "beam_width")
    beam_width = true;
  else if (name == "trigger_latency")
    trigger_latency = true;
  else if (name == "speed_variation")
    speed_variation = true;
  else if (name == "sensor_plane_tilt")
    sensor_plane_tilt = true;
  else if (name == "tool_axis_rotation")
    tool_axis_rotation = true;
  else
    return false;
  return true;
}

void DeviceEffects::EnableList(const std::string& list, const std::string& option) {
  std::string name;
  auto flush = [&] {
    if (name.empty()) return;
    if (name == "all") {
      for (const std::string& n : Names()) Enable(n);
    } else if (!Enable(name)) {
      std::string known;
      for (const std::string& n : Names()) known += " " + n;
      throw InputError({"", 0, option}, "unknown effect '" + name + "'; known:" + known + " all");
    }
    name.clear();
  };
  for (char c : list) {
    if (c == ',')
      flush();
    else if (c != ' ')
      name += c;
  }
  flush();
}

std::vector<std::string> DeviceEffects::Names() {
  return {"beam_non_perpendicular", "beam_offset",       "beam_width",        "trigger_latency",
          "speed_variation",        "sensor_plane_tilt", "tool_axis_rotation"};
}

Isometry3 TcfSimulationOptions::DefaultBaseFromLaserSensor() {
  Isometry3 s = Isometry3::Identity();
  s.linear() = RotZ(DegToRad(-1.7)) * RotY(DegToRad(-2.3)) * RotX(DegToRad(1.3));  // like eq. (5-3)
  s.translation() = Vec3(799.41, -126.30, 194.50);
  return s;
}

std::string TcfSimulationOptions::Validate() const {
  if (std::string bad = CheckNoise("repeatability_mm", repeatability_mm, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  if (std::string bad = CheckNoise("timing_jitter_s", timing_jitter_s, kMaxNoiseS, "s"); !bad.empty()) return bad;
  if (!(tool_radius_mm > 0.0)) return "tool_radius_mm must be > 0";
  if (!(circle_radius_mm > tool_radius_mm)) return "circle_radius_mm must exceed tool_radius_mm";
  if (!(angular_speed_deg_s > 0.0)) return "angular_speed_deg_s must be > 0";
  if (!(revolutions >= 1.0)) return "revolutions must be >= 1";
  if (!(lower_height_mm > upper_height_mm + 1.0)) return "lower_height_mm must exceed upper_height_mm";
  if (!(approach_speed_mm_s > 0.0 && retract_speed_mm_s > 0.0)) return "speeds must be > 0";
  if (!(approach_passes >= 1)) return "approach_passes must be >= 1";
  if (!(effects.beta_deg > 45.0 && effects.beta_deg < 135.0)) return "effects.beta_deg must be in (45, 135)";
  return "";
}

namespace {

// The true tool and device of the simulation (with the effects switched on), and the sensor frame
// as its calibration gives it.
void SetTruth(const TcfSimulationOptions& opt, TcfSimulation* sim) {
  const DeviceEffects& fx = opt.effects;
  TcfTruth& truth = sim->truth;
  const Mat3 r5 = FiveDofRotation(DegToRad(opt.tool_psi_deg), DegToRad(opt.tool_theta_deg));
  const double spin = fx.tool_axis_rotation ? DegToRad(fx.tool_axis_rotation_deg) : 0.0;
  truth.flange_from_tcp.linear() = r5 * RotZ(spin);
  truth.flange_from_tcp.translation() = opt.tcp_in_flange;
  truth.tcp_in_flange = opt.tcp_in_flange;
  truth.axis_in_flange = r5.col(2);
  truth.beta_rad = DegToRad(fx.beam_non_perpendicular ? fx.beta_deg : 90.0);
  truth.x_beam_z_mm = fx.beam_offset ? 0.5 * fx.beam_offset_mm : 0.0;
  truth.y_beam_z_mm = fx.beam_offset ? -0.5 * fx.beam_offset_mm : 0.0;
  truth.beam_width_mm = fx.beam_width ? fx.beam_width_mm : 0.0;
  truth.latency_s = fx.trigger_latency ? fx.latency_s : 0.0;
  const Isometry3& cal = opt.base_from_lasersensor;  // the calibrated frame
  truth.base_from_lasersensor = cal;
  if (fx.sensor_plane_tilt) truth.base_from_lasersensor.linear() = cal.linear() * RotX(DegToRad(fx.plane_tilt_deg));

  SensorFrame& s = sim->calibrated_sensor;
  s.base_from_lasersensor = cal;
  s.beta_rad = truth.beta_rad;  // the calibration measures β (Table 5-3 style)
  s.n = cal.linear().col(0);
  s.o = cal.linear().col(1);
  s.p = cal.linear().col(2);
  s.m = std::cos(s.beta_rad) * s.n + std::sin(s.beta_rad) * s.o;
  s.m_in_base = cal.translation();
}

// Runs programmed segments on the simulated robot and device: the actual flange pose over a
// segment's window (repeatability offset, speed error) against the true beams gives the events
// (latency, jitter). The beams' blocked state carries over from segment to segment.
class SegmentRunner {
 public:
  SegmentRunner(const TcfSimulationOptions& opt, const TcfTruth& truth, std::mt19937_64* rng,
                std::normal_distribution<double>* normal)
      : opt_(opt),
        truth_(truth),
        rng_(*rng),
        normal_(*normal),
        tool_{opt.tcp_in_flange, truth.axis_in_flange, opt.tool_radius_mm},
        half_width_(0.5 * truth.beam_width_mm) {
    const Isometry3& tb = truth.base_from_lasersensor;
    beam_point_[0] = tb * Vec3(0, 0, truth.x_beam_z_mm);
    beam_point_[1] = tb * Vec3(0, 0, truth.y_beam_z_mm);
    beam_dir_[0] = tb.linear() * Vec3::UnitX();
    beam_dir_[1] = tb.linear() * Vec3(std::cos(truth.beta_rad), std::sin(truth.beta_rad), 0.0);
  }

  // Robot time warp: programmed elapsed time -> executed elapsed time.
  double Executed(double tau) const {
    const DeviceEffects& fx = opt_.effects;
    if (!fx.speed_variation) return tau;
    const double w = 2.0 * kPi * fx.speed_ripple_hz;
    return (1.0 + fx.speed_scale_error) * tau + fx.speed_ripple * std::sin(w * tau) / w;
  }

  // The events of one segment starting at t0: its programmed pose at elapsed time τ is `programmed`.
  std::vector<BeamEvent> Run(double t0, double duration, const std::function<Isometry3(double)>& programmed) {
    std::mt19937_64& rng = rng_;
    std::normal_distribution<double>& normal = normal_;
    const Vec3 offset(opt_.repeatability_mm * normal(rng), opt_.repeatability_mm * normal(rng),
                      opt_.repeatability_mm * normal(rng));
    auto actual = [&](double t) {
      Isometry3 f = programmed(Executed(t - t0));
      f.translation() += offset;
      return f;
    };
    const int steps = 4000;
    std::vector<BeamEvent> out;
    for (int b = 0; b < 2; ++b) {
      auto g = [&](double t) { return Clearance(beam_point_[b], beam_dir_[b], half_width_, tool_, actual(t)); };
      double prev_t = t0, prev_g = g(t0);
      auto emit = [&](double t_true, bool blocked) {
        BeamEvent e;
        e.beam = static_cast<Beam>(b);
        e.state = blocked ? BeamState::kBlocked : BeamState::kClear;
        e.time_s = t_true + truth_.latency_s + opt_.timing_jitter_s * normal(rng);
        out.push_back(e);
        beam_blocked_[b] = blocked;
      };
      // A change during the (unmodelled) transfer from the previous segment.
      if ((prev_g < 0) != beam_blocked_[b]) emit(t0 - 0.05, prev_g < 0);
      for (int i = 1; i <= steps; ++i) {
        const double t = t0 + duration * i / steps;
        const double gt = g(t);
        if ((gt < 0) != (prev_g < 0)) {
          double lo = prev_t, hi = t;
          for (int k = 0; k < 60; ++k) {
            const double mid = 0.5 * (lo + hi);
            ((g(mid) < 0) == (prev_g < 0) ? lo : hi) = mid;
          }
          emit(0.5 * (lo + hi), gt < 0);
        }
        prev_t = t;
        prev_g = gt;
      }
    }
    return out;
  }

 private:
  const TcfSimulationOptions& opt_;
  const TcfTruth& truth_;
  std::mt19937_64& rng_;
  std::normal_distribution<double>& normal_;
  const Tool tool_;
  const double half_width_;
  Vec3 beam_point_[2], beam_dir_[2];
  bool beam_blocked_[2] = {false, false};
};

}  // namespace

TcfSimulation SimulateTcf(const TcfSimulationOptions& opt) {
  ThrowIfInvalid(opt.Validate(), "TcfSimulationOptions");
  std::mt19937_64 rng(opt.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  TcfSimulation sim;
  SetTruth(opt, &sim);
  const Isometry3& cal = opt.base_from_lasersensor;  // the calibrated frame
  const SensorFrame& s = sim.calibrated_sensor;
  SegmentRunner runner(opt, sim.truth, &rng, &normal);
  auto run_segment = [&runner](double t0, double duration, const std::function<Isometry3(double)>& programmed) {
    return runner.Run(t0, duration, programmed);
  };

  // Programme, phase 1: circles. Flange: X_e = X_s, Y_e = −Y_s, Z_e = −Z_s (thesis Fig. 4-8).
  ProgrammedMotion& m = sim.motion;
  m.tool_radius_mm = opt.tool_radius_mm;
  Isometry3 flange0 = Isometry3::Identity();
  flange0.linear() = cal.linear() * Vec3(1.0, -1.0, -1.0).asDiagonal();
  const double omega = DegToRad(opt.angular_speed_deg_s);
  const double circle_duration = opt.revolutions * 2.0 * kPi / omega;
  double t = 0.5;
  struct CirclePlan {
    const char* name;
    double height;
    int direction;
  };
  const CirclePlan plans[] = {{"upper_ccw", opt.upper_height_mm, 1},
                              {"lower_ccw", opt.lower_height_mm, 1},
                              {"upper_cw", opt.upper_height_mm, -1}};
  for (const CirclePlan& p : plans) {
    CircleSegment c;
    c.name = p.name;
    c.start_time_s = t;
    c.duration_s = circle_duration;
    c.base_from_flange_centre = flange0;
    // The nominal tool's point p.height above its tip sits at the device origin.
    c.base_from_flange_centre.translation() =
        cal.translation() - flange0.linear() * Vec3(0, 0, opt.nominal_tool_length_mm - p.height);
    c.u_in_base = cal.linear().col(0);
    c.v_in_base = cal.linear().col(1);
    c.radius_mm = opt.circle_radius_mm;
    c.angular_speed_rad_s = omega;
    c.direction = p.direction;
    c.start_angle_rad = DegToRad(opt.start_angle_deg);
    m.circles.push_back(c);
    const CircleSegment cc = c;
    auto ev = run_segment(c.start_time_s, c.duration_s,
                          [cc](double tau) { return cc.BaseFromFlange(cc.start_time_s + tau); });
    sim.events.insert(sim.events.end(), ev.begin(), ev.end());
    t += circle_duration + 0.5;
  }
  std::sort(sim.events.begin(), sim.events.end(),
            [](const BeamEvent& a, const BeamEvent& b) { return a.time_s < b.time_s; });

  // Phase 2: the controller estimates the axis from the circles (library, no truth) and moves the
  // estimated apex down through the crossing and back.
  const AxisEstimate est = EstimateToolAxisFromCircles(sim.events, m, s);
  const double lambda_tip =
      (opt.nominal_tool_length_mm - est.point_in_flange.z()) / std::max(0.5, est.axis_in_flange.z());
  const Vec3 apex_in_flange = est.point_in_flange + lambda_tip * est.axis_in_flange;
  const Vec3 down = -cal.linear().col(2);
  for (int pass = 0; pass < opt.approach_passes; ++pass) {
    LineSegment d;
    d.name = "down" + std::to_string(pass + 1);
    d.start_time_s = t;
    d.duration_s = opt.approach_travel_mm / opt.approach_speed_mm_s;
    d.base_from_flange_start = flange0;
    d.base_from_flange_start.translation() =
        cal.translation() + opt.approach_start_mm * cal.linear().col(2) - flange0.linear() * apex_in_flange;
    d.velocity_in_base_mm_s = opt.approach_speed_mm_s * down;
    LineSegment u;
    u.name = "up" + std::to_string(pass + 1);
    u.start_time_s = d.start_time_s + d.duration_s + 0.3;
    u.duration_s = opt.approach_travel_mm / opt.retract_speed_mm_s;
    u.base_from_flange_start = d.BaseFromFlange(d.start_time_s + d.duration_s);
    u.velocity_in_base_mm_s = -opt.retract_speed_mm_s * down;
    for (const LineSegment& l : {d, u}) {
      m.lines.push_back(l);
      auto ev =
          run_segment(l.start_time_s, l.duration_s, [l](double tau) { return l.BaseFromFlange(l.start_time_s + tau); });
      sim.events.insert(sim.events.end(), ev.begin(), ev.end());
    }
    t = u.start_time_s + u.duration_s + 0.3;
  }
  std::sort(sim.events.begin(), sim.events.end(),
            [](const BeamEvent& a, const BeamEvent& b) { return a.time_s < b.time_s; });
  return sim;
}

std::map<std::string, Vec3> SimulateSensorCalibrationPoints(const TcfTruth& truth,
                                                            const SensorCalibrationSimulationOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto noise = [&]() -> Vec3 {
    const double a = normal(rng), b = normal(rng), c = normal(rng);
    return o.repeatability_mm * Vec3(a, b, c);
  };
  const Isometry3& tb = truth.base_from_lasersensor;
  const double half = o.pin_radius_mm + 0.5 * truth.beam_width_mm;
  std::map<std::string, Vec3> out;
  // Beam b: foot point and direction in the base frame; the flange (pin axis) positions at the
  // state changes are symmetric about the beam point crossed.
  auto add = [&](const std::string& label, const Vec3& foot, const Vec3& dir, double s, bool scan_along_y) {
    const Vec3 pb = foot + s * dir;  // the beam point the passes cross
    // Horizontal pass with a vertical pin: along Y_b (x beam) or X_b (y beam), 30 mm above.
    const Vec3 h = scan_along_y ? Vec3::UnitY() : Vec3::UnitX();
    const double k = half / std::max(1e-6, std::abs(h.dot(Vec3::UnitZ().cross(dir).normalized())));
    out[label + "1"] = pb - k * h + Vec3(0, 0, 13.0) + noise();
    out[label + "2"] = pb + k * h + Vec3(0, 0, 13.0) + noise();
    // Vertical pass with a horizontal pin along the scan direction, offset 13 mm along it.
    out[label + "3"] = pb + half * Vec3::UnitZ() - 13.0 * h + noise();
    out[label + "4"] = pb - half * Vec3::UnitZ() - 13.0 * h + noise();
  };
  const Vec3 x_foot = tb * Vec3(0, 0, truth.x_beam_z_mm), y_foot = tb * Vec3(0, 0, truth.y_beam_z_mm);
  const Vec3 x_dir = tb.linear() * Vec3::UnitX();
  const Vec3 y_dir = tb.linear() * Vec3(std::cos(truth.beta_rad), std::sin(truth.beta_rad), 0.0);
  add("A", x_foot, x_dir, -o.half_span_mm, true);
  add("B", x_foot, x_dir, o.half_span_mm, true);
  add("C", y_foot, y_dir, -o.half_span_mm, false);
  add("D", y_foot, y_dir, o.half_span_mm, false);
  return out;
}

std::string TcfTruthToJson(const TcfTruth& t, const DeviceEffects& fx) {
  nlohmann::json j;
  j["flange_from_tcp"] = PoseToJson(t.flange_from_tcp);
  j["tcp_in_flange_mm"] = Vec3ToJson(t.tcp_in_flange);
  j["axis_in_flange"] = Vec3ToJson(t.axis_in_flange);
  j["true_base_from_lasersensor"] = PoseToJson(t.base_from_lasersensor);
  j["beta_deg"] = RadToDeg(t.beta_rad);
  j["x_beam_z_mm"] = t.x_beam_z_mm;
  j["y_beam_z_mm"] = t.y_beam_z_mm;
  j["beam_width_mm"] = t.beam_width_mm;
  j["latency_ms"] = t.latency_s * 1e3;
  nlohmann::json e = nlohmann::json::array();
  const bool on[] = {fx.beam_non_perpendicular, fx.beam_offset,       fx.beam_width,        fx.trigger_latency,
                     fx.speed_variation,        fx.sensor_plane_tilt, fx.tool_axis_rotation};
  const auto names = DeviceEffects::Names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (on[i]) e.push_back(names[i]);
  j["effects"] = e;
  return j.dump(2) + "\n";
}

}  // namespace ramtk::tcf
