#pragma once
// Hand-eye for a camera on the flange, refined by least squares on SE(3) with the covariance of
// the result (mrcal's rule: the uncertainty is an output). Starts from CalibrateCameraOnFlange.
//
// Unknowns: X = flange_from_camera and Z = base_from_board. Per pose i the model predicts
//   camera_from_board_i = X⁻¹ · base_from_flange_i⁻¹ · Z
// and the residuals are the measured-vs-predicted rotation (rotation vector of R_meas · R_predᵀ,
// i.e. in the camera frame) over σ_rot and translation difference over σ_t. Covariance of X from
// (JᵀJ)⁻¹ of the whitened problem, in X's tangent space: a rotation vector applied on the left
// (in the flange frame, rad) and the translation (mm).
#include <Eigen/Core>
#include <vector>

#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange.h"

namespace ramtk::calib {

struct EyeInHandRefineOptions {
  // Noise of one camera_from_board measurement: rotation per axis (deg) and translation per axis
  // (mm). 0: estimated from the residuals of a first fit (each from its share of the degrees of
  // freedom, 3n − 6 apiece), then the problem is solved again with those weights.
  double sigma_deg = 0.0;
  double sigma_mm = 0.0;
  int max_iterations = 100;
  // With no noise given and every pose carrying camera_from_board_covariance (poses from images),
  // each pose is weighed by its own covariance; false: one noise level for all.
  bool use_pose_covariance = true;
  // Returns "" or what is wrong.
  std::string Validate() const;
};

struct EyeInHandRefinement {
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // Ceres costs (0.5 Σ whitened²)
  double sigma_deg = 0.0, sigma_mm = 0.0;       // the noise used for the weights and the covariance
  bool noise_estimated = false;                 // true when it came from the residuals
  // Each pose weighed by its own covariance. sigma_deg / sigma_mm are then the residuals' RMS per
  // axis, and the covariance below is scaled by max(1, variance_factor).
  bool pose_covariance = false;
  double variance_factor = 1.0;  // χ² / (6n − 12) of the whitened residuals (≈ 1 when the weights are right)
  // Noise per axis added to every pose's own covariance: what the residuals of a first, equally
  // weighted fit show beyond the poses' mean own variance (the robot's pose error; 0 when the
  // images explain the residuals).
  double extra_noise_deg = 0.0, extra_noise_mm = 0.0;
  // Covariance of flange_from_camera (stand case: camera_from_base): [rotation vector (rad, applied
  // on the left); translation (mm)].
  Eigen::Matrix<double, 6, 6> flange_from_camera_covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Vec3 rotation_sigma_deg = Vec3::Zero();    // sqrt of the diagonal, deg
  Vec3 translation_sigma_mm = Vec3::Zero();  // sqrt of the diagonal, mm
};

// Refines `initial` (its flange_from_camera and base_from_board) over `obs`; the result carries
// the refined poses and residuals. InputError (field "poses") for fewer than 3 poses or
// non-finite input, (field from the options) for bad options.
EyeInHandResult RefineCameraOnFlange(const std::vector<FlangeCameraObservation>& obs, const EyeInHandResult& initial,
                                     const EyeInHandRefineOptions& options, EyeInHandRefinement* refinement);

// The same for a camera on a stand (AX = ZB): unknowns C = camera_from_base and
// B = flange_from_board, camera_from_board_i = C · base_from_flange_i · B, starting from
// CalibrateStandCamera. The refinement's covariance is then that of camera_from_base: rotation
// vector applied on the left (in the camera frame, rad), translation (mm); the fields keep the
// names of the flange case.
HandEyeResult RefineStandCamera(const std::vector<StandCameraObservation>& obs, const HandEyeResult& initial,
                                const EyeInHandRefineOptions& options, EyeInHandRefinement* refinement);

// Camera on a stand in one call: OpenCV's closed form (options.method; options.refine is ignored),
// then RefineStandCamera. The summary describes the refined result (refined = true).
HandEyeResult CalibrateStandCameraWithCovariance(const std::vector<StandCameraObservation>& obs,
                                                 const HandEyeOptions& options,
                                                 const EyeInHandRefineOptions& refine_options,
                                                 HandEyeSummary* summary = nullptr,
                                                 EyeInHandRefinement* refinement = nullptr);

}  // namespace ramtk::calib
