#pragma once
// Kinematic calibration of a serial robot (any number of revolute joints) from a tracker's
// measurements: targets on the tool measured as 3-D points, or the tool's 6-D pose.
//
//   target_k_in_tracker(q) = tracker_from_base · base_from_flange(q; links, terms) · target_k_in_flange
//   tracker_from_tool(q)   = tracker_from_base · base_from_flange(q; links, terms) · flange_from_tool
//
// Unknowns: the links' MDH(β) parameters (thesis eq. 2-18; β is offered where consecutive axes
// are near-parallel, thesis §2.2.3), tracker_from_base, each target in the flange, the tool's
// rotation for 6-D data, and optional non-geometric terms (per-joint cyclic errors, joint
// compliance under gravity from the robot file's masses), each kept only when it lowers the
// held-out error.
//
// Identifiability comes first: the measurement Jacobian with unit-norm columns is orthogonalised
// in a fixed order of preference (set-up, then θ, a, α, β per joint, then the d's, then the
// terms); a parameter whose column lies (almost) in the span of those before it is eliminated
// and the combination it forms is reported. The solve (Ceres, Levenberg–Marquardt) never sees a
// rank-deficient problem.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/progress.h"
#include "ramtk/core/rotation.h"
#include "ramtk/core/termination.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::calib {

// How parameter uncertainties are computed.
enum class CovarianceKind {
  kScaled,    // (JᵀJ)⁻¹ of the weighted Jacobian times the reduced χ² (the residual sets the scale)
  kSandwich,  // (JᵀJ)⁻¹·(Σ_poses J_iᵀ r_i r_iᵀ J_i)·(JᵀJ)⁻¹: robust to unequal and model-error residuals
  kNominal,   // (JᵀJ)⁻¹ with the stated σ as they are
};

// How the poses are split for held-out validation.
enum class HoldoutSplit {
  kRandom,  // k folds drawn at random (seeded)
  kBlocks,  // k contiguous blocks in file order: predicts regions (and times) not seen
};

struct RobotCalibrationOptions {
  // Identify the links (true) or only the set-up: tracker_from_base, the targets and the tool
  // rotation, the links as given (what `calib sensor-robot` does; used to carry a calibration to
  // another series).
  bool identify_links = true;
  // Offer β_i where the axes of joints i and i+1 are within this angle (deg) of parallel, also
  // when the robot file lists β_i as a structural zero (a DH file); the output file is then MDH.
  double parallel_axes_deg = 10.0;
  // Elimination: a parameter whose unit-norm column keeps less than this fraction outside the
  // span of the columns before it is not identifiable (structurally, at the nominal geometry).
  double structural_tolerance = 1e-6;
  // Below this fraction (but above the structural one) it is eliminated as not identifiable from
  // this pose set; its σ would exceed 1/fraction times the column's own resolution.
  double weak_tolerance = 1e-4;
  // Use the measured rotation of 6-D data (false: positions only).
  bool use_rotation = true;
  // σ of each measured coordinate (mm) and rotation component (deg) where the file gives none.
  // With estimate_sigmas they are only the start: after a first fit each kind's σ is set to its
  // residual RMS (variance components), so positions and rotations weigh by how well they fit.
  double position_sigma_mm = 0.02;
  double rotation_sigma_deg = 0.002;
  bool estimate_sigmas = true;
  // Robust loss on each pose's whitened residual; scale in σ units.
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale = 3.0;
  // Non-geometric terms offered (each kept only when the held-out RMS drops by min_term_gain):
  // cyclic errors Δθ_j = Σ_h s_jh·sin(h·q_j) + c_jh·cos(h·q_j), h = 1..cyclic_harmonics, and
  // compliance Δθ_j = k_j·τ_j(q) with τ_j the gravity torque from the robot file's masses.
  bool try_cyclic = true;
  int cyclic_harmonics = 2;
  bool try_compliance = true;
  double min_term_gain = 0.02;  // fraction of the held-out RMS
  // Coverage warnings: a joint that moved less than this (deg), targets spread (RMS about their
  // centroid) less than this fraction of the reach.
  double min_joint_range_deg = 30.0;
  double min_spread_fraction = 0.15;
  // Held-out validation: `folds` folds (≥ 2), split as named, seeded.
  int folds = 5;
  HoldoutSplit split = HoldoutSplit::kRandom;
  unsigned seed = 1;
  CovarianceKind covariance = CovarianceKind::kScaled;
  int max_iterations = 100;
  int num_threads = 2;
  ProgressCallback progress;  // stages: "setup", "links", "terms", "held-out"

  std::string Validate() const;  // "" if usable
};

