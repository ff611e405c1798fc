#pragma once
// The cross-laser TCF solver (thesis §4.2.2, §4.3.2) with ramtk's self-calibration.
//
// Pipeline:
//  1. Each circle -> signed distances d_x, d_y of the tool axis' cross-section from the beams
//     (circle_timing.h).
//  2. Oblique beams (eqs. 4-28, 4-29): centre (x, y) = (d_y / sin β + d_x / tan β, d_x) in the
//     orthogonal sensor frame X_s, Y'_s. The thesis's uncorrected variant uses (d_y, d_x).
//  3. Two circles at different flange heights give two points of the tool axis; mapped into the
//     flange frame they give the axis direction a (eqs. 4-11, 4-12) and the Euler angles ψ, θ of
//     R = RotZ(ψ)·RotX(θ)·RotZ(−ψ) (eqs. 4-10, 4-13), with R·e_z = a.
//  4. Straight moves through the beams locate the tip along the axis (eq. 4-14): ramtk models the
//     tool as a ball-nosed cylinder and finds where the axis' ball centre was when a beam's
//     distance to the tool reached the blocking radius measured on the circles; the TCP is the
//     apex, ball centre + tool radius · a. The thesis variant puts the apex on the beam line.
//  5. flange_from_tcp = [R | TCP], 5 DOF (no rotation about the tool axis).
//
// Self-calibration (beyond the thesis), each switchable:
//  * trigger latency: clockwise and counter-clockwise circles shift the crossings' phase by
//    ±ω·latency; their difference gives the latency, used to look up the flange on straight moves;
//  * beam offset along the tool axis: the x- and y-beam events of the straight moves give the
//    beams' height difference; the circles' d_x, d_y are referred to one plane with the axis slope;
//  * speed scale: the circles' measured period against the programmed one;
//  * β: from the phase difference of the x- and y-beam crossings on the circles.
// The TCP uncertainty is propagated to first order from a timing noise and the robot's
// repeatability (numerical Jacobian of the whole solve).

#include <string>
#include <vector>

#include "ramtk/tcf/circle_timing.h"
#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"

