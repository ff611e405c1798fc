#pragma once
// Sensor-to-robot calibration (thesis §3.3): from the ball centre measured by a fixed sensor at
// several robot poses, find sensor_from_base (T_b^s) and ball_in_flange (P_e) of eq. (3-1):
//   ball_in_sensor_i = sensor_from_base · base_from_flange(q_i) · ball_in_flange.
//
// Two estimators:
//  * CalibrateSensorRobotThesis: the thesis method as printed, eqs. (3-11)..(3-19): difference
//    equations of every pose against the first, B'·ΔK = b' with ΔK = [R_sᵀ (row-major), P_e], an
//    orthogonality penalty M·Σf_i², Levenberg–Marquardt, then t_s averaged over the poses. Kept
//    as the reference.
//  * CalibrateSensorRobot: a closed-form linear solution (every pose, rotation projected onto
//    SO(3)) refined by a Ceres fit of all 9 unknowns with the rotation on the SO(3) manifold and
//    a robust loss, plus the covariance of the estimate from the Jacobian.
// Both check the pose set first (DiagnosePoseSet) and refuse sets that cannot determine the
// unknowns.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/core/termination.h"
#include "ramtk/kinematics/measurements_io.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::calib {

// One robot pose and the ball centre the sensor measured there.
struct BallObservation {
  kinematics::JointVector q_controller = kinematics::JointVector::Zero();  // controller joints, rad
  Vec3 ball_in_sensor = Vec3::Zero();                                      // mm
  int pose = 0;  // the `pose` column of the measurement file (for reports)
  int line = 0;  // 1-based line of the measurement file (0 if not from a file)
  // Covariance of ball_in_sensor (mm², from the scan's sphere fit: the cov_xx..cov_yz columns
  // of the measurement file); has_covariance false when the file has none.
  Mat3 covariance_mm2 = Mat3::Zero();
  bool has_covariance = false;
};

// Ball observations from a robot measurement set (kind kBall). Every row becomes one
// observation, with its centre covariance when the set has the cov_xx..cov_yz columns.
// InputError if the set holds monitoring points, a value is not finite or a covariance is not
// positive definite.
std::vector<BallObservation> BallObservationsFromMeasurements(const kinematics::RobotMeasurementSet& set,
                                                              const std::string& path);

// The estimate. The 9-vector of unknowns is ordered [φ, t_s, P_e]: φ is a small rotation vector
// (rad) applied on the left, R_s = Exp(φ)·R̂_s (so it is expressed in the sensor frame), t_s the
// translation of sensor_from_base (mm), P_e = ball_in_flange (mm).
struct SensorRobotCalibration {
  // For the thesis method the linear part is the LM solution R_s as found (near-orthonormal, not
  // projected); `orthonormality_error` says how far from a rotation it is.
  Isometry3 sensor_from_base = Isometry3::Identity();
  Vec3 ball_in_flange = Vec3::Zero();  // mm
  double orthonormality_error = 0.0;   // max |R_sᵀR_s − I| and |det − 1|
  // Covariance of [φ (rad), t_s (mm), P_e (mm)], scaled by the residual variance; zero and
  // has_covariance = false when not computed (thesis method).
  Eigen::Matrix<double, 9, 9> covariance = Eigen::Matrix<double, 9, 9>::Zero();
  bool has_covariance = false;
  // Per observation, in input order: measured − predicted ball centre in the sensor frame (mm).
  std::vector<Vec3> residuals_mm;
  double rms_mm = 0.0;           // sqrt(mean |residual|²)
  double max_residual_mm = 0.0;  // largest |residual|
  // Standard deviations from the covariance: rotation (arc-seconds, per axis of φ), translation
  // and ball (mm, per axis).
  Vec3 RotationStdArcsec() const;
  Vec3 TranslationStdMm() const;
  Vec3 BallStdMm() const;
};

// Limits on the pose set. A set below an error limit is refused with an InputError; a set below
// a warning limit is solved and the warning goes to the log and the Summary.
struct PoseSetCheckOptions {
  // Fewest poses accepted. The thesis (§3.3) needs 3n ≥ 12 difference equations, so 5 poses.
  int min_poses = 5;
  // Largest angle (deg) between any two flange orientations: below the error limit the ball
  // offset cannot be told from the sensor translation.
  double min_rotation_spread_deg = 1.0;
  double warn_rotation_spread_deg = 15.0;
  // Condition number of the column-scaled 9-unknown Jacobian (see PoseSetDiagnostics). The
  // default simulated 9-pose set (tilts up to 35 deg) gives about 8; tilts of 5 deg about 60.
  double max_condition_number = 1e4;
  double warn_condition_number = 30.0;

  std::string Validate() const;  // empty if valid
};

struct PoseSetDiagnostics {
  int num_poses = 0;
  double rotation_spread_deg = 0.0;  // largest angle between two flange orientations
  // Smallest rotation spread about any axis (deg): the smallest singular value of the stacked
  // (R_i − R̄) turned into an angle; small when every rotation is about one axis.
  double min_axis_spread_deg = 0.0;
  // Condition number of the Jacobian of the 9 unknowns with the rotation taken about the
  // centroid of the ball positions and scaled by their RMS radius (so all columns are in mm and
  // the number does not depend on the frames). Infinity if singular.
  double condition_number = 0.0;
  std::vector<std::string> warnings;  // human-readable
  std::string error;                  // non-empty when the set must be refused
};

// Checks the set. ball_in_flange is an estimate (the condition number depends on it mildly).
PoseSetDiagnostics DiagnosePoseSet(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                                   const Vec3& ball_in_flange, const PoseSetCheckOptions& options);

