// Circle timings -> centre distances from the beams (eqs. 4-8, 4-9 and the exact edge model).
#include "ramtk/tcf/circle_timing.h"

#include <cmath>
#include <cstdio>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::tcf {
namespace {

double WrapPi(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

struct Interval {
  double blocked = 0.0, clear = 0.0;
};

}  // namespace

Vec3 BeamNormalInSensor(Beam beam, double beta_rad) {
  return beam == Beam::kX ? Vec3(0.0, 1.0, 0.0) : Vec3(std::sin(beta_rad), -std::cos(beta_rad), 0.0);
}

CircleObservation AnalyseCircle(const CircleSegment& circle, const std::vector<BeamEvent>& events,
                                const SensorFrame& sensor, double beta_rad, CrossingModel model,
                                const std::string& source) {
  CircleObservation out;
  out.name = circle.name;
  const double t0 = circle.start_time_s, t1 = circle.start_time_s + circle.duration_s;
  std::vector<Interval> intervals[2];
  int open_line[2] = {0, 0};
  bool open[2] = {false, false};
  for (const BeamEvent& e : events) {
    if (e.time_s < t0 || e.time_s > t1) continue;
    const int b = static_cast<int>(e.beam);
    if (e.state == BeamState::kBlocked) {
      if (open[b])
        throw InputError({source, e.line, "state"}, "beam events do not alternate in circle '" + circle.name + "'");
      intervals[b].push_back({e.time_s, 0.0});
      open[b] = true;
      open_line[b] = e.line;
    } else {
      if (!open[b])
        throw InputError({source, e.line, "state"},
                         "circle '" + circle.name + "' starts inside the " + BeamName(e.beam) +
                             " beam ('clear' without 'blocked'); start the circle between the beams");
      intervals[b].back().clear = e.time_s;
      open[b] = false;
    }
  }
  for (int b = 0; b < 2; ++b) {
    if (open[b]) intervals[b].pop_back();  // a crossing cut by the window's end is not used
    (void)open_line[b];
  }
  const int nx = static_cast<int>(intervals[0].size()), ny = static_cast<int>(intervals[1].size());
  if (nx < 2 || ny < 2) {
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "circle '%s' has %d complete beam crossings (x: %d, y: %d); at least 4 (2 per beam) are needed — "
                  "is the tool axis within the device's range?",
                  circle.name.c_str(), nx + ny, nx, ny);
    throw InputError({source, 0, "circles"}, buf);
  }
  // Period: from crossings that repeat one revolution later (the 3rd interval of a beam).
  double period_sum = 0.0;
  int period_n = 0;
  for (int b = 0; b < 2; ++b) {
    if (intervals[b].size() >= 3) {
      period_sum += intervals[b][2].blocked - intervals[b][0].blocked;
      period_sum += intervals[b][2].clear - intervals[b][0].clear;
      period_n += 2;
    }
  }
  const double programmed_period = 2.0 * kPi / circle.angular_speed_rad_s;
  out.period_s = period_n > 0 ? period_sum / period_n : programmed_period;
  out.period_measured = period_n > 0;
  if (std::abs(out.period_s - programmed_period) > 0.2 * programmed_period)
    throw InputError({source, 0, "circles"}, "circle '" + circle.name +
                                                 "': the measured revolution period differs from the programme by more "
                                                 "than 20%");
  const double omega = 2.0 * kPi / out.period_s;  // eq. (4-8): angles as fractions of a revolution
  const double r_mm = circle.radius_mm;
  const Mat3 sensor_rot = sensor.base_from_lasersensor.linear();
  // Sense of the programmed angle relative to the sensor's Z: +1 if u × v is along Z_s.
  const double sense = circle.u_in_base.cross(circle.v_in_base).dot(sensor_rot.col(2)) >= 0 ? 1.0 : -1.0;

  for (int b = 0; b < 2; ++b) {
    const Beam beam = static_cast<Beam>(b);
    const Interval& i1 = intervals[b][0];
    const Interval& i2 = intervals[b][1];
    const Vec3 nu_base = sensor_rot * BeamNormalInSensor(beam, beta_rad);
    // Angle of −ν in the circle's frame.
    const double neg_angle = std::atan2(-nu_base.dot(circle.v_in_base), -nu_base.dot(circle.u_in_base));
    // The two gaps: between the intervals (a) and around the end of the revolution (b).
    const double gap_a = i2.blocked - i1.clear;
    const double gap_b = out.period_s - (i2.clear - i1.blocked);
    const double mid_a = 0.5 * (i1.clear + i2.blocked);
    const double mid_b = i2.clear + 0.5 * gap_b;
    if (gap_a <= 0.0 || gap_b <= 0.0)
      throw InputError({source, 0, "circles"}, "circle '" + circle.name + "': " + BeamName(beam) +
                                                   " beam crossings overlap; radius too small for the tool?");
    // Which gap is on the −ν side: its middle points along −ν.
    const double phi_a = circle.AngleAt(mid_a), phi_b = circle.AngleAt(mid_b);
    const double da = std::cos(phi_a - neg_angle), db = std::cos(phi_b - neg_angle);
    if ((da > 0) == (db > 0))
      throw InputError({source, 0, "circles"}, "circle '" + circle.name + "': the " + BeamName(beam) +
                                                   " beam crossings do not match the programmed circle");
    const bool a_is_neg = da > 0;
    const double gap_neg = a_is_neg ? gap_a : gap_b, gap_pos = a_is_neg ? gap_b : gap_a;
    const double mid_neg = a_is_neg ? mid_a : mid_b;
    BeamCircleObservation& o = b == 0 ? out.x : out.y;
    o.crossings = static_cast<int>(intervals[b].size());
    if (model == CrossingModel::kEdges) {
      const double g_neg = r_mm * std::cos(0.5 * omega * gap_neg);
      const double g_pos = r_mm * std::cos(0.5 * omega * gap_pos);
      o.distance_mm = 0.5 * (g_neg - g_pos);
      o.blocking_radius_mm = 0.5 * (g_neg + g_pos);
    } else {
      // Eq. (4-9): arc between the crossing midpoints on the −ν side.
      const double m1 = 0.5 * (i1.blocked + i1.clear), m2 = 0.5 * (i2.blocked + i2.clear);
      const double arc_a = omega * (m2 - m1);
      const double arc_neg = a_is_neg ? arc_a : 2.0 * kPi - arc_a;
      o.distance_mm = r_mm * std::cos(0.5 * arc_neg);
      o.blocking_radius_mm = 0.0;
    }
    // Phase with the measured angular speed, so a robot speed-scale error is not taken for latency.
    o.neg_gap_mid_angle_rad = circle.start_angle_rad + circle.direction * omega * (mid_neg - circle.start_time_s);
    o.phase_offset_rad = WrapPi(o.neg_gap_mid_angle_rad - neg_angle);
    (void)sense;
  }
  return out;
}

}  // namespace ramtk::tcf
