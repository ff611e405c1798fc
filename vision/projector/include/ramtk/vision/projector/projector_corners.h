#pragma once
// Projector coordinates of calibration-board corners from decoded fringes (the projector as an
// inverse camera "sees" the board through the phase): around each corner the camera-to-projector
// map of a flat board is a homography, fitted by least squares to the window's decoded (u, v)
// (vertical and horizontal fringes) and evaluated at the corner's camera position (local
// homographies; Moreno and Taubin, 3DIMPVT 2012), weighted by the decoder's coordinate sigma. The
// corner's sigma is the fit's prediction sigma at the corner (from the fit's covariance).

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision {

struct ProjectorCornerOptions {
  // Half side of the square window around each corner (camera px); the window holds
  // (2 half_window_px + 1)^2 pixels.
  int half_window_px = 15;
  // A corner is kept when at least this share of its window's pixels decoded in both directions.
  double min_valid_fraction = 0.5;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct ProjectorCorner {
  bool valid = false;                 // false: too few decoded pixels in the window, or outside the image
  Vec2 projector_px = Vec2::Zero();   // projector pixel of the corner
  Vec2 sigma_px = Vec2::Zero();       // its sigma along u and v (projector px)
  int pixels = 0;                     // pixels fitted
  double residual_rms_px = 0;         // RMS of the homography's residuals in the window (projector px)
};

// One entry per camera corner. `columns` decodes vertical fringes (projector u), `rows` horizontal
// ones (projector v), both of the same camera image size. InputError (field coordinate) if not.
std::vector<ProjectorCorner> ProjectorCornersFromPhase(const std::vector<cv::Point2f>& camera_corners,
                                                       const DecodedCamera& columns, const DecodedCamera& rows,
                                                       const ProjectorCornerOptions& options = {});

}  // namespace ramtk::vision