namespace ramtk::tcf {

enum class TipTriggerModel {
  kBallNose,        // ramtk: blocking radius from the circles, apex = ball centre + radius · a
  kApexAtBeamLine,  // thesis eq. (4-14): the apex is on the beam line when the beam is blocked
};

struct TcfSolverOptions {
  CrossingModel crossing_model = CrossingModel::kEdges;
  TipTriggerModel tip_model = TipTriggerModel::kBallNose;
  // Apply eq. (4-29) for β != 90°; false is the thesis's uncorrected variant (β taken as 90°).
  bool correct_oblique_beams = true;
  // Estimate β from the circle phases instead of taking it from the sensor frame.
  bool self_calibrate_beta = false;
  // Estimate the trigger latency from cw + ccw circles (needs both directions; else 0).
  bool self_calibrate_latency = true;
  // Estimate the beams' height difference from the straight moves (needs events of both beams).
  bool self_calibrate_beam_offset = true;
  // Scale the straight moves' speed by the programmed / measured revolution period of the
  // circles (a controller speed override or scale error shows there first).
  bool self_calibrate_speed = true;
  // Latency (s) assumed when it is not self-calibrated.
  double assumed_latency_s = 0.0;
  // The axis slope, beam heights and tip are refined as a fixed point: at most this many passes,
  // stopping when the TCP moves less than tcp_tolerance_mm.
  int max_iterations = 10;
  double tcp_tolerance_mm = 1e-7;
  // Blocked intervals shorter than this (s) are receiver glitches and are dropped (a real crossing
  // of a 5 mm tool at the programmed speeds lasts > 0.1 s).
  double min_blocked_duration_s = 2e-3;
  // Largest tool-axis tilt from the device normal the device can measure (deg).
  double max_axis_tilt_deg = 30.0;
  // Uncertainty propagation: 1-sigma timing noise (s) of one event and robot repeatability
  // (1-sigma per axis, mm) of one programmed segment. Skipped if both are 0.
  double timing_sigma_s = 1e-4;
  double repeatability_sigma_mm = 0.03;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// A self-calibrated quantity disagreeing with the sensor file by more than this many σ is reported.
inline constexpr double kBetaDisagreementSigmas = 5.0;
// … and by more than this (deg): smaller differences move the TCP by well under a micrometre.
inline constexpr double kBetaMaterialDeg = 0.1;
// Tip residual RMS beyond this multiple of the expected noise counts as structure (σ inflated).
inline constexpr double kStructureRatio = 2.0;

struct TcfSolution {
  Isometry3 flange_from_tcp = Isometry3::Identity();  // 5-DOF tool frame
  Vec3 tcp_in_flange = Vec3::Zero();
  Vec3 axis_in_flange = Vec3::UnitZ();    // unit, towards the tip
  double psi_rad = 0.0, theta_rad = 0.0;  // eq. (4-13)
};

struct TcfSummary {
  TcfSolution solution;
  std::vector<CircleObservation> circles;
  double beta_used_rad = 0.0;             // β used in eq. (4-29) (90° if not corrected)
  double beta_self_calibrated_rad = 0.0;  // from circle phases (0 if fewer than 1 circle)
  // 1σ of beta_self_calibrated_rad: the larger of the circles' scatter and the timing noise
  // propagated to the phase difference (ω·σ_t per circle), over √K.
  double beta_self_calibrated_sigma_rad = 0.0;
  // The sensor file's β disagrees with the circle phases by more than kBetaDisagreementSigmas σ and
  // kBetaMaterialDeg (and β was not self-calibrated): a warning is logged and listed in `warnings`.
  bool beta_disagrees = false;
  // Tip residual RMS over its expected scatter (√(σ_rep² + (v·σ_t)²) per event): > kStructureRatio
  // means the residual holds more than the noise (an unmodelled effect); tcp_sigma_mm and
  // axis_sigma_deg are then multiplied by this ratio (sigma_inflated).
  double tip_noise_ratio = 0.0;
  bool sigma_inflated = false;
  std::vector<std::string> warnings;  // one sentence each; also logged at kWarning
  double latency_s = 0.0;                 // used on straight moves
  bool latency_estimated = false;
  double phase_misalignment_rad = 0.0;     // common phase offset of cw + ccw circles
  double speed_scale = 1.0;                // executed / programmed speed applied to the straight moves
  double beam_height_difference_mm = 0.0;  // z_x − z_y used
  bool beam_offset_estimated = false;
  // Blocking radius of each beam (3-D distance beam line – tool axis at the state change: tool radius
  // + half the beam width), from the circles' in-plane values and the axis tilt.
  double blocking_radius_x_mm = 0.0, blocking_radius_y_mm = 0.0;
  // Termination and residuals. The residual of a straight-move event is its tip position along
  // the axis minus the mean over events.
  int iterations = 0;
  bool converged = false;           // the TCP moved less than tcp_tolerance_mm in the last pass
  int glitches_removed = 0;         // blocked/clear pairs shorter than min_blocked_duration_s
  int tip_events = 0;               // straight-move events used for the TCP
  int tip_events_unused = 0;        // events where the tool never reached the blocking radius (outliers)
  double initial_tip_rms_mm = 0.0;  // residual RMS of the first pass (calibrated heights, vertical slope)
  double tip_rms_mm = 0.0;          // final residual RMS
  double tip_worst_mm = 0.0;        // final largest residual
  // Distances of the circles' axis points from the fitted axis (RMS, largest).
  double circle_rms_mm = 0.0, circle_worst_mm = 0.0;
  // First-order 1-sigma uncertainties.
  Mat3 tcp_covariance_mm2 = Mat3::Zero();
  double tcp_sigma_mm = 0.0;    // sqrt(trace)
  double axis_sigma_deg = 0.0;  // RMS angular uncertainty of the axis
  std::string BriefReport() const;
};

// Solves the tool frame from the device log, the programmed motion and the sensor frame.
// InputError for bad input (see docs/tcf.md); `log_path` names the log in errors.
TcfSummary SolveTcf(const std::vector<BeamEvent>& events, const ProgrammedMotion& motion, const SensorFrame& sensor,
                    const TcfSolverOptions& options = {}, const std::string& log_path = "");

// The tool axis from the circles alone (steps 1-3, calibrated β and beam heights): a point of the
// axis and its direction (towards the tip) in the flange frame. Used by a controller (and the
// simulator) to place the straight moves through the beam crossing (thesis step 3).
struct AxisEstimate {
  Vec3 point_in_flange = Vec3::Zero();
  Vec3 axis_in_flange = Vec3::UnitZ();
};
AxisEstimate EstimateToolAxisFromCircles(const std::vector<BeamEvent>& events, const ProgrammedMotion& motion,
                                         const SensorFrame& sensor, const std::string& log_path = "");

// Eq. (4-10): RotZ(ψ)·RotX(θ)·RotZ(−ψ).
Mat3 FiveDofRotation(double psi_rad, double theta_rad);
// ψ, θ with FiveDofRotation(ψ, θ)·e_z = axis/|axis| (θ in [0, π], ψ in (−π, π]).
void EulerFromAxis(const Vec3& axis, double* psi_rad, double* theta_rad);
// Eq. (4-13) exactly as printed: ψ = sgn(−Δx)·arccos(Δy/√(Δx²+Δy²)), θ = arccos(Δz/|Δ|).
// Used with the printed eq. (4-12), whose x and y carry the opposite sign (see docs/tcf.md).
void ThesisEulerFromAxis(const Vec3& delta, double* psi_rad, double* theta_rad);

// JSON of a solution for `ramtk tcf solve`.
std::string TcfSummaryToJson(const TcfSummary& summary);

}  // namespace ramtk::tcf
