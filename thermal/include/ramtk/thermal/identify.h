#pragma once
// Identification of the thermal parameter drift ΔX (thesis eqs. 3-5 to 3-10).
//
// For pose i the ball centre moves by Y_i = P_swarm,i − P_scool,i = M_i · ΔX (eq. 3-7), with
// M_i = R_b^s · ∂(T_e^b · P_e)/∂X (3×30). Stacking the poses gives Y = A · ΔX (eq. 3-8), solved
// by SVD, ΔX = V S⁻¹ Uᵀ Y (eqs. 3-9, 3-10), for any chosen subset of the 30 parameters (the
// others are held at zero drift). Columns are equilibrated (scaled to unit norm) before the SVD
// so that mm and rad columns compare; singular values and condition numbers are reported for the
// equilibrated matrix.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/core/termination.h"
#include "ramtk/kinematics/robot_model.h"
#include "ramtk/thermal/cycles.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::thermal {

using kinematics::ParamVector;
using kinematics::RobotModel;

struct IdentificationOptions {
  // Parameters to identify (ParamVector indices). Empty: every non-structural-zero parameter.
  std::vector<int> params;
  // Positions (0-based, in CycleSeries::ids order) of the poses to use. Empty: all poses.
  std::vector<int> poses;
  // Singular values below singular_value_rtol·σ_max are dropped from the pseudo-inverse (0 keeps
  // every non-zero one, as the thesis's plain V S⁻¹ Uᵀ).
  double singular_value_rtol = 1e-12;
  // Rank threshold (relative to the largest |R_ii|) of the column-pivoted QR that names the
  // parameters not identifiable given the others, and of the null-space report.
  double rank_rtol = 1e-8;
  // Covariance of each difference Y (mm²), [column of Y (cycle)][pose position over every pose of
  // the model] (CycleSeries::DifferenceCovariances). Given, each column is solved by generalised
  // least squares (every 3-row block whitened by its covariance) instead of the plain eq. (3-10).
  // Empty: unweighted.
  std::vector<std::vector<Mat3>> difference_covariance_mm2;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// A parameter combination the poses cannot see: Σ coefficient_k · Δp_k has no effect on Y.
struct NullCombination {
  std::vector<int> params;           // parameter indices with a non-negligible coefficient
  std::vector<double> coefficients;  // unit vector over the equilibrated columns
};

struct IdentificationSummary {
  Termination termination = Termination::kNotRun;  // kSuccess, or kPartial when parameters were dropped
  std::string message = "not run";                 // "solved", "rank deficient (k dropped)"
  int iterations = 0;                              // 1 for the direct solve
  std::vector<int> params;                         // identified parameters
  int num_poses = 0;
  int num_equations = 0;
  Eigen::VectorXd singular_values;    // equilibrated A, descending
  double condition_number = 0.0;      // σ_max/σ_min of the equilibrated A (inf if singular)
  int rank = 0;                       // column-pivoted QR rank
  std::vector<int> dependent_params;  // params QR pivoted behind the rank (not identifiable)
  std::vector<NullCombination> null_space;
  int num_cycles = 0;              // columns of Y solved
  double initial_cost = 0.0;       // ½‖Y‖² over all cycles, mm²
  double final_cost = 0.0;         // ½‖Y − AΔX‖², mm²
  double rms_residual_mm = 0.0;    // per coordinate, over all cycles
  double worst_residual_mm = 0.0;  // largest |coordinate residual|
  int outliers = 0;                // not rejected: always 0 (plain least squares)
  bool weighted = false;           // each difference weighted by its covariance
  // Covariance of ΔX over `params` (mm, rad; params order), one matrix per column of Y (cycle):
  // covariance_scale · (Aᵀ W A)⁻¹ with W = I unweighted, or the inverse difference covariances
  // when weighted (the same truncated SVD as the solve). Empty when not computed.
  std::vector<Eigen::MatrixXd> covariance;
  int residual_dof = 0;  // Σ over the columns of Y that are not identically zero of (equations − params)
  // Residual χ² / residual_dof: unweighted, the residual variance per coordinate s² (mm²);
  // weighted, the reduced χ² of the whitened residual (dimensionless). NaN when residual_dof is 0.
  double reduced_chi2 = 0.0;
  // Factor on (Aᵀ W A)⁻¹: unweighted s² (the plain scaling, the noise is estimated from the
  // residual); weighted max(1, reduced χ²) (the centre covariances are a lower bound, inflated
  // when the residual is larger, never shrunk).
  double covariance_scale = 0.0;
  std::string covariance_scaling;  // one sentence saying which scaling was used, with its value
  // Standard deviation of params[k] in column c (mm or rad); NaN without a covariance.
  double Sigma(int k, int c) const;

