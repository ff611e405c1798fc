// Cross-laser TCF solver: circles -> tool axis, straight moves -> TCP, self-calibration and
// first-order uncertainty. See tcf_solver.h for the method.
#include "ramtk/tcf/tcf_solver.h"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

#include "ramtk/core/error.h"
#include "ramtk/core/json.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"
#include "ramtk/tcf/geometry.h"

namespace ramtk::tcf {
namespace {

double WrapTwoPi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0 ? a + 2.0 * kPi : a;
}

struct BeamLine {
  Vec3 point_in_base, dir_in_base;
};

struct CoreResult {
  TcfSummary summary;
  Vec3 tcp = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
};

// Axis points of the circles in the flange frame given the beam heights and axis slope.
void CirclePoints(const ProgrammedMotion& motion, const std::vector<CircleObservation>& obs, const SensorFrame& sensor,
                  double beta_used, double z_x, double z_y, const Vec3& axis_in_sensor, std::vector<Vec3>* points) {
  points->clear();
  const Vec3 nu_y = BeamNormalInSensor(Beam::kY, beta_used);
  const double az = std::abs(axis_in_sensor.z()) > 1e-6 ? axis_in_sensor.z() : -1.0;
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const double dx = obs[k].x.distance_mm, dy = obs[k].y.distance_mm;
    // The axis crosses height z at q0 + (z / a_z)·a; the x beam sees it at z_x, the y beam at z_y.
    const double y0 = dx - z_x * axis_in_sensor.y() / az;
    const double x0 =
        (dy - (z_y / az) * axis_in_sensor.dot(nu_y) + y0 * std::cos(beta_used)) / std::sin(beta_used);  // (4-29)
    const Vec3 q0_in_sensor(x0, y0, 0.0);
    const Isometry3& f = motion.circles[k].base_from_flange_centre;
    points->push_back(f.inverse() * (sensor.base_from_lasersensor * q0_in_sensor));
  }
}

// β from the circles' phases (−ν_x at −90°, −ν_y at 90° + β in the sensor frame) and its σ.
void BetaFromPhases(const ProgrammedMotion& motion, const Isometry3& base_from_sensor, const TcfSolverOptions& opt,
                    TcfSummary* summary) {
  TcfSummary& s = *summary;
  double sum = 0.0;
  for (std::size_t k = 0; k < s.circles.size(); ++k) {
    const CircleSegment& c = motion.circles[k];
    const double sense = c.u_in_base.cross(c.v_in_base).dot(base_from_sensor.linear().col(2)) >= 0 ? 1.0 : -1.0;
    // −ν_x is at −90°, −ν_y at 90° + β (sensor frame), so β = sense·(φ_y − φ_x) − 180°.
    sum += WrapTwoPi(sense * (s.circles[k].y.neg_gap_mid_angle_rad - s.circles[k].x.neg_gap_mid_angle_rad) - kPi);
  }
  s.beta_self_calibrated_rad = sum / s.circles.size();
  // Its σ: the circles' scatter, or the noise propagated to a phase difference if larger.
  const int kc = static_cast<int>(s.circles.size());
  double scatter = 0.0, noise = 0.0;
  for (int k = 0; k < kc; ++k) {
    const CircleSegment& c = motion.circles[k];
    const double sense = c.u_in_base.cross(c.v_in_base).dot(base_from_sensor.linear().col(2)) >= 0 ? 1.0 : -1.0;
    const double b =
        WrapTwoPi(sense * (s.circles[k].y.neg_gap_mid_angle_rad - s.circles[k].x.neg_gap_mid_angle_rad) - kPi);
    scatter += (b - s.beta_self_calibrated_rad) * (b - s.beta_self_calibrated_rad);
    // Timing noise moves each gap midpoint by ω·σ_t/√2; a circle-centre offset (repeatability)
    // moves both crossings of a gap alike and leaves its midpoint, hence β, in place.
    noise += std::pow(c.angular_speed_rad_s * opt.timing_sigma_s, 2);
  }
  const double sd = kc > 1 ? std::sqrt(scatter / (kc - 1)) : 0.0;
  s.beta_self_calibrated_sigma_rad = std::max(sd, std::sqrt(noise / std::max(kc, 1))) / std::sqrt(std::max(kc, 1));
}

