// Independent cross-laser device log generator; see laser_gen.h and README.md.
#include "laser_gen.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace indep {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Event {
  double time_s;
  char beam;
  bool blocked;
};

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json PoseJson(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  nlohmann::json m = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) m.push_back({r(i, 0), r(i, 1), r(i, 2), t(i)});
  m.push_back({0.0, 0.0, 0.0, 1.0});
  return {{"position_mm", Vec(t)}, {"abc_deg", Vec(KukaAbcDeg(r))}, {"matrix", m}};
}

}  // namespace

double LineSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b) {
  // Minimise |p + s d − (a + t (b − a))| over s ∈ ℝ, t ∈ [0, 1]: for fixed t the best s is the
  // projection, so the squared distance is the perpendicular part of (a + t e − p), a quadratic in t.
  const Eigen::Vector3d e = b - a;
  auto perp = [&](const Eigen::Vector3d& v) { return v - d * d.dot(v); };
  const Eigen::Vector3d w0 = perp(a - p), we = perp(e);
  const double den = we.squaredNorm();
  double t = den > 0 ? -w0.dot(we) / den : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (w0 + t * we).norm();
}

Eigen::Vector3d KukaAbcDeg(const Eigen::Matrix3d& r) {
  const double b = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  const double a = std::atan2(r(1, 0), r(0, 0));
  const double c = std::atan2(r(2, 1), r(2, 2));
  return Eigen::Vector3d(a, b, c) / kDeg;
}

