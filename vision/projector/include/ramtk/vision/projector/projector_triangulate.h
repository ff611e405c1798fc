#pragma once
// Camera–projector triangulation: each camera pixel's decoded projector coordinate names a
// projector plane (one fringe direction: the column u of vertical fringes or the row v of
// horizontal ones) or a projector pixel (both directions); the point is where the camera pixel's
// ray meets it. The projector's lens distortion bends a "plane" of one projector column, so the
// intersection is solved on the ray itself: the depth z along the undistorted camera ray
// X(z) = z·(x', y', 1) whose projection into the projector (with its distortion) gives the decoded
// coordinate(s), by Gauss-Newton from the ideal-plane solution. Its sensitivity carries the
// decoder's coordinate sigma into the point's:
//   sigma_z = 1 / sqrt(sum_i (dp_i/dz)^2 / sigma_i^2),   sigma (along the ray) = |(x', y', 1)|·sigma_z,
// p_i the projected projector coordinate(s), sigma_i the decoded coordinate's sigma (projector px).

#include <opencv2/core.hpp>
#include <string>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace ramtk::vision {

struct ProjectorTriangulationOptions {
  // Points whose depth z (camera frame, mm) lies outside (min_depth_mm, max_depth_mm) are dropped.
  double min_depth_mm = 0;
  double max_depth_mm = 1e5;
  // Most Gauss-Newton iterations on the depth (the solve stops when a step is below 1e-12 of the
  // depth; two or three steps on the lenses OpenCV calibrates).
  int max_iterations = 8;
  // Both directions: a pixel whose decoded projector pixel misses the ray's projection by more
  // than this many sigma (chi with one degree of freedom) is dropped (the coordinates disagree).
  double max_residual_sigma = 5;
  // Keep each point's camera pixel in PointCloud::left_pixels.
  bool keep_pixels = true;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct ProjectorTriangulationSummary {
  long coded_pixels = 0;        // camera pixels with a decoded coordinate (both, for ray–ray)
  long points = 0;              // points written to the cloud
  long rejected_geometry = 0;   // no intersection in front of both, outside the projector image, or
                                // outside the depth range
  long rejected_residual = 0;   // both directions: coordinates that disagree (max_residual_sigma)
  double median_sigma_mm = 0;   // median point sigma
  double depth_min_mm = 0, depth_max_mm = 0;  // z range of the cloud
  std::string BriefReport() const;
};

// Ray–plane: `coded` holds the projector coordinate along `direction` (DecodedCamera::coordinate,
// sigma_coordinate, modulation) for the camera's pixels. Per point: position (mm, camera frame),
// sigma (mm, along the camera ray) and quality (modulation / sigma_I). `depth` (optional) receives
// a CV_32F map of z (mm, NaN where there is no point). InputError (field coordinate) if a map's
// size differs from the calibration's camera image size.
PointCloud TriangulateProjectorPlanes(const ProjectorCalibration& calibration, FringeDirection direction,
                                      const DecodedCamera& coded, const ProjectorTriangulationOptions& options,
                                      ProjectorTriangulationSummary* summary = nullptr, cv::Mat* depth = nullptr);

// Ray–ray: `columns` from vertical fringes (projector u), `rows` from horizontal ones (projector v),
// the same camera pixels; each point is the depth whose projector pixel best matches (u, v) by
// weighted least squares. Quality from `columns`.
PointCloud TriangulateProjectorPixels(const ProjectorCalibration& calibration, const DecodedCamera& columns,
                                      const DecodedCamera& rows, const ProjectorTriangulationOptions& options,
                                      ProjectorTriangulationSummary* summary = nullptr, cv::Mat* depth = nullptr);

}  // namespace ramtk::vision