// Latency from cw + ccw phases: phase_k = dir_k·ω_k·L + δ; the speed scale from the measured
// circle periods.
void LatencyAndSpeed(const ProgrammedMotion& motion, const TcfSolverOptions& opt, TcfSummary* summary) {
  TcfSummary& s = *summary;
  s.latency_s = opt.assumed_latency_s;
  {
    bool has_cw = false, has_ccw = false;
    Eigen::MatrixXd a(s.circles.size(), 2);
    Eigen::VectorXd b(s.circles.size());
    for (std::size_t k = 0; k < s.circles.size(); ++k) {
      const CircleSegment& c = motion.circles[k];
      (c.direction > 0 ? has_ccw : has_cw) = true;
      a(k, 0) = c.direction * 2.0 * kPi / s.circles[k].period_s;  // measured ω, as the phases use
      a(k, 1) = 1.0;
      b(k) = 0.5 * (s.circles[k].x.phase_offset_rad + s.circles[k].y.phase_offset_rad);
    }
    if (opt.self_calibrate_latency && has_cw && has_ccw) {
      const Eigen::Vector2d sol = a.colPivHouseholderQr().solve(b);
      s.latency_s = sol(0);
      s.phase_misalignment_rad = sol(1);
      s.latency_estimated = true;
    }
  }
  if (opt.self_calibrate_speed) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < s.circles.size(); ++k) {
      if (!s.circles[k].period_measured) continue;
      sum += (2.0 * kPi / motion.circles[k].angular_speed_rad_s) / s.circles[k].period_s;
      ++n;
    }
    if (n > 0) s.speed_scale = sum / n;
  }
}

// A beam event on a straight move with the flange pose at its executed time.
struct TipEvent {
  int beam;
  Isometry3 flange;
};

std::vector<TipEvent> TipEvents(const std::vector<BeamEvent>& events, const ProgrammedMotion& motion,
                                const TcfSummary& s) {
  std::vector<TipEvent> tip_events;
  for (const LineSegment& l : motion.lines) {
    for (const BeamEvent& e : events) {
      if (e.time_s < l.start_time_s || e.time_s > l.start_time_s + l.duration_s) continue;
      const double t_exec = l.start_time_s + s.speed_scale * (e.time_s - s.latency_s - l.start_time_s);
      tip_events.push_back({static_cast<int>(e.beam), l.BaseFromFlange(t_exec)});
    }
  }
  return tip_events;
}

// The tool axis as the line through the circles' axis points (principal direction), with the
// points' residuals from it.
void FitAxisLine(const std::vector<Vec3>& pts, const std::string& mpath, Vec3* point, Vec3* axis,
                 TcfSummary* summary) {
  Vec3& p_ref = *point;
  Vec3& axis_f = *axis;
  p_ref = Vec3::Zero();
  for (const Vec3& p : pts) p_ref += p / pts.size();
  Mat3 scatter = Mat3::Zero();
  for (const Vec3& p : pts) scatter += (p - p_ref) * (p - p_ref).transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  const double spread = std::sqrt(std::max(0.0, eig.eigenvalues()(2)));
  if (spread < 0.5)
    throw InputError({mpath, 0, "circles"}, "the circles' axis points coincide: program circles at two heights");
  axis_f = eig.eigenvectors().col(2).normalized();
  // Residuals of the circles' axis points from the fitted axis (cw and ccw circles at one height
  // must agree; with two heights only, these are zero).
  double css = 0.0, cworst = 0.0;
  for (const Vec3& p : pts) {
    const Vec3 d = (p - p_ref) - (p - p_ref).dot(axis_f) * axis_f;
    css += d.squaredNorm();
    cworst = std::max(cworst, d.norm());
  }
  summary->circle_rms_mm = std::sqrt(css / pts.size());
  summary->circle_worst_mm = cworst;
}

