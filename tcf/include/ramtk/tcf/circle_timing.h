#pragma once
// From the beam-break timings of one programmed circle to the circle centre's signed distances
// from the two beams (thesis eqs. 4-8, 4-9) and, beyond the thesis, the effective blocking
// radius (tool radius + half the beam width) and the phase of the crossings.
//
// Geometry. In the beam plane the tool's cross-section centre runs on a circle of radius R about
// c. A beam through the origin with unit in-plane normal ν sees the signed distance
// s(φ) = c·ν + R cos(φ − φ_ν), and is blocked while |s| < r (r = tool radius + half beam width).
// Per revolution each beam has two blocked intervals and two gaps: the gap on the −ν side spans
// 2h₋ with R cos h₋ = c·ν + r, the one on the +ν side 2h₊ with R cos h₊ = r − c·ν, so
//   d = c·ν = (R cos h₋ − R cos h₊) / 2,   r = (R cos h₋ + R cos h₊) / 2      (exact, "edges")
// whatever r is. The thesis (eq. 4-9) takes one time per crossing (here: the blocked interval's
// midpoint) and d = R cos(A₋/2) with A₋ the arc between the two crossings on the −ν side; that is
// exact only for r = 0 (bias ≈ d r² / (2 R²)).
// Angles come from times as fractions of the revolution period (eq. 4-8), so a constant speed
// error cancels; the period is measured when a crossing repeats, else taken from the programme.
// Normals: ν_x = (0, 1) (so d_x = c_y), ν_y = (sin β, −cos β) (so d_y = c_x for β = 90°).

#include <string>
#include <vector>

#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"

namespace ramtk::tcf {

enum class CrossingModel {
  kEdges,            // both edges of each crossing, exact for any blocking radius (ramtk)
  kThesisMidpoints,  // one time per crossing, eq. (4-9) (the thesis)
};

// What one circle tells about one beam.
struct BeamCircleObservation {
  double distance_mm = 0.0;         // d = c·ν, signed distance of the centre from the beam
  double blocking_radius_mm = 0.0;  // r (edges model only; 0 for the midpoint model)
  // Angle (rad) at the middle of the −ν gap — start angle + direction·ω_measured·(t − start) —
  // minus the angle of −ν in the circle's (u, v) frame, wrapped to (−π, π]:
  // ≈ direction·ω·latency + angular misalignment.
  double phase_offset_rad = 0.0;
  double neg_gap_mid_angle_rad = 0.0;  // the angle at the middle of the −ν gap
  int crossings = 0;                   // blocked intervals in the circle's window
};

struct CircleObservation {
  std::string name;
  double period_s = 0.0;         // one revolution
  bool period_measured = false;  // true if measured from a repeated crossing
  BeamCircleObservation x, y;
};

// Analyses the events of `circle` (the events whose time lies in the circle's window are used).
// beta_rad: the angle of the y beam (sets ν_y and the expected phase). InputError if a beam is
// crossed fewer than twice, or the crossings are inconsistent with the programme.
CircleObservation AnalyseCircle(const CircleSegment& circle, const std::vector<BeamEvent>& events,
                                const SensorFrame& sensor, double beta_rad, CrossingModel model,
                                const std::string& source = "");

// Normal ν of a beam in the sensor plane (see the header comment).
Vec3 BeamNormalInSensor(Beam beam, double beta_rad);

}  // namespace ramtk::tcf