// The words the result file uses for a sensor-robot fit's end (docs/formats.md): kSuccess
// "converged", kNoConvergence "no_convergence", anything else "failed".
const char* SensorRobotTerminationText(Termination t);

struct SensorRobotSummary {
  std::string method;                               // "thesis" or "manifold"
  Termination termination = Termination::kFailure;  // kSuccess, kNoConvergence or kFailure
  int iterations = 0;
  double initial_cost = 0.0;  // ½Σ|r|² of the solver's own objective at the start
  double final_cost = 0.0;
  double rms_mm = 0.0;
  double max_residual_mm = 0.0;
  int worst_pose = -1;                // index into the observations of the largest residual
  std::vector<int> outliers;          // observations whose residual exceeds the outlier limit
  PoseSetDiagnostics diagnostics;     // of the pose set
  std::vector<std::string> warnings;  // diagnostics warnings and solver remarks
  // Each centre's residual was weighted by its covariance (manifold method, every observation
  // has one and SensorRobotOptions::use_covariance).
  bool weighted = false;
  // Block hold-out (SensorRobotOptions::jackknife_blocks): RMS of |residual| of the left-out poses
  // (0 when not run), and sqrt(trace C_jackknife / trace C_residual-scaled): how much the model
  // error widens the σ the residual alone gives.
  double held_out_rms_mm = 0.0;
  double jackknife_ratio = 0.0;
  std::string covariance_source;  // "residual-scaled" or "block jackknife"

  std::string BriefReport() const;  // one line
};

// The thesis method, eqs. (3-11)..(3-19).
struct ThesisCalibrationOptions {
  // Penalty factor M of eq. (3-18) on the six orthogonality conditions (3-17). The thesis gives
  // no value; B' has entries of the size of the pose differences (hundreds of mm), so M must be
  // large against Σ|ΔP|² to keep R_s near-orthonormal.
  double penalty_factor = 1e8;
  // Levenberg–Marquardt iterations and stopping tolerances (Ceres).
  int max_iterations = 500;
  double function_tolerance = 1e-15;
  double parameter_tolerance = 1e-14;
  PoseSetCheckOptions checks;

  std::string Validate() const;
};

SensorRobotCalibration CalibrateSensorRobotThesis(const kinematics::RobotModel& model,
                                                  const std::vector<BallObservation>& obs,
                                                  const ThesisCalibrationOptions& options,
                                                  SensorRobotSummary* summary = nullptr);

enum class RobustLoss { kNone, kHuber, kCauchy };

// The closed-form + manifold estimator.
struct SensorRobotOptions {
  // Robust loss on each pose's 3-D residual and its scale (mm). Residuals well inside the scale
  // are plain least squares; Huber down-weights a pose beyond it linearly.
  RobustLoss loss = RobustLoss::kHuber;
  double loss_scale_mm = 0.1;
  // A pose is listed as an outlier when |residual| exceeds this many times the median |residual|
  // (for Gaussian noise the median is 1.54σ, so 4× is beyond 6σ).
  double outlier_factor = 4.0;
  int max_iterations = 100;
  double function_tolerance = 1e-15;
  double parameter_tolerance = 1e-14;
  double gradient_tolerance = 1e-16;
  // Compute the covariance (ceres::Covariance, scaled by the residual variance Σ|r|²/(3n − 9);
  // weighted: of the weighted residuals).
  bool compute_covariance = true;
  // Weight each centre's residual by the inverse of its covariance when every observation has
  // one (generalised least squares). The weights are normalised by the mean variance so that
  // loss_scale_mm and the residuals keep their mm meaning.
  bool use_covariance = true;
  // Robot repeatability σ per axis (mm), added as σ²·I to every centre's covariance when
  // weighting: it moves the ball but is not in the scan's covariance.
  double robot_noise_mm = 0.0;
  // Held-out check and honest σ: the poses in input order are cut into this many contiguous
  // blocks, each left out in turn and predicted by the fit of the others (SensorRobotSummary::
  // held_out_rms_mm). The spread of those fits, (K−1)/K·Σ(θ_k − θ̄)(θ_k − θ̄)ᵀ (delete-a-block
  // jackknife), holds the error of the robot model, which differs from one region of the
  // workspace to another and which the residual-scaled covariance misses; the reported covariance
  // is the jackknife's when it is clearly the larger (trace above twice the residual-scaled one).
  // 0 or 1: off. Needs ≥ 3 poses per block.
  int jackknife_blocks = 10;
  PoseSetCheckOptions checks;

  std::string Validate() const;
};

SensorRobotCalibration CalibrateSensorRobot(const kinematics::RobotModel& model,
                                            const std::vector<BallObservation>& obs,
                                            const SensorRobotOptions& options = {},
                                            SensorRobotSummary* summary = nullptr);

// The closed-form starting point alone: the linear least-squares problem
//   R_sᵀ·P_si − R_i·P_e − u = t_i  (u = R_sᵀ t_s; 15 unknowns, every pose),
// R_sᵀ projected onto SO(3) by SVD, then P_e and t_s re-solved linearly with R_s fixed.
SensorRobotCalibration SolveSensorRobotLinear(const kinematics::RobotModel& model,
                                              const std::vector<BallObservation>& obs);

// Predicted ball centre in the sensor frame.
Vec3 PredictBallInSensor(const kinematics::RobotModel& model, const Isometry3& sensor_from_base,
                         const Vec3& ball_in_flange, const kinematics::JointVector& q_controller);

}  // namespace ramtk::calib