  std::string BriefReport() const;
};

// ---------------------------------------------------------------- identifiability guard
// Before solving, the identification matrix A of the chosen parameters and poses (unweighted: the
// geometry of the poses) is scaled column by column to unit norm, so that mm and rad columns
// compare and the condition number measures how nearly one parameter's effect is a combination
// of the others' (it is 1 for orthogonal columns). A set whose condition number exceeds
// max_condition is not identifiable: the right singular vector of the smallest singular value is
// the combination of parameters the poses cannot see, and its noise is amplified by the condition
// number relative to the best-determined combination.

class DriftModel;

struct IdentifiabilityOptions {
  // Largest accepted condition number σ_max/σ_min of the column-scaled identification matrix.
  double max_condition = 1e3;
  // A parameter belongs to the unobservable combination when its component in the smallest
  // right singular vector (unit length over the scaled columns) exceeds this in magnitude.
  double min_component = 0.2;
  // false: only check. true: drop one parameter of each unobservable combination (the one whose
  // removal leaves the best-conditioned set) until the set passes.
  bool reduce = false;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// A combination Σ coefficient_k · Δp_k (over column-scaled parameters) the poses barely see.
struct UnobservableCombination {
  std::vector<int> params;           // parameters with |component| > min_component, by |component| descending
  std::vector<double> coefficients;  // their components in the smallest right singular vector
  double condition_number = 0.0;     // of the set in which it was found
  // "joints 1 and 5 axes parallel at these poses (largest angle 0.021 deg)" when the named
  // parameters are d or θ of joints whose axes stay within 1° of parallel over the poses; else "".
  std::string cause;
  // "+0.707·d1 -0.707·d5"
  std::string Describe() const;
};

struct IdentifiabilitySummary {
  Termination termination = Termination::kNotRun;  // kSuccess, kPartial (parameters dropped), kNoResult (refused)
  std::string message = "not run";                 // "identifiable", "identifiable after dropping d5", the refusal
  std::vector<int> requested;                      // the set asked for
  std::vector<int> params;                         // the set that passed (after dropping), or the refused set
  std::vector<int> dropped;                        // in the order they were dropped
  std::vector<UnobservableCombination> combinations;  // the one behind each drop, or the refused one
  Eigen::VectorXd singular_values;                 // column-scaled A of `params`, descending
  double condition_number = 0.0;                   // of `params` (inf if singular)
  double max_condition = 0.0;                      // the limit applied
  int num_poses = 0;
  bool Identifiable() const { return termination == Termination::kSuccess || termination == Termination::kPartial; }
  // One line: condition number against the limit, and what was dropped or why it was refused.
  std::string BriefReport() const;
};

// A pose set too small for the parameters (fewer equations than parameters) is an InputError, as
// in DriftModel::Solve. params empty: every free parameter; poses empty: every pose.
IdentifiabilitySummary CheckIdentifiability(const DriftModel& drift_model, const std::vector<int>& params,
                                            const std::vector<int>& poses, const IdentifiabilityOptions& options);

// The stacked sensitivity A (eq. 3-8, all 30 columns) of a fixed pose set, and solvers over it.
class DriftModel {
 public:
  // `taught` are the poses' controller joints (rad).
  DriftModel(const RobotModel& model, const ThermalSetup& setup, const std::vector<JointVector>& taught);

  int NumPoses() const { return static_cast<int>(a_full_.rows() / 3); }
  // 3·poses × 30, in the sensor frame (mm per mm / per rad).
  const Eigen::MatrixXd& FullSensitivity() const { return a_full_; }
  const RobotModel& model() const { return model_; }
  // The poses' controller joints (rad), as given.
  const std::vector<JointVector>& taught() const { return taught_; }

  // Solves ΔX for every column of `y` (3·|options.poses| × n, the differences of those poses).
  // Returns 30 × n with zeros outside options.params. InputError when the poses give fewer
  // equations than parameters.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& y, const IdentificationOptions& options,
                        IdentificationSummary* summary = nullptr) const;

  // Covariance (params × params, mm / rad units) of ΔX identified from the poses of `options`
  // when every coordinate of Y has standard deviation sigma_y_mm: σ²(AᵀA)⁻¹ (pseudo-inverse if
  // singular).
  Eigen::MatrixXd Covariance(const IdentificationOptions& options, double sigma_y_mm) const;

  // Covariance (params × params, mm / rad units) of the weighted ΔX of each cycle c:
  // (Aᵀ C_c⁻¹ A)⁻¹ with C_c block-diagonal over the poses of `options`, its blocks
  // options.difference_covariance_mm2[c] (pseudo-inverse if singular). One matrix per cycle;
  // InputError if the covariances are absent, lack a pose or are not positive definite.
  std::vector<Eigen::MatrixXd> WeightedCovariances(const IdentificationOptions& options) const;

 private:
  RobotModel model_;
  std::vector<JointVector> taught_;
  Eigen::MatrixXd a_full_;
};

// Identifies ΔX for every cycle of `ball` against its reference cycle (column 0 ≈ 0).
// Returns 30 × cycles.
Eigen::MatrixXd IdentifyCycles(const RobotModel& model, const ThermalSetup& setup, const CycleSeries& ball,
                               const IdentificationOptions& options, IdentificationSummary* summary = nullptr);

// Greedy D-optimal pose selection: `count` pose positions out of the model's poses that maximise
// log det(AᵀA) of the equilibrated columns `params` (for the 6-pose production budget).
// σ_Y per coordinate estimated from an identification's residual: its RMS corrected for the
// identified parameters' degrees of freedom, rms·sqrt(n / (n − p)) with n the equations per cycle.
// What DriftModel::Covariance needs when the noise is not known beforehand.
double ResidualSigmaY(const IdentificationSummary& summary);

std::vector<int> SelectPoses(const DriftModel& drift_model, const std::vector<int>& params, int count);

// Parameter names ("d4", "alpha3") from a comma list, or "traditional" / "all" / "free".
// InputError naming `field` on an unknown name.
std::vector<int> ParseParamList(const std::string& text, const RobotModel& model, const std::string& field);
// Non-zero length parameters of the model (d_i, a_i with a non-zero nominal value): the
// traditional compensation set (thesis §3.2; d1 d4 d6 a1 a2 a3 for the KR150).
std::vector<int> TraditionalParams(const RobotModel& model);
std::string ParamListToString(const std::vector<int>& params);
// Value of parameter `index` in file units: mm for lengths, degrees for angles.
double ToFileUnits(int index, double value);
// Standard deviation of parameter `index` in file units: mm for lengths, degrees for angles.
double SigmaToFileUnits(int index, double sigma);

}  // namespace ramtk::thermal
