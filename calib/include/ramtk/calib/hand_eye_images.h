#pragma once
// A hand-eye session from board images: detection, PnP with each view's covariance
// (board_pose.h), and the pairing with the robot's flange poses, for either set-up
// (CalibrateStandCameraWithCovariance, or CalibrateCameraOnFlange + RefineCameraOnFlange).

#include <string>
#include <vector>

#include "ramtk/calib/board_pose.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/core/progress.h"

namespace ramtk::calib {

struct HandEyeViews {
  std::vector<FlangePoseObservation> observations;  // views with a board pose, each with its covariance
  std::vector<std::string> names;                   // their image names, in the same order
  std::vector<int> indices;                         // their index among the views / flange poses
  BoardPoseSummary poses;                           // PnP figures; `skipped` lists the views left out
};

// Detections (views[i] taken at base_from_flange[i]) to hand-eye observations. Views whose board
// was not found or whose PnP failed are skipped and listed. InputError (field "poses") when the
// counts differ.
HandEyeViews HandEyeViewsFromDetections(const std::vector<ViewPoints>& views, const camera::CameraIntrinsics& camera,
                                        const std::vector<Isometry3>& base_from_flange,
                                        const BoardPoseOptions& options = {});

// The same from image files (image i taken at base_from_flange[i]): DetectBoardInImages, then the
// above. InputError when an image's size differs from the camera's.
HandEyeViews HandEyeViewsFromImages(const std::vector<std::string>& image_paths, const BoardSpec& board,
                                    const camera::CameraIntrinsics& camera,
                                    const std::vector<Isometry3>& base_from_flange,
                                    const BoardPoseOptions& options = {}, const ProgressCallback& progress = {});

}  // namespace ramtk::calib