// RMS and worst deviation of the tip events' apex distances from their mean `lambda_apex` (n used).
void TipScatter(const std::vector<TipEvent>& tip_events, const std::function<double(const TipEvent&)>& lambda_of,
                double lambda_apex, int n, TcfSummary* summary) {
  double ss = 0.0, worst = 0.0;
  for (const TipEvent& te : tip_events) {
    const double l = lambda_of(te);
    if (std::isnan(l)) continue;
    ss += (l - lambda_apex) * (l - lambda_apex);
    worst = std::max(worst, std::abs(l - lambda_apex));
  }
  summary->tip_rms_mm = std::sqrt(ss / std::max(1, n));
  summary->tip_worst_mm = worst;
  summary->tip_events_unused = static_cast<int>(tip_events.size()) - n;
}

// InputError when the tool axis is further from the device normal than opt.max_axis_tilt_deg.
void CheckAxisTilt(const Vec3& axis_in_sensor, const TcfSolverOptions& opt, const std::string& log_path) {
  const double tilt = std::acos(std::clamp(-axis_in_sensor.z(), -1.0, 1.0));
  if (tilt > DegToRad(opt.max_axis_tilt_deg)) {
    char buf[200];
    std::snprintf(buf, sizeof(buf), "the tool axis is %.1f deg from the device normal, beyond the range of %.1f deg",
                  RadToDeg(tilt), opt.max_axis_tilt_deg);
    throw InputError({log_path, 0, "tool axis"}, buf);
  }
}

// The beam height difference at which `mismatch` (x-beam tip minus y-beam tip) vanishes: secant
// steps from `start`.
double BalanceBeamHeights(const std::function<double(double)>& mismatch, double start) {
  double d0 = start, d1 = d0 + 0.1;
  double f0 = mismatch(d0), f1 = mismatch(d1);
  for (int i = 0; i < 6 && std::abs(f1 - f0) > 1e-12; ++i) {
    const double d2 = d1 - f1 * (d1 - d0) / (f1 - f0);
    d0 = d1;
    f0 = f1;
    d1 = d2;
    f1 = mismatch(d1);
  }
  return d1;
}

