// Circle timings -> centre distances: closed-form geometry generated here independently of the
// simulator (the blocked set of a disc of radius r against a line, scanned and bisected).
#include "ramtk/tcf/circle_timing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/tcf/geometry.h"

namespace ramtk::tcf {
namespace {

struct Config {
  double cx = 2.0, cy = -3.0;  // centre of the cross-section's circle, sensor frame (mm)
  double r_block = 2.8;        // blocking radius (mm)
  double radius = 12.0;
  double beta = DegToRad(92.15);
  double omega = DegToRad(180.0);
  double latency = 0.0;
  int direction = 1;
};

SensorFrame IdentitySensor(double beta) {
  SensorFrame s;
  s.beta_rad = beta;
  return s;
}

CircleSegment MakeCircle(const Config& c) {
  CircleSegment seg;
  seg.name = "c";
  seg.start_time_s = 1.0;
  seg.radius_mm = c.radius;
  seg.angular_speed_rad_s = c.omega;
  seg.direction = c.direction;
  seg.start_angle_rad = DegToRad(45.0);
  seg.duration_s = 1.25 * 2 * kPi / c.omega;
  return seg;
}

// Events of the point c + R(cos φ, sin φ) against the two beams through the origin.
std::vector<BeamEvent> Events(const Config& c, const CircleSegment& seg) {
  std::vector<BeamEvent> ev;
  const Vec3 nu[2] = {Vec3(0, 1, 0), Vec3(std::sin(c.beta), -std::cos(c.beta), 0)};
  for (int b = 0; b < 2; ++b) {
    auto blocked = [&](double t) {
      const double phi = seg.AngleAt(t);
      const Vec3 p(c.cx + c.radius * std::cos(phi), c.cy + c.radius * std::sin(phi), 0);
      return std::abs(p.dot(nu[b])) < c.r_block;
    };
    const int n = 20000;
    bool prev = blocked(seg.start_time_s);
    for (int i = 1; i <= n; ++i) {
      const double t0 = seg.start_time_s + seg.duration_s * (i - 1) / n, t1 = seg.start_time_s + seg.duration_s * i / n;
      if (blocked(t1) == prev) continue;
      double lo = t0, hi = t1;
      for (int k = 0; k < 60; ++k) (blocked(0.5 * (lo + hi)) == prev ? lo : hi) = 0.5 * (lo + hi);
      prev = !prev;
      ev.push_back(
          {0.5 * (lo + hi) + c.latency, static_cast<Beam>(b), prev ? BeamState::kBlocked : BeamState::kClear, 0});
    }
  }
  std::sort(ev.begin(), ev.end(), [](const BeamEvent& a, const BeamEvent& b) { return a.time_s < b.time_s; });
  return ev;
}

TEST(CircleTiming, EdgesModelIsExactForAnyBlockingRadius) {
  Config c;
  const CircleSegment seg = MakeCircle(c);
  const CircleObservation o = AnalyseCircle(seg, Events(c, seg), IdentitySensor(c.beta), c.beta, CrossingModel::kEdges);
  const double dx = c.cy;                                               // distance from the x beam
  const double dy = c.cx * std::sin(c.beta) - c.cy * std::cos(c.beta);  // from the y beam
  EXPECT_NEAR(o.x.distance_mm, dx, 1e-7);
  EXPECT_NEAR(o.y.distance_mm, dy, 1e-7);
  EXPECT_NEAR(o.x.blocking_radius_mm, c.r_block, 1e-7);
  EXPECT_NEAR(o.y.blocking_radius_mm, c.r_block, 1e-7);
  EXPECT_TRUE(o.period_measured);
  EXPECT_NEAR(o.period_s, 2.0, 1e-8);
  EXPECT_NEAR(o.x.phase_offset_rad, 0.0, 1e-7);
  EXPECT_NEAR(o.y.phase_offset_rad, 0.0, 1e-7);
  // Eq. (4-29) recovers the Cartesian centre; taking β = 90° (the uncorrected variant) does not.
  const double x2 = dy / std::cos(c.beta - kPi / 2) + dx / std::tan(c.beta);
  EXPECT_NEAR(x2, c.cx, 1e-12);
  EXPECT_GT(std::abs(dy - c.cx), 0.1);
  // With the thesis's printed 87.85° instead of 92.15° the correction has the wrong sign.
  const double b_printed = DegToRad(87.85);
  EXPECT_GT(std::abs(dy / std::sin(b_printed) + dx / std::tan(b_printed) - c.cx), 0.2);
}

TEST(CircleTiming, ThesisMidpointsAreBiasedByTheBlockingRadius) {
  Config c;
  const CircleSegment seg = MakeCircle(c);
  const CircleObservation o =
      AnalyseCircle(seg, Events(c, seg), IdentitySensor(c.beta), c.beta, CrossingModel::kThesisMidpoints);
  // Exact for the midpoint model: d' = R sin(mean of asin((d ± r)/R)).
  auto midpoint_d = [&](double d) {
    return c.radius * std::sin(0.5 * (std::asin((d + c.r_block) / c.radius) + std::asin((d - c.r_block) / c.radius)));
  };
  EXPECT_NEAR(o.x.distance_mm, midpoint_d(c.cy), 1e-7);
  EXPECT_GT(std::abs(o.x.distance_mm - c.cy), 0.5 * std::abs(c.cy) * c.r_block * c.r_block / (c.radius * c.radius));
  // With a thin tool the thesis's formula is exact.
  Config thin = c;
  thin.r_block = 0.02;
  const CircleObservation t =
      AnalyseCircle(seg, Events(thin, seg), IdentitySensor(c.beta), c.beta, CrossingModel::kThesisMidpoints);
  // Bias d r² / (2 R²) = 4e-6 mm for r = 0.02 mm.
  EXPECT_NEAR(t.x.distance_mm, thin.cy, 1e-5);
}

TEST(CircleTiming, LatencyShiftsThePhaseByDirectionTimesOmega) {
  for (int dir : {1, -1}) {
    Config c;
    c.latency = 0.01;
    c.direction = dir;
    const CircleSegment seg = MakeCircle(c);
    const CircleObservation o =
        AnalyseCircle(seg, Events(c, seg), IdentitySensor(c.beta), c.beta, CrossingModel::kEdges);
    EXPECT_NEAR(o.x.phase_offset_rad, dir * c.omega * c.latency, 1e-7);
    EXPECT_NEAR(o.y.phase_offset_rad, dir * c.omega * c.latency, 1e-7);
    EXPECT_NEAR(o.x.distance_mm, c.cy, 1e-7);  // a constant latency cancels in the distances
  }
}

TEST(CircleTiming, TooFewCrossingsIsAnInputError) {
  Config c;
  c.cx = 0.0;
  c.cy = 10.5;  // the circle dips into the x beam only once: |d| + r > R
  const CircleSegment seg = MakeCircle(c);
  try {
    AnalyseCircle(seg, Events(c, seg), IdentitySensor(c.beta), c.beta, CrossingModel::kEdges, "log.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ramtk::tcf

namespace ramtk::tcf {
namespace {

// LineToRayDistance (one implementation for the simulator, the solver and the diagnosis) against
// closed forms: a perpendicular ray passing the line, a ray pointing away (the clamp μ ≥ 0), a
// ray parallel to the line.
TEST(TcfGeometry, LineToRayDistanceClosedForms) {
  const Vec3 p(0, 0, 0), d(1, 0, 0);  // the x axis
  // Ray from (3, 5, 2) straight down −y: crosses below the line's height 2 away in z.
  EXPECT_NEAR(LineToRayDistance(p, d, Vec3(3, 5, 2), Vec3(0, -1, 0)), 2.0, 1e-12);
  // The same ray pointing up +y: the closest point is its start, √(5² + 2²) away.
  EXPECT_NEAR(LineToRayDistance(p, d, Vec3(3, 5, 2), Vec3(0, 1, 0)), std::sqrt(29.0), 1e-12);
  // Parallel to the line, 4 away.
  EXPECT_NEAR(LineToRayDistance(p, d, Vec3(-7, 0, 4), Vec3(1, 0, 0)), 4.0, 1e-12);
  // A skew ray: against a dense sampling of μ.
  const Vec3 c(1, 2, 3), e = Vec3(0.3, -0.8, 0.5).normalized();
  double best = 1e300;
  for (int i = 0; i <= 200000; ++i) {
    const Vec3 q = c + (i * 1e-4) * e;
    best = std::min(best, std::hypot(q.y(), q.z()));
  }
  EXPECT_NEAR(LineToRayDistance(p, d, c, e), best, 1e-6);
}

}  // namespace
}  // namespace ramtk::tcf