void GenerateLaser(const GenOptions& o) {
  const std::string& effect = o.effect;
  if (effect != "none" && effect != "beam_non_perpendicular" && effect != "speed_ripple") {
    throw std::runtime_error("laser: unknown effect '" + effect + "'");
  }
  Rng rng(0x2545f4914f6cdd1dULL ^ (static_cast<std::uint64_t>(o.seed) * 40503ULL + 101));

  // Device frame near the thesis's (Table 5-5: origin ≈ (799.4, −126.3, 194.5) mm, tilted ~2°).
  const Eigen::Vector3d origin(799.41 + rng.Uniform(-20, 20), -126.3 + rng.Uniform(-20, 20), 194.5 + rng.Uniform(-10, 10));
  const Eigen::Matrix3d base_from_device =
      (Eigen::AngleAxisd(rng.Uniform(-3, 3) * kDeg, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(rng.Uniform(-3, 3) * kDeg, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(rng.Uniform(-3, 3) * kDeg, Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Eigen::Vector3d xs = base_from_device.col(0), ys = base_from_device.col(1), zs = base_from_device.col(2);

  Truth truth;
  truth.kind = "laser";
  truth.effect = effect;
  truth.expected = effect;
  truth.accepted = {effect};
  nlohmann::json& par = truth.parameters;
  double beta = 90 * kDeg, ripple = 0, ripple_phase = 0;
  if (effect == "beam_non_perpendicular") {
    const double dev = std::isnan(o.magnitude) ? 2.2 : o.magnitude;
    beta = (90 + (rng.Uniform() < 0.5 ? -dev : dev)) * kDeg;
    par["beta_deg"] = beta / kDeg;
    par["beta_in_sensor_file_deg"] = 90.0;
  } else if (effect == "speed_ripple") {
    ripple = std::isnan(o.magnitude) ? 0.03 : o.magnitude;
    ripple_phase = rng.Uniform(-M_PI, M_PI);
    par["relative_speed_ripple"] = ripple;
    par["ripple_per_revolution"] = 2;
    par["ripple_phase_deg"] = ripple_phase / kDeg;
    par["law"] = "executed circle angle = programmed + dir*(ripple/2) sin(2 (programmed - start) + phase) (rad)";
    truth.expected = "unexplained";
    truth.accepted = {"unexplained:time", "unexplained:angle", "unexplained:phase"};
    truth.explaining_variable = "time in segment (angle along the circle)";
  }
  const Eigen::Vector3d x_beam_dir = xs;
  const Eigen::Vector3d y_beam_dir = std::cos(beta) * xs + std::sin(beta) * ys;

  // Tool: ball-nosed cylinder of radius 2.5 mm; apex (TCP) and axis in the flange frame, a
  // slightly bent tool (axis tilt 1–4°, lateral apex offset up to 3 mm).
  const double tool_r = 2.5;
  const double tilt = rng.Uniform(1, 4) * kDeg, tilt_dir = rng.Uniform(-M_PI, M_PI);
  const Eigen::Vector3d axis_in_flange(std::sin(tilt) * std::cos(tilt_dir), std::sin(tilt) * std::sin(tilt_dir), std::cos(tilt));
  const Eigen::Vector3d tcp_in_flange(rng.Uniform(-3, 3), rng.Uniform(-3, 3), 150 + rng.Uniform(-5, 5));
  const Eigen::Vector3d ball_in_flange = tcp_in_flange - tool_r * axis_in_flange;
  const Eigen::Vector3d shank_in_flange = ball_in_flange - 80.0 * axis_in_flange;
  par["tcp_in_flange_mm"] = Vec(tcp_in_flange);
  par["axis_in_flange"] = Vec(axis_in_flange);
  par["tool_radius_mm"] = tool_r;

  // Flange orientation: Z_e = −Z_s, X_e = X_s (the tool points down through the beam plane).
  Eigen::Matrix3d flange_rot;
  flange_rot << xs, -ys, -zs;
  const double repeat_sigma = 0.03, jitter_s = 20e-6;
  par["repeatability_sigma_mm"] = repeat_sigma;
  par["receiver_jitter_s"] = jitter_s;

  std::vector<Event> events;
  // One segment: flange position f(t) for t in [t0, t1] executed with a constant repeatability
  // offset; each beam's state from the capsule distance, changes found by bisection.
  auto run_segment = [&](double t0, double t1, const std::function<Eigen::Vector3d(double)>& flange_at) {
    Eigen::Vector3d offset(repeat_sigma * rng.Normal(), repeat_sigma * rng.Normal(), repeat_sigma * rng.Normal());
    for (char beam : {'x', 'y'}) {
      const Eigen::Vector3d dir = beam == 'x' ? x_beam_dir : y_beam_dir;
      auto gap = [&](double t) {
        const Eigen::Vector3d f = flange_at(t) + offset;
        return LineSegmentDistance(origin, dir, f + flange_rot * ball_in_flange, f + flange_rot * shank_in_flange) - tool_r;
      };
      const double dt = 1e-3;
      double prev_t = t0, prev = gap(t0);
      if (prev < 0) throw std::runtime_error("laser: a segment starts with a beam blocked");
      for (double t = t0 + dt; t <= t1 + 1e-12; t += dt) {
        const double g = gap(t);
        if ((g < 0) != (prev < 0)) {
          double lo = prev_t, hi = t;
          for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            if ((gap(mid) < 0) == (prev < 0)) lo = mid; else hi = mid;
          }
          events.push_back({0.5 * (lo + hi) + jitter_s * rng.Normal(), beam, g < 0});
        }
        prev_t = t;
        prev = g;
      }
      if (prev < 0) throw std::runtime_error("laser: a segment ends with a beam blocked");
    }
  };

  // Programme written with the nominal tool (straight, 150 mm): circles of R = 12 mm at 180°/s,
  // 1.25 revolutions, with the nominal axis point h above the tip at the crossing.
  nlohmann::json circles = nlohmann::json::array(), lines = nlohmann::json::array();
  struct CircleSpec { const char* name; double h; int dir; double start; };
  const CircleSpec specs[3] = {{"upper_ccw", 26, 1, 0.5}, {"lower_ccw", 6, 1, 3.5}, {"lower_cw", 6, -1, 6.5}};
  const double radius = 12, omega = 180 * kDeg, duration = 2.5, start_angle = 45 * kDeg;
  for (const auto& c : specs) {
    const Eigen::Vector3d centre = origin - flange_rot * Eigen::Vector3d(0, 0, 150 - c.h);
    auto flange_at = [&, c, centre](double t) {
      const double prog = start_angle + c.dir * omega * (t - c.start);
      const double phi = prog + c.dir * 0.5 * ripple * std::sin(2 * (prog - start_angle) + ripple_phase);
      return Eigen::Vector3d(centre + radius * (std::cos(phi) * xs + std::sin(phi) * ys));
    };
    run_segment(c.start, c.start + duration, flange_at);
    circles.push_back({{"name", c.name}, {"start_time_s", c.start}, {"duration_s", duration},
                       {"centre_flange_pose", PoseJson(flange_rot, centre)}, {"u_in_base", Vec(xs)},
                       {"v_in_base", Vec(ys)}, {"radius_mm", radius}, {"angular_speed_deg_s", omega / kDeg},
                       {"direction", c.dir > 0 ? "ccw" : "cw"}, {"start_angle_deg", start_angle / kDeg}});
  }
  // Plunges: the tool's own axis (as estimated from the circles, here taken as known to 0.1 mm)
  // driven down through the crossing at 20 mm/s from 10 mm above to 10 mm below, back up at 40 mm/s.
  const Eigen::Vector3d axis_in_base = flange_rot * axis_in_flange;
  const Eigen::Vector3d aim(0.1 * rng.Normal(), 0.1 * rng.Normal(), 0);
  const Eigen::Vector3d apex_start = origin + base_from_device * aim - 10.0 * axis_in_base;
  const Eigen::Vector3d flange_top = apex_start - flange_rot * tcp_in_flange;
  double t = 9.5;
  for (int k = 1; k <= 2; ++k) {
    // Down 1.0 s, dwell 0.3 s at the bottom (the shank still in the beams), up 0.5 s: one
    // continuous execution with one repeatability offset.
    const Eigen::Vector3d v_down = 20.0 * axis_in_base, v_up = -40.0 * axis_in_base;
    const Eigen::Vector3d flange_bottom = flange_top + v_down * 1.0;
    const double t_down = t, t_up = t + 1.3;
    run_segment(t_down, t_up + 0.5, [&](double s) {
      if (s <= t_down + 1.0) return Eigen::Vector3d(flange_top + v_down * (s - t_down));
      if (s <= t_up) return flange_bottom;
      return Eigen::Vector3d(flange_bottom + v_up * (s - t_up));
    });
    lines.push_back({{"name", "down" + std::to_string(k)}, {"start_time_s", t_down}, {"duration_s", 1.0},
                     {"start_flange_pose", PoseJson(flange_rot, flange_top)}, {"velocity_in_base_mm_s", Vec(v_down)}});
    lines.push_back({{"name", "up" + std::to_string(k)}, {"start_time_s", t_up}, {"duration_s", 0.5},
                     {"start_flange_pose", PoseJson(flange_rot, flange_bottom)}, {"velocity_in_base_mm_s", Vec(v_up)}});
    t = t_up + 0.8;
  }

  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.time_s < b.time_s; });
  std::ostringstream log;
  log << "time_s,beam,state\n";
  for (const Event& e : events) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.7f,%c,%s\n", e.time_s, e.beam, e.blocked ? "blocked" : "clear");
    log << buf;
  }
  par["num_events"] = events.size();

  nlohmann::json motion;
  motion["tool_radius_mm"] = tool_r;
  motion["circles"] = circles;
  motion["lines"] = lines;
  nlohmann::json sensor;  // what the device calibration says: perpendicular beams at one height
  sensor["base_from_lasersensor"] = PoseJson(base_from_device, origin);
  sensor["beta_deg"] = 90.0;
  sensor["beam_gap_mm"] = 0.0;
  sensor["x_beam_z_mm"] = 0.0;
  sensor["y_beam_z_mm"] = 0.0;

  std::filesystem::create_directories(o.out_dir);
  WriteFileAtomic(o.out_dir + "/laser_log.csv", log.str());
  WriteFileAtomic(o.out_dir + "/motion.json", motion.dump(2) + "\n");
  WriteFileAtomic(o.out_dir + "/sensor.json", sensor.dump(2) + "\n");
  WriteTruth(o.out_dir, truth, o);
}

}  // namespace indep
