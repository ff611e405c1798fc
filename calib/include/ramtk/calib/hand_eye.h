#pragma once
// Robot-world / hand-eye calibration for a fixed camera that sees a board carried by the robot
// (camera on a stand), through OpenCV's cv::calibrateRobotWorldHandEye (Shah 2013 or Li 2010).
//
// Per pose i the camera measures camera_from_board_i (e.g. cv::solvePnP on a detected board):
//   camera_from_board_i = camera_from_base · base_from_flange(q_i) · flange_from_board.
// OpenCV's equation is ᶜT_w · ʷT_b = ᶜT_g · ᵍT_b; with OpenCV's "world" = our board, its
// "base" = our flange and its "gripper" = our robot base, its outputs are board_from_flange and
// camera_from_base. camera_from_base plays the role of sensor_from_base of §3.3.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/calib/board.h"
#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::calib {

struct BoardPoseObservation {
  kinematics::JointVector q_controller = kinematics::JointVector::Zero();  // rad
  Isometry3 camera_from_board = Isometry3::Identity();                     // mm
};

enum class HandEyeMethod { kShah, kLi };

struct HandEyeOptions {
  HandEyeMethod method = HandEyeMethod::kShah;
  int min_poses = 3;  // OpenCV needs at least 3
  // Refine OpenCV's closed form by least squares on SE(3) (RefineStandCamera, both rotations on
  // Ceres's quaternion manifold; the rotation and translation residuals weighted by their noise,
  // estimated from a first fit's residuals).
  bool refine = true;

  std::string Validate() const;
};

struct HandEyeResult {
  Isometry3 camera_from_base = Isometry3::Identity();
  Isometry3 flange_from_board = Isometry3::Identity();
  // Per pose: measured vs predicted camera_from_board (rotation angle in rad, translation in mm).
  std::vector<double> rotation_residual_rad;
  std::vector<double> translation_residual_mm;
};

struct HandEyeSummary {
  std::string method;
  bool refined = false;
  int iterations = 0;         // Ceres iterations of the refinement (0 if not refined)
  double initial_cost = 0.0;  // refinement cost before / after (½Σ|r|², mm²)
  double final_cost = 0.0;
  int num_poses = 0;
  double rms_rotation_deg = 0.0;
  double rms_translation_mm = 0.0;
  double worst_translation_mm = 0.0;
  int worst_pose = -1;

  std::string BriefReport() const;
};

// camera_from_board from a board detection and the camera's intrinsics (cv::solvePnP, iterative
// Levenberg–Marquardt on the reprojection error). False if the detection has < 4 points or the
// solver fails.
bool CameraFromBoard(const BoardDetection& detection, const cv::Matx33d& camera_matrix,
                     const std::vector<double>& distortion, Isometry3* camera_from_board);

// One pose of a hand-eye session, either set-up: the controller's flange pose and the camera's
// measured board pose.
struct FlangePoseObservation {
  Isometry3 base_from_flange = Isometry3::Identity();   // mm, from the controller (or FK of its joints)
  Isometry3 camera_from_board = Isometry3::Identity();  // mm, e.g. cv::solvePnP on a detected board
  // Covariance of camera_from_board in [ω (rad, applied on the left, camera frame); t (mm)]
  // (board_pose.h); zero when unknown. When every pose has one, the SE(3) refinement weighs each
  // pose by it instead of one noise level for all.
  Eigen::Matrix<double, 6, 6> camera_from_board_covariance = Eigen::Matrix<double, 6, 6>::Zero();
};
// The same from flange poses given directly (the controller's base_from_flange, no robot model).
using StandCameraObservation = FlangePoseObservation;
HandEyeResult CalibrateStandCamera(const std::vector<StandCameraObservation>& obs, const HandEyeOptions& options = {},
                                   HandEyeSummary* summary = nullptr);

// InputError (field "poses") if the flange rotations relative to the first pose do not span two
// axes (more than 1 deg, axes more than 5 deg apart): hand-eye is then degenerate.
void CheckRotationsExciteTwoAxes(const std::vector<Isometry3>& base_from_flange);

// InputError (field "poses") for fewer than min_poses poses.
HandEyeResult CalibrateCameraToRobot(const kinematics::RobotModel& model, const std::vector<BoardPoseObservation>& obs,
                                     const HandEyeOptions& options = {}, HandEyeSummary* summary = nullptr);

}  // namespace ramtk::calib