CoreResult SolveCore(const std::vector<BeamEvent>& events, const ProgrammedMotion& motion, const SensorFrame& sensor,
                     const TcfSolverOptions& opt, const std::string& log_path) {
  CoreResult out;
  TcfSummary& s = out.summary;
  const std::string& mpath = motion.source;
  if (motion.circles.size() < 2)
    throw InputError({mpath, 0, "circles"}, "at least two circles at different heights are needed for the tool axis");
  const Isometry3& base_from_sensor = sensor.base_from_lasersensor;
  const Isometry3 sensor_from_base = base_from_sensor.inverse();

  // 1. Circles with the calibrated β; then optionally β from the phases and again.
  double beta_geom = sensor.beta_rad;
  auto analyse = [&](double beta) {
    std::vector<CircleObservation> obs;
    for (const CircleSegment& c : motion.circles)
      obs.push_back(AnalyseCircle(c, events, sensor, beta, opt.crossing_model, log_path));
    return obs;
  };
  s.circles = analyse(beta_geom);
  BetaFromPhases(motion, base_from_sensor, opt, &s);
  if (opt.self_calibrate_beta) {
    if (!(s.beta_self_calibrated_rad > DegToRad(20) && s.beta_self_calibrated_rad < DegToRad(160)))
      throw InputError({log_path, 0, "beta"}, "the beam angle from the circle phases is implausible; check the log");
    beta_geom = s.beta_self_calibrated_rad;
    s.circles = analyse(beta_geom);
  }
  const double beta_used = opt.correct_oblique_beams ? beta_geom : 0.5 * kPi;
  s.beta_used_rad = beta_used;

  // 2. Latency from cw + ccw phases, the robot's speed from the circle periods.
  LatencyAndSpeed(motion, opt, &s);
  double in_plane_radius[2] = {0.0, 0.0};
  for (const CircleObservation& o : s.circles) {
    in_plane_radius[0] += o.x.blocking_radius_mm / s.circles.size();
    in_plane_radius[1] += o.y.blocking_radius_mm / s.circles.size();
  }

  // 3./4. Axis and tip, iterating the beam heights and the axis slope.
  const double z_mean = 0.5 * (sensor.x_beam_z_mm + sensor.y_beam_z_mm);
  double z_x = sensor.x_beam_z_mm, z_y = sensor.y_beam_z_mm;
  Vec3 axis_in_sensor(0.0, 0.0, -1.0);
  Vec3 axis_f = Vec3::UnitZ(), p_ref = Vec3::Zero();
  double lambda_apex = 0.0;
  const Vec3 y_dir_geom(std::cos(beta_geom), std::sin(beta_geom), 0.0);
  Vec3 previous_tcp = Vec3::Constant(std::numeric_limits<double>::infinity());
  for (int iter = 0; iter < opt.max_iterations; ++iter) {
    std::vector<Vec3> pts;
    CirclePoints(motion, s.circles, sensor, beta_used, z_x, z_y, axis_in_sensor, &pts);
    FitAxisLine(pts, mpath, &p_ref, &axis_f, &s);
    if (axis_f.dot(p_ref) < 0) axis_f = -axis_f;  // towards the tip, away from the flange
    axis_in_sensor = sensor_from_base.linear() * motion.circles[0].base_from_flange_centre.linear() * axis_f;
    CheckAxisTilt(axis_in_sensor, opt, log_path);

    // Tip events on the straight moves.
    const std::vector<TipEvent> tip_events = TipEvents(events, motion, s);
    if (tip_events.empty())
      throw InputError({log_path, 0, "lines"}, "no beam events during the straight moves: the tip was not found");
    const double tool_r = motion.tool_radius_mm;
    // The circles measure the blocking radius in the beam plane; the 3-D distance between the beam
    // line and the tilted tool axis is smaller by |a_z| / sqrt(1 − (a·d)²).
    auto radius_3d = [&](double in_plane, const Vec3& dir_s) {
      if (!(in_plane > 0)) return tool_r;
      const double ad = axis_in_sensor.dot(dir_s);
      return in_plane * std::abs(axis_in_sensor.z()) / std::sqrt(std::max(1e-12, 1.0 - ad * ad));
    };
    const double r_eff[2] = {radius_3d(in_plane_radius[0], Vec3::UnitX()), radius_3d(in_plane_radius[1], y_dir_geom)};
    s.blocking_radius_x_mm = r_eff[0];
    s.blocking_radius_y_mm = r_eff[1];
    auto tip_lambda = [&](const TipEvent& te, double zx, double zy) {
      const double zb = te.beam == 0 ? zx : zy;
      const Vec3 a_base = te.flange.linear() * axis_f;
      const Vec3 c0 = te.flange * p_ref;
      if (opt.tip_model == TipTriggerModel::kApexAtBeamLine) {
        // Sensor z of c0 + λ a equals the beam height.
        const Vec3 c0_s = sensor_from_base * c0, a_s = sensor_from_base.linear() * a_base;
        return (zb - c0_s.z()) / a_s.z();
      }
      const Vec3 dir_s = te.beam == 0 ? Vec3::UnitX() : y_dir_geom;
      const Vec3 bp = base_from_sensor * Vec3(0.0, 0.0, zb), bd = base_from_sensor.linear() * dir_s;
      // dist(line, ray(λ)) is non-increasing in λ: bisect for dist = r_eff.
      double lo = -1000.0, hi = 1000.0;
      if (LineToRayDistance(bp, bd, c0 + hi * a_base, -(a_base)) > r_eff[te.beam]) return std::nan("");
      for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        (LineToRayDistance(bp, bd, c0 + mid * a_base, -(a_base)) > r_eff[te.beam] ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi) + tool_r;
    };
    auto mean_lambda = [&](int beam, double zx, double zy, int* count) {
      double sum = 0.0;
      int n = 0;
      for (const TipEvent& te : tip_events) {
        if (beam >= 0 && te.beam != beam) continue;
        const double l = tip_lambda(te, zx, zy);
        if (std::isnan(l)) continue;
        sum += l;
        ++n;
      }
      if (count) *count = n;
      return n > 0 ? sum / n : std::nan("");
    };
    int nx = 0, ny = 0;
    mean_lambda(0, z_x, z_y, &nx);
    mean_lambda(1, z_x, z_y, &ny);
    if (nx + ny == 0)
      throw InputError({log_path, 0, "lines"},
                       "the tool never came within the blocking radius of a beam on the straight moves");
    if (opt.self_calibrate_beam_offset && nx > 0 && ny > 0) {
      // Height difference Δ = z_x − z_y (mean fixed) such that both beams give the same tip.
      const double delta = BalanceBeamHeights(
          [&](double d) {
            return mean_lambda(0, z_mean + 0.5 * d, z_mean - 0.5 * d, nullptr) -
                   mean_lambda(1, z_mean + 0.5 * d, z_mean - 0.5 * d, nullptr);
          },
          z_x - z_y);
      z_x = z_mean + 0.5 * delta;
      z_y = z_mean - 0.5 * delta;
      s.beam_offset_estimated = true;
    }
    int n = 0;
    lambda_apex = mean_lambda(-1, z_x, z_y, &n);
    s.tip_events = n;
    TipScatter(tip_events, [&](const TipEvent& te) { return tip_lambda(te, z_x, z_y); }, lambda_apex, n, &s);
    if (iter == 0) s.initial_tip_rms_mm = s.tip_rms_mm;
    s.iterations = iter + 1;
    // Fixed point of axis slope, beam heights and tip: stop when the TCP no longer moves.
    const Vec3 tcp = p_ref + lambda_apex * axis_f;
    const double change = (tcp - previous_tcp).norm();
    previous_tcp = tcp;
    if (change < opt.tcp_tolerance_mm) {
      s.converged = true;
      break;
    }
  }
  s.beam_height_difference_mm = z_x - z_y;

  // 5. The 5-DOF frame.
  TcfSolution& sol = s.solution;
  sol.axis_in_flange = axis_f;
  sol.tcp_in_flange = p_ref + lambda_apex * axis_f;
  EulerFromAxis(axis_f, &sol.psi_rad, &sol.theta_rad);
  sol.flange_from_tcp.linear() = FiveDofRotation(sol.psi_rad, sol.theta_rad);
  sol.flange_from_tcp.translation() = sol.tcp_in_flange;
  out.tcp = sol.tcp_in_flange;
  out.axis = axis_f;
  return out;
}

}  // namespace

