#pragma once
// Hand-eye calibration for a camera on the flange (AX = XB) from flange poses given directly
// (the controller's base_from_flange, no robot model needed), through OpenCV's
// cv::calibrateHandEye with any of its five methods.
//
// Per pose i the camera measures camera_from_board_i; the board is fixed in the cell:
//   base_from_board = base_from_flange_i · flange_from_camera · camera_from_board_i  (all i).
// OpenCV's gripper = our flange, its target = our board; its output cam2gripper is our
// flange_from_camera.

#include <string>
#include <vector>

#include "ramtk/calib/hand_eye.h"
#include "ramtk/core/error.h"
#include "ramtk/core/rotation.h"

namespace ramtk::calib {

using FlangeCameraObservation = FlangePoseObservation;

// OpenCV's cv::HandEyeCalibrationMethod values.
enum class EyeInHandMethod { kTsai, kPark, kHoraud, kAndreff, kDaniilidis };
const char* EyeInHandMethodName(EyeInHandMethod method);
// "tsai", "park", "horaud", "andreff", "daniilidis"; InputError naming `where` otherwise.
EyeInHandMethod ParseEyeInHandMethod(const std::string& text, const InputLocation& where);

struct EyeInHandResult {
  Isometry3 flange_from_camera = Isometry3::Identity();
  // The board in the base frame: the chordal mean (rotation) and mean (translation) of
  // base_from_flange_i · flange_from_camera · camera_from_board_i over the poses.
  Isometry3 base_from_board = Isometry3::Identity();
  // Per pose: measured vs predicted camera_from_board (rotation angle in degrees, translation mm).
  std::vector<double> rotation_residual_deg, translation_residual_mm;
  double rms_rotation_deg = 0, rms_translation_mm = 0;
};

// InputError (field "poses") for fewer than 3 poses, or if OpenCV fails (e.g. all rotations
// about one axis: the problem is then degenerate).
EyeInHandResult CalibrateCameraOnFlange(const std::vector<FlangeCameraObservation>& obs, EyeInHandMethod method);

// Pose files: ReadFlangePoseObservations / FormatFlangePoseObservations (hand_eye.h).

// The result as JSON text: flange_from_camera and base_from_board (4x4, mm, KUKA A,B,C deg),
// per-pose residuals, their RMS and the method.
struct EyeInHandRefinement;  // hand_eye_flange_refine.h
std::string EyeInHandResultJson(const EyeInHandResult& result, EyeInHandMethod method,
                                const EyeInHandRefinement* refinement = nullptr);
// One line: method, poses, residual RMS, flange_from_camera.
std::string EyeInHandBriefReport(const EyeInHandResult& result, EyeInHandMethod method,
                                 const EyeInHandRefinement* refinement = nullptr);

// Simulated observations of a board at base_from_board by a camera at flange_from_camera, at
// the given flange poses; noise as SimulateBoardPoses: a rotation of sigma_deg·|w| about a
// random axis (w ~ N(0, I)) and sigma_mm per axis of translation, from `seed`.
std::vector<FlangeCameraObservation> SimulateFlangeCameraPoses(const std::vector<Isometry3>& base_from_flange,
                                                               const Isometry3& flange_from_camera,
                                                               const Isometry3& base_from_board, double sigma_deg,
                                                               double sigma_mm, unsigned seed);

}  // namespace ramtk::calib
