#pragma once
// Baseline TCP/TCF methods of thesis §4.1 on the same simulated tool, for comparison with the
// cross-laser device:
//  * 4-point (eqs. 4-1, 4-2, 4-4): the operator brings the tip to one reference point from four
//    orientations; the sphere through the four flange positions gives the point, least squares the
//    TCP. 7-point: plus the operator aligning the tool frame with the base and moving along X_b
//    and Z_b (eq. 4-5); its orientation accuracy is the operator's visual alignment.
//  * parallel laser (eqs. 4-6, 4-7): two horizontal beams along Y_b at two heights; the tool is
//    moved along X_b through them at two flange rotations 90° apart (blocked/clear midpoints locate
//    the axis at both heights), then lowered until the upper beam is blocked (the apex on the beam
//    line, eq. 4-7). Simplification: the tool is not re-oriented vertical before lowering; the
//    measured axis is used to place it instead.
// Each "Simulate…" function simulates the measurements of the method with the given noise and
// returns the method's result; the solvers take the recorded flange poses.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"

namespace ramtk::tcf {

struct BaselineResult {
  Vec3 tcp_in_flange = Vec3::Zero();
  Vec3 axis_in_flange = Vec3::UnitZ();  // unit, towards the tip
  bool has_axis = false;                // the 4-point method gives no orientation
  double residual_rms_mm = 0.0;         // RMS residual of the TCP least squares
};

// Eq. (4-2): sphere centre through four points; eq. (4-4): TCP by least squares.
BaselineResult SolveFourPoint(const std::array<Isometry3, 4>& base_from_flange);
// Eq. (4-5): adds the orientation from P5 (tool frame aligned with the base by eye), P6 (moved
// along X_b) and P7 (then along Z_b). The axis is the tool frame's Z.
BaselineResult SolveSevenPoint(const std::array<Isometry3, 4>& touch_poses, const std::array<Isometry3, 3>& axis_poses);

struct TouchUpSimulationOptions {
  std::uint64_t seed = 1;
  double repeatability_mm = 0.03;  // robot: 1-sigma per axis of each recorded pose
  double touch_sigma_mm = 0.1;     // operator: 1-sigma per axis of the tip-on-point alignment by eye
  double align_sigma_deg = 0.5;    // operator: 1-sigma per axis of the tool-frame alignment by eye
  double tilt_deg = 40.0;          // largest tilt of the four touch orientations (0.4, 0.6, 0.8, 1.0 of it)
  double move_mm = 50.0;           // P5 -> P6 along X_b, P6 -> P7 along Z_b
  Vec3 reference_point_in_base = Vec3(900.0, 0.0, 300.0);
};
BaselineResult SimulateFourPoint(const Isometry3& flange_from_tcp, const TouchUpSimulationOptions& options);
BaselineResult SimulateSevenPoint(const Isometry3& flange_from_tcp, const TouchUpSimulationOptions& options);

struct ParallelLaserSimulationOptions {
  std::uint64_t seed = 1;
  double repeatability_mm = 0.03;  // robot: 1-sigma per axis of each scan's position error
  double timing_jitter_s = 2e-5;   // receiver jitter
  double scan_speed_mm_s = 10.0;   // along X_b and down
  double beam_spacing_mm = 20.0;   // Δh
  double beam_width_mm = 0.0;
  double tool_radius_mm = 2.5;  // ball-nosed cylinder, as in the cross-laser simulator
  double nominal_tool_length_mm = 150.0;
  Vec3 upper_beam_point_in_base = Vec3(900.0, 0.0, 300.0);  // beams along Y_b; lower one Δh below
};
BaselineResult SimulateParallelLaser(const Isometry3& flange_from_tcp, const ParallelLaserSimulationOptions& options);

}  // namespace ramtk::tcf