std::string TcfSolverOptions::Validate() const {
  if (!(max_axis_tilt_deg > 0.0 && max_axis_tilt_deg < 80.0)) return "max_axis_tilt_deg must be in (0, 80)";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(min_blocked_duration_s >= 0.0)) return "min_blocked_duration_s must be >= 0";
  if (!(tcp_tolerance_mm > 0.0)) return "tcp_tolerance_mm must be > 0";
  if (!(timing_sigma_s >= 0.0)) return "timing_sigma_s must be >= 0";
  if (!(repeatability_sigma_mm >= 0.0)) return "repeatability_sigma_mm must be >= 0";
  if (!std::isfinite(assumed_latency_s)) return "assumed_latency_s must be finite";
  return "";
}

std::string TcfSummary::BriefReport() const {
  char buf[400];
  const Vec3& t = solution.tcp_in_flange;
  std::snprintf(buf, sizeof(buf),
                "TCP (%.4f, %.4f, %.4f) mm +- %.4f, psi %.3f theta %.4f deg +- %.4f, beta %.3f deg, latency %.2f ms%s, "
                "beam dz %.3f mm, circle rms %.4f mm, %d tip events (rms %.4f mm), %d iterations%s",
                t.x(), t.y(), t.z(), tcp_sigma_mm, RadToDeg(solution.psi_rad), RadToDeg(solution.theta_rad),
                axis_sigma_deg, RadToDeg(beta_used_rad), latency_s * 1e3, latency_estimated ? " (estimated)" : "",
                beam_height_difference_mm, circle_rms_mm, tip_events, tip_rms_mm, iterations,
                converged ? "" : " (not converged)");
  return buf;
}