// One unknown of the calibration and what became of it.
struct CalibrationUnknown {
  std::string name;  // "a2", "beta3", "base_rx", "target1_x", "tool_rz", "cyc_s1_j2", "compliance_j3"
  std::string unit;  // "mm", "deg", "deg/(kg·m)"
  // "identified", "not_identifiable" (structural), "weak" (not identifiable from these poses),
  // "fixed" (a structural zero of the robot file, or a link with identify_links false),
  // "not_kept" (a term that did not pay on held-out data).
  std::string status;
  double nominal = 0.0;  // value before (file units)
  double value = 0.0;    // value after (file units)
  double sigma = 0.0;    // 1σ (file units), 0 unless identified
  // For an eliminated unknown: the fraction of its column outside the others' span, and the
  // combination it forms ("acts as +1.000·d2 −0.998·d4").
  double independence = 1.0;
  std::string combination;
};

struct RobotCalibration {
  // The final model's links, fitted together with the terms kept (use them with the terms).
  kinematics::RobotChain chain;
  // The best links without any term (fitted before the terms were tried): the calibrated robot file
  // every other command reads, which knows no terms.
  kinematics::RobotChain links_only;
  Isometry3 tracker_from_base = Isometry3::Identity();
  std::vector<Vec3> targets_in_flange;  // mm
  std::optional<Mat3> flange_from_tool_rotation;  // 6-D data only
  // Non-geometric terms kept (empty when not): cyclic coefficients per joint [s_1 c_1 s_2 c_2 ...]
  // (rad), compliance per joint (rad per kg·mm of gravity torque).
  Eigen::MatrixXd cyclic;       // N × 2H
  Eigen::VectorXd compliance;   // N
  std::vector<CalibrationUnknown> unknowns;
  Eigen::MatrixXd covariance;   // of the identified unknowns, in the order of `identified` (mm, rad)
  std::vector<int> identified;  // indices into `unknowns`
};

// Residual statistics of one set of poses (positions only; mm).
struct ResidualStats {
  int poses = 0;
  double rms_per_coordinate_mm = 0.0;  // sqrt(mean over poses, targets and x,y,z of r²)
  double rms_3d_mm = 0.0;              // sqrt(mean |r|²)
  double max_3d_mm = 0.0;
  double rms_rotation_deg = 0.0;       // 6-D data: RMS rotation error angle
};

struct RobotCalibrationSummary {
  Termination termination = Termination::kNotRun;
  std::string message;
  int iterations = 0;
  int num_poses = 0;
  int num_targets = 0;
  bool used_rotation = false;
  double position_sigma_mm = 0.0;   // the σ the fit weighted by (estimated or given)
  double rotation_sigma_deg = 0.0;
  ResidualStats before;             // nominal links, set-up fitted
  ResidualStats after;              // calibrated, all poses
  ResidualStats held_out;           // k-fold, each pose predicted by the fit without it
  ResidualStats held_out_geometric; // the same with the links only (no terms)
  // Held-out RMS per coordinate predicted from the fit: sqrt(s² + mean trace(J C Jᵀ)/3).
  double predicted_held_out_mm = 0.0;
  double reduced_chi2 = 0.0;
  // Identifiability of the kept unknowns: the column-scaled Jacobian's condition number, the
  // observability index O1 = (Π σ_i)^(1/p)/√m and the noise amplification index σ_min²/σ_max.
  double condition_number = 0.0;
  double observability_index = 0.0;
  double noise_amplification_index = 0.0;
  int num_identified = 0;
  int num_eliminated = 0;
  // Pose-set coverage: the range each joint moved over (deg) and the RMS distance of the measured
  // targets from their centroid (mm) beside the robot's reach (Σ|a| + |d|). A pose set that spans
  // little of either fits well and predicts the rest of the workspace poorly: a warning says so.
  std::vector<double> joint_range_deg;
  double workspace_spread_mm = 0.0;
  double reach_mm = 0.0;
  std::vector<std::string> terms_kept;  // "cyclic", "compliance"
  std::vector<std::string> warnings;
  std::vector<Vec3> residuals_before;   // per pose, first target (mm, tracker frame)
  std::vector<Vec3> residuals_after;
  std::vector<Vec3> residuals_held_out;

  std::string BriefReport() const;
};

// Calibrates. InputError for unusable data (fewer poses than unknowns, joint counts that do not
// match the robot); kNoResult when nothing is identifiable.
RobotCalibration CalibrateRobot(const kinematics::RobotChain& nominal, const kinematics::TrackerMeasurements& data,
                                const RobotCalibrationOptions& options, RobotCalibrationSummary* summary);

// Predicted measurement of target k (mm, tracker frame) at controller joints q (rad).
Vec3 PredictTarget(const RobotCalibration& calibration, const Eigen::VectorXd& q_controller, int target);
// Predicted tool rotation in the tracker frame (6-D calibrations).
Mat3 PredictToolRotation(const RobotCalibration& calibration, const Eigen::VectorXd& q_controller);
// Residual statistics of a calibration on a set of poses.
ResidualStats EvaluateCalibration(const RobotCalibration& calibration, const kinematics::TrackerMeasurements& data,
                                  std::vector<Vec3>* residuals = nullptr);

}  // namespace ramtk::calib
