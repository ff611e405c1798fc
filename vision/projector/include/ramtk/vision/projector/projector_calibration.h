#pragma once
// Calibration of one camera and one projector (the projector as an inverse camera): both
// pinholes with OpenCV distortion and the rigid transform from the camera to the projector.
//
// Files (docs/formats.md, "Projector calibration"), OpenCV FileStorage YAML or JSON:
//  * ramtk's layout: the stereo calibration keys with the projector as camera 2 — K1 D1 (camera),
//    K2 D2 (projector), R T (projector_from_camera: x_in_projector = R·x_in_camera + T, T in mm),
//    image_size (camera) and image_size2 (projector resolution);
//  * SLMaster's monocular caliInfo.yml: M1 D1 (camera), M4 D4 (projector), Rlp Tlp and S. SLMaster
//    builds its projector matrix as M4·[Rlp | Tlp] applied to camera-frame points (its
//    CameraEngine's monocular patterns, CalibrateEngine's solvePnP of camera-frame board corners
//    against projector pixels), so Rlp, Tlp are projector_from_camera, in the board's unit (mm).
//    The file carries no projector resolution: it comes from the fringe-set manifest.

#include <limits>
#include <string>
#include <vector>

#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision {

struct ProjectorCalibration {
  CameraIntrinsics camera;     // the camera (the reference frame of every 3-D result)
  CameraIntrinsics projector;  // the projector as an inverse camera; width, height = its resolution
  Isometry3 projector_from_camera = Isometry3::Identity();  // translation in mm
  // Quality figures from a calibration session, when the file has them (NaN / empty otherwise).
  double rms_px = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> parameter_std;
};

// The same numbers as a stereo pair (camera = left, projector = right, right_from_left =
// projector_from_camera), and back.
StereoCalibration AsStereoPair(const ProjectorCalibration& calibration);
ProjectorCalibration FromStereoPair(const StereoCalibration& pair);

// Reads either layout. A projector resolution of `projector_width` x `projector_height` (> 0)
// overrides the file's image_size2 (SLMaster's files have none). InputError naming the file and
// key for anything ReadStereoCalibration refuses, and for a projector without a resolution.
ProjectorCalibration ReadProjectorCalibration(const std::string& path, int projector_width = 0,
                                              int projector_height = 0);
// The same from the file's text; `path` names it in errors.
ProjectorCalibration ParseProjectorCalibration(const std::string& text, const std::string& path,
                                               int projector_width = 0, int projector_height = 0);

// Writes ramtk's layout (WriteStereoCalibration with the projector as camera 2).
void WriteProjectorCalibration(const std::string& path, const ProjectorCalibration& calibration);

}  // namespace ramtk::vision