Mat3 FiveDofRotation(double psi, double theta) { return RotZ(psi) * RotX(theta) * RotZ(-psi); }

void EulerFromAxis(const Vec3& axis, double* psi, double* theta) {
  const Vec3 a = axis.normalized();
  // R·e_z = (sin ψ sin θ, −cos ψ sin θ, cos θ).
  *theta = std::acos(std::clamp(a.z(), -1.0, 1.0));
  *psi = (std::hypot(a.x(), a.y()) > 1e-15) ? std::atan2(a.x(), -a.y()) : 0.0;
}

void ThesisEulerFromAxis(const Vec3& d, double* psi, double* theta) {
  const double rho = std::hypot(d.x(), d.y());
  const double sign = -d.x() >= 0 ? 1.0 : -1.0;
  *psi = rho > 0 ? sign * std::acos(std::clamp(d.y() / rho, -1.0, 1.0)) : 0.0;
  *theta = std::acos(std::clamp(d.z() / d.norm(), -1.0, 1.0));
}

AxisEstimate EstimateToolAxisFromCircles(const std::vector<BeamEvent>& events, const ProgrammedMotion& motion,
                                         const SensorFrame& sensor, const std::string& log_path) {
  if (motion.circles.size() < 2)
    throw InputError({motion.source, 0, "circles"}, "at least two circles at different heights are needed");
  std::vector<CircleObservation> obs;
  for (const CircleSegment& c : motion.circles)
    obs.push_back(AnalyseCircle(c, events, sensor, sensor.beta_rad, CrossingModel::kEdges, log_path));
  Vec3 axis_in_sensor(0.0, 0.0, -1.0);
  AxisEstimate est;
  for (int iter = 0; iter < 3; ++iter) {
    std::vector<Vec3> pts;
    CirclePoints(motion, obs, sensor, sensor.beta_rad, sensor.x_beam_z_mm, sensor.y_beam_z_mm, axis_in_sensor, &pts);
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : pts) mean += p / pts.size();
    Mat3 scatter = Mat3::Zero();
    for (const Vec3& p : pts) scatter += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
    Vec3 a = eig.eigenvectors().col(2).normalized();
    if (a.dot(mean) < 0) a = -a;
    est.point_in_flange = mean;
    est.axis_in_flange = a;
    axis_in_sensor =
        sensor.base_from_lasersensor.linear().transpose() * motion.circles[0].base_from_flange_centre.linear() * a;
  }
  return est;
}

