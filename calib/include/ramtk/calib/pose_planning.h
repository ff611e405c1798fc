#pragma once
// Pose planning for the robot calibration (robot_calibration.h): from a set of candidate joint
// configurations, choose the N at which to measure so that the identifiable unknowns are
// determined best.
//
// The unknowns and their identifiability are those CalibrateRobot would find with every candidate
// measured at the nominal geometry (robot_identifiability.h; links, tracker_from_base, targets,
// the tool rotation for 6-D data; no non-geometric terms). The choice is D-optimal: maximise
// log det(JᵀJ) of the whitened Jacobian's identifiable columns (the inverse of the parameter
// covariance, up to σ²). Greedy: each step adds the candidate with the largest
// log det(I + J_c A⁻¹ J_cᵀ) (matrix determinant lemma, a rank-3 or rank-6 update), starting from a
// tiny ridge on the column-normalised information so that the first steps add rank; then
// exchange passes (remove each chosen pose in turn, add the best candidate instead when log det
// grows) until none improves.
//
// With isotropic noise JᵀJ does not depend on tracker_from_base (a rotation of every pose's rows
// and a fixed translation): only the targets' positions in the flange matter for the choice.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::calib {

struct PosePlanningOptions {
  // Poses to choose.
  int num_poses = 50;
  // Measurement kind: the tool's 6-D pose (one target, its origin, plus rotation), or
  // num_targets points on the tool.
  bool six_d = false;
  int num_targets = 1;
  // Approximate set-up. Targets in the flange (mm); empty: DefaultTargets(num_targets) (one
  // target for 6-D).
  std::vector<Vec3> targets_in_flange;
  Isometry3 tracker_from_base = DefaultTrackerFromBase();
  // Measurement noise: σ per coordinate (mm) and per rotation component (deg).
  double position_sigma_mm = 0.02;
  double rotation_sigma_deg = 0.002;
  // Identifiability, as in RobotCalibrationOptions.
  double parallel_axes_deg = 10.0;
  double structural_tolerance = 1e-6;
  double weak_tolerance = 1e-4;
  // Exchange passes after the greedy choice (0: greedy only); each pass tries every chosen pose.
  int exchange_passes = 3;
  // Random sets of num_poses drawn from the same candidates for the comparison in the summary.
  int random_draws = 5;
  std::uint64_t seed = 1;  // random draws (and SampleJointConfigurations)

  std::string Validate() const;  // "" if usable
  static Isometry3 DefaultTrackerFromBase();  // the simulator's: 2.6 m from the base
  // One target: (20, -10, 120) mm; K targets: on a circle of radius 80 mm about the flange axis
  // at 100 mm, plus the first on the axis at 150 mm.
  static std::vector<Vec3> DefaultTargets(int count);
};

// How well a set of poses determines the identifiable unknowns.
struct PoseSetQuality {
  int poses = 0;
  bool full_rank = false;
  double log_det = 0.0;  // log det(JᵀJ), whitened Jacobian, internal units (mm, rad)
  // Predicted 1σ of every identifiable unknown, sqrt(diag((JᵀJ)⁻¹)) with the stated noise, in
  // file units (mm, deg); infinity when not full rank.
  Eigen::VectorXd sigma;
  double condition_number = 0.0;  // of the column-scaled Jacobian
  double observability_index = 0.0;
  double noise_amplification_index = 0.0;
};

struct PosePlanningSummary {
  int num_candidates = 0;
  int rows_per_pose = 0;
  // The identifiable unknowns (names as in CalibrationUnknown, units "mm"/"deg") and the
  // eliminated ones with the combination they act as.
  std::vector<std::string> names;
  std::vector<std::string> units;
  std::vector<std::string> eliminated;  // "d3: not_identifiable, acts as +1.000·d2"
  int greedy_steps = 0;
  int exchanges = 0;   // swaps accepted
  int exchange_passes = 0;
  PoseSetQuality planned;
  // Random sets: σ as the RMS over the draws, log det and indices as means (full-rank draws).
  PoseSetQuality random;
  int random_full_rank = 0;  // of random_draws

  // The predicted-σ table, planned against random, one unknown a line, and the indices.
  std::string Table() const;
};

// Plans over candidate joint configurations (controller joints, rad). Holds the whitened
// Jacobian of every candidate at the nominal geometry.
class PosePlanner {
 public:
  // InputError when a candidate has the wrong joint count or too few candidates are given.
  PosePlanner(const kinematics::RobotChain& nominal, std::vector<Eigen::VectorXd> candidates,
              const PosePlanningOptions& options);

  // Indices into the candidates, ascending (the candidates' order). InputError when num_poses
  // exceeds the candidates or gives fewer rows than identifiable unknowns.
  std::vector<int> Plan(PosePlanningSummary* summary = nullptr) const;
  // Quality of any set of candidate indices (repeats allowed).
  PoseSetQuality Evaluate(const std::vector<int>& poses) const;
  // num_poses random distinct indices (seeded).
  std::vector<int> RandomSet(int num_poses, std::uint64_t seed) const;

  int num_candidates() const { return static_cast<int>(candidates_.size()); }
  int num_unknowns() const { return static_cast<int>(jacobian_.cols()); }
  const std::vector<Eigen::VectorXd>& candidates() const { return candidates_; }

 private:
  PosePlanningOptions options_;
  std::vector<Eigen::VectorXd> candidates_;
  int rows_ = 0;                 // per pose
  Eigen::MatrixXd jacobian_;     // candidates·rows × identifiable unknowns, whitened
  Eigen::VectorXd file_scale_;   // file units per internal unit, per identifiable unknown
  Eigen::VectorXd column_scale_; // 1 / RMS per-pose column norm (normalisation for the ridge)
  PosePlanningSummary base_;     // names, units, eliminated
};

// Candidate joint configurations (controller joints, rad):
// from a tracker file read with `format` (the measured columns are read but not used);
// or, when `format` is null and the file's header has no x/x1 column, a plain CSV whose q1..qN
// columns (degrees) are the joints (other columns ignored; the output of `ramtk plan poses`).
std::vector<Eigen::VectorXd> ReadCandidateJoints(const std::string& path, const kinematics::TrackerFormat* format,
                                                 int num_joints);
// count configurations uniform in [-limit_j, +limit_j] (deg; one value for every joint or one
// per joint), seeded.
std::vector<Eigen::VectorXd> SampleJointConfigurations(int count, const std::vector<double>& limits_deg,
                                                       int num_joints, std::uint64_t seed);
// The chosen joints as CSV: pose,q1..qN in degrees.
std::string FormatJointCsv(const std::vector<Eigen::VectorXd>& joints_rad, const std::string& comment = "");

}  // namespace ramtk::calib