namespace ramtk::calib {

// Board-pose files (CSV with a header): `pose,q1,...,q6,x,y,z,a,b,c` — controller joints (deg)
// and camera_from_board as translation (mm) and KUKA A,B,C (deg, R = RotZ(a)·RotY(b)·RotX(c)).
// InputError names the file, line and column of anything malformed.
std::vector<BoardPoseObservation> ReadBoardPoseObservations(const std::string& path);
std::string FormatBoardPoseObservations(const std::vector<BoardPoseObservation>& obs);

// Hand-eye pose files, either set-up (CSV with a header, any column order). The camera's
// camera_from_board is always `x,y,z` (mm) and `a,b,c` (KUKA A,B,C, deg); the flange pose is one of
//   q1,...,q6                                                   (controller joints, deg; needs `model`)
//   flange_x,flange_y,flange_z,flange_a,flange_b,flange_c      (KUKA A,B,C, deg)
//   flange_x,flange_y,flange_z,flange_qw,flange_qx,flange_qy,flange_qz   (unit quaternion)
//   flange_m00 ... flange_m23     (the top 3 rows of the 4x4 base_from_flange, row-major)
// A flange translation is in `flange_units` ("mm" or "m"). InputError names the file, line and
// column: a missing column, a non-number, a quaternion far from unit norm, a matrix whose rotation
// part is not a rotation (|R^T R - I| beyond 4 times the rounding of its printed decimals, at
// least 1e-6, at most 2e-3; or det < 0), joints without a robot model; a position beyond
// kMaxAbsPositionMm, an angle beyond kMaxAbsPoseAngleDeg, a joint beyond kMaxAbsJointDeg; a row
// whose two flange forms (say matrix and A,B,C) differ by more than kFlangeFormsAgreeDeg or
// kFlangeFormsAgreeMm; and a file whose flange positions all lie within kMinFlangeReachMm of the
// base (metres given as millimetres). A matrix's rotation is replaced by the nearest rotation.
inline constexpr double kMaxAbsPoseAngleDeg = 360.0;  // KUKA A, B, C of a pose
inline constexpr double kFlangeFormsAgreeDeg = 0.01;  // two forms of one row's flange pose
inline constexpr double kFlangeFormsAgreeMm = 0.01;
inline constexpr double kMinFlangeReachMm = 20.0;  // some flange position is at least this far from the base
std::vector<FlangePoseObservation> ReadFlangePoseObservations(const std::string& path,
                                                              const std::string& flange_units = "mm",
                                                              const kinematics::RobotModel* model = nullptr);
// Optional per-row covariance of camera_from_board: the 21 columns cov_ij (0 <= i <= j <= 5) of
// FormatBoardPoseEstimates (board_pose.h), in [ω (deg); t (mm)]; all or none.

// Flange poses alone, one base_from_flange per pose in file order: either a CSV with a header and
// the flange columns above (or q1..q6 with `model`), or plain text with one matrix per line, 16
// (4x4) or 12 (3x4) numbers, row-major, separated by spaces, tabs or commas ('#' comments and
// blank lines skipped). Translations in `flange_units`; the same checks as above.
std::vector<Isometry3> ReadFlangePoses(const std::string& path, const std::string& flange_units = "mm",
                                       const kinematics::RobotModel* model = nullptr);
// Camera poses alone (x,y,z,a,b,c and the optional covariance columns), e.g. a board-pose file of
// `calib cameras --poses-out`, paired with `base_from_flange`: by its `pose` column (1-based
// flange pose number) when it has one, else row by row. InputError (field "poses") for a pose
// number beyond the flange poses, or (row by row) when the counts differ.
std::vector<FlangePoseObservation> ReadCameraPosesWithFlange(const std::string& path,
                                                             const std::vector<Isometry3>& base_from_flange);

// The forms above that carry the flange pose itself.
enum class FlangePoseForm { kKukaAbc, kQuaternion, kMatrix };
// Writes `obs` with a `pose` column, the flange pose in `form` and its translation in
// `flange_units` ("mm" or "m"); an optional comment block first (each line prefixed "# ").
std::string FormatFlangePoseObservations(const std::vector<FlangePoseObservation>& obs,
                                         FlangePoseForm form = FlangePoseForm::kKukaAbc,
                                         const std::string& flange_units = "mm", const std::string& comment = "");

// The result as JSON text (camera_from_base and flange_from_board: 4×4, mm, KUKA A,B,C deg;
// per-pose residuals; summary; with a refinement, the covariance of camera_from_base).
struct EyeInHandRefinement;  // hand_eye_flange_refine.h
std::string HandEyeResultJson(const HandEyeResult& result, const HandEyeSummary& summary,
                              const EyeInHandRefinement* refinement = nullptr);

// Simulated board poses for a board at flange_from_board, seen by a camera at camera_from_base,
// at the given joints; noise: a rotation of sigma_deg·|w| about a random axis (w ~ N(0, I)) and
// sigma_mm per axis of translation, from `seed`.
std::vector<BoardPoseObservation> SimulateBoardPoses(const kinematics::RobotModel& model,
                                                     const std::vector<kinematics::JointVector>& joints,
                                                     const Isometry3& camera_from_base,
                                                     const Isometry3& flange_from_board, double sigma_deg,
                                                     double sigma_mm, unsigned seed);

}  // namespace ramtk::calib