TcfSummary SolveTcf(const std::vector<BeamEvent>& events_in, const ProgrammedMotion& motion, const SensorFrame& sensor,
                    const TcfSolverOptions& options, const std::string& log_path) {
  ThrowIfInvalid(options.Validate(), "TcfSolverOptions");
  CheckAlternation(events_in, log_path);
  // Glitches: blocked intervals shorter than min_blocked_duration_s (dust, receiver chatter) are
  // dropped with their clear event; alternation is kept.
  std::vector<BeamEvent> events;
  int glitches = 0;
  {
    std::vector<bool> keep(events_in.size(), true);
    int open_index[2] = {-1, -1};
    for (std::size_t i = 0; i < events_in.size(); ++i) {
      const int b = static_cast<int>(events_in[i].beam);
      if (events_in[i].state == BeamState::kBlocked) {
        open_index[b] = static_cast<int>(i);
      } else if (open_index[b] >= 0 &&
                 events_in[i].time_s - events_in[open_index[b]].time_s < options.min_blocked_duration_s) {
        keep[i] = keep[open_index[b]] = false;
        ++glitches;
      }
    }
    for (std::size_t i = 0; i < events_in.size(); ++i)
      if (keep[i]) events.push_back(events_in[i]);
  }
  CoreResult base = SolveCore(events, motion, sensor, options, log_path);
  TcfSummary& s = base.summary;
  s.glitches_removed = glitches;
  if (options.timing_sigma_s > 0.0 || options.repeatability_sigma_mm > 0.0) {
    // First-order propagation: numerical Jacobian of (TCP, axis) w.r.t. every event time and
    // every segment's translation.
    Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
    auto add = [&](const CoreResult& r, double h, double sigma) {
      Eigen::Matrix<double, 6, 1> j;
      j.head<3>() = (r.tcp - base.tcp) / h;
      j.tail<3>() = (r.axis - base.axis) / h;
      cov += sigma * sigma * j * j.transpose();
    };
    if (options.timing_sigma_s > 0.0) {
      const double h = 1e-6;
      for (std::size_t i = 0; i < events.size(); ++i) {
        std::vector<BeamEvent> ev = events;
        ev[i].time_s += h;
        if ((i + 1 < ev.size() && ev[i].time_s > ev[i + 1].time_s)) continue;
        add(SolveCore(ev, motion, sensor, options, log_path), h, options.timing_sigma_s);
      }
    }
    if (options.repeatability_sigma_mm > 0.0) {
      const double h = 1e-4;
      for (std::size_t k = 0; k < motion.circles.size() + motion.lines.size(); ++k) {
        for (int axis = 0; axis < 3; ++axis) {
          ProgrammedMotion m = motion;
          // The robot's offset from its programme is the programme's offset in the opposite sense.
          if (k < motion.circles.size()) {
            m.circles[k].base_from_flange_centre.translation()[axis] += h;
          } else {
            m.lines[k - motion.circles.size()].base_from_flange_start.translation()[axis] += h;
          }
          add(SolveCore(events, m, sensor, options, log_path), h, options.repeatability_sigma_mm);
        }
      }
    }
    s.tcp_covariance_mm2 = cov.topLeftCorner<3, 3>();
    s.tcp_sigma_mm = std::sqrt(std::max(0.0, s.tcp_covariance_mm2.trace()));
    s.axis_sigma_deg = RadToDeg(std::sqrt(std::max(0.0, cov.bottomRightCorner<3, 3>().trace())));
    // Does the tip residual hold more than the noise? Expected scatter of one tip event: the
    // segment's repeatability plus the timing noise times the straight moves' speed.
    double speed2 = 0.0;
    for (const LineSegment& l : motion.lines) speed2 += l.velocity_in_base_mm_s.squaredNorm();
    speed2 /= std::max<std::size_t>(1, motion.lines.size());
    const double expected =
        std::sqrt(std::pow(options.repeatability_sigma_mm, 2) + speed2 * std::pow(options.timing_sigma_s, 2));
    if (expected > 0.0 && s.tip_events > 1) {
      s.tip_noise_ratio = s.tip_rms_mm / expected;
      if (s.tip_noise_ratio > kStructureRatio) {
        s.sigma_inflated = true;
        s.tcp_covariance_mm2 *= s.tip_noise_ratio * s.tip_noise_ratio;
        s.tcp_sigma_mm *= s.tip_noise_ratio;
        s.axis_sigma_deg *= s.tip_noise_ratio;
        char buf[300];
        std::snprintf(buf, sizeof(buf),
                      "tip residual RMS %.4f mm is %.1fx the expected noise %.4f mm: the data hold an effect the "
                      "solver does not model; the reported sigmas are inflated by that factor (run ramtk diagnose "
                      "on the log)",
                      s.tip_rms_mm, s.tip_noise_ratio, expected);
        s.warnings.push_back(buf);
      }
    }
  }
  if (!options.self_calibrate_beta && s.beta_self_calibrated_sigma_rad > 0.0 && !s.circles.empty() &&
      std::abs(s.beta_self_calibrated_rad - sensor.beta_rad) >
          std::max(kBetaDisagreementSigmas * s.beta_self_calibrated_sigma_rad, DegToRad(kBetaMaterialDeg))) {
    s.beta_disagrees = true;
    char buf[300];
    std::snprintf(buf, sizeof(buf),
                  "the circle phases give beta = %.3f +- %.3f deg, the sensor file says %.3f deg (%.0f sigma): "
                  "the file's beta was used; pass --self-calibrate-beta or recalibrate the device",
                  RadToDeg(s.beta_self_calibrated_rad), RadToDeg(s.beta_self_calibrated_sigma_rad),
                  RadToDeg(sensor.beta_rad),
                  std::abs(s.beta_self_calibrated_rad - sensor.beta_rad) / s.beta_self_calibrated_sigma_rad);
    s.warnings.push_back(buf);
  }
  for (const std::string& w : s.warnings) RAMTK_LOG(kWarning) << w;
  RAMTK_LOG(kDebug) << s.BriefReport();
  return s;
}

