#pragma once
// Camera + projector calibration from a projector calibration session (projector_session.h;
// `ramtk calib projector`). Per pose: both fringe directions decoded (vision::DecodeCamera), the
// board found in the decoded background of the vertical fringes (the flat-lit board, scaled to
// 8 bit), its corners' projector pixels found from the decoded phase by local homographies
// (vision::ProjectorCornersFromPhase, with σ). Then the camera (its image size) and the projector
// (its resolution) are each calibrated alone and refined jointly as a stereo pair (CalibrateStereo
// with two image sizes), the parameter σ from the joint Jacobian with each device's own residual
// variance. The result is the projector calibration file `ramtk scan` reads (camera = camera 1,
// projector = camera 2, R T = projector_from_camera).

#include <limits>
#include <string>
#include <vector>

#include "ramtk/calib/board.h"
#include "ramtk/calib/camera_calibration.h"
#include "ramtk/calib/projector/projector_session.h"
#include "ramtk/core/progress.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/projector/projector_corners.h"

namespace ramtk::calib {

struct ProjectorSessionOptions {
  // Lens model, outlier rejection and minimum views of both devices (per_camera_variance is set
  // by the calibration: the projector's corners are not as noisy as the camera's).
  CameraCalibrationOptions calibration;
  vision::ProjectorCornerOptions corners;  // window of the local homographies
  vision::DecodeOptions decode;            // decode of each direction's fringes
  BoardDetectOptions detect;               // corner detection in the flat-lit image
  // A pose is used only when at least this share of its corners has a projector pixel.
  double min_projector_corner_fraction = 0.8;
  ProgressCallback progress;  // stage "pose" per pose decoded, then "calibrate"
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// One pose of the session.
struct ProjectorPoseReport {
  std::string name;
  bool used = false;          // in the final stereo calibration
  std::string reason;         // why not (board not found, too few projector corners, rejected)
  int camera_corners = 0;     // corners found in the camera image
  int projector_corners = 0;  // of those, with a projector pixel
  double median_corner_sigma_px = std::numeric_limits<double>::quiet_NaN();  // projector px, larger axis
  double camera_rms_px = std::numeric_limits<double>::quiet_NaN();           // reprojection RMS, camera px
  double projector_rms_px = std::numeric_limits<double>::quiet_NaN();        // reprojection RMS, projector px
};

struct ProjectorSessionResult {
  vision::ProjectorCalibration calibration;  // what the file holds (parameter_std in kCalibParameterStdOrder)
  StereoCalibrationResult stereo;            // the joint fit and each device's own fit
  std::vector<ProjectorPoseReport> poses;    // every pose of the session, in its order
  double camera_rms_px = 0.0;                // over every corner of the used poses, camera px
  double projector_rms_px = 0.0;             // the same in projector px
  int camera_width = 0, camera_height = 0;
  int projector_width = 0, projector_height = 0;
};

struct ProjectorSessionSummary {
  int poses = 0;       // in the session
  int used_poses = 0;  // in the final calibration
  double camera_rms_px = 0.0, projector_rms_px = 0.0;
  std::string BriefReport() const;
};

// Calibrates from a session. `board` is the board in the images. InputError naming the manifest
// (and its field) for an unreadable pose, a direction that is not the one its key says, projector
// resolutions or camera image sizes that differ between poses, and when fewer than
// calibration.min_views poses remain.
ProjectorSessionResult CalibrateProjectorSession(const ProjectorSession& session, const BoardSpec& board,
                                                 const ProjectorSessionOptions& options,
                                                 ProjectorSessionSummary* summary = nullptr);

// The summary JSON of `calib projector`: sizes, the parameters with their σ (kCalibParameterStdOrder
// names), the overall and per-pose RMS in camera and projector pixels, every pose's corner counts.
std::string ProjectorSessionResultJson(const ProjectorSessionResult& result, const BoardSpec& board);

}  // namespace ramtk::calib