std::string TcfSummaryToJson(const TcfSummary& s) {
  nlohmann::json j;
  j["flange_from_tcp"] = PoseToJson(s.solution.flange_from_tcp);
  j["tcp_in_flange_mm"] = Vec3ToJson(s.solution.tcp_in_flange);
  j["axis_in_flange"] = Vec3ToJson(s.solution.axis_in_flange);
  j["psi_deg"] = RadToDeg(s.solution.psi_rad);
  j["theta_deg"] = RadToDeg(s.solution.theta_rad);
  j["beta_used_deg"] = RadToDeg(s.beta_used_rad);
  j["beta_from_circle_phases_deg"] = RadToDeg(s.beta_self_calibrated_rad);
  j["beta_from_circle_phases_sigma_deg"] = RadToDeg(s.beta_self_calibrated_sigma_rad);
  j["beta_disagrees"] = s.beta_disagrees;
  j["tip_noise_ratio"] = s.tip_noise_ratio;
  j["sigma_inflated"] = s.sigma_inflated;
  j["warnings"] = s.warnings;
  j["latency_ms"] = s.latency_s * 1e3;
  j["latency_estimated"] = s.latency_estimated;
  j["phase_misalignment_deg"] = RadToDeg(s.phase_misalignment_rad);
  j["speed_scale"] = s.speed_scale;
  j["beam_height_difference_mm"] = s.beam_height_difference_mm;
  j["beam_offset_estimated"] = s.beam_offset_estimated;
  j["blocking_radius_mm"] = {s.blocking_radius_x_mm, s.blocking_radius_y_mm};
  j["tip_events"] = s.tip_events;
  j["tip_rms_mm"] = s.tip_rms_mm;
  j["tip_worst_mm"] = s.tip_worst_mm;
  j["tip_events_unused"] = s.tip_events_unused;
  j["initial_tip_rms_mm"] = s.initial_tip_rms_mm;
  j["iterations"] = s.iterations;
  j["glitches_removed"] = s.glitches_removed;
  j["circle_rms_mm"] = s.circle_rms_mm;
  j["circle_worst_mm"] = s.circle_worst_mm;
  j["converged"] = s.converged;
  j["tcp_sigma_mm"] = s.tcp_sigma_mm;
  j["axis_sigma_deg"] = s.axis_sigma_deg;
  nlohmann::json circles = nlohmann::json::array();
  for (const CircleObservation& c : s.circles) {
    circles.push_back({{"name", c.name},
                       {"period_s", c.period_s},
                       {"d_x_mm", c.x.distance_mm},
                       {"d_y_mm", c.y.distance_mm},
                       {"blocking_radius_x_mm", c.x.blocking_radius_mm},
                       {"blocking_radius_y_mm", c.y.blocking_radius_mm}});
  }
  j["circles"] = circles;
  j["report"] = s.BriefReport();
  return j.dump(2) + "\n";
}

}  // namespace ramtk::tcf
