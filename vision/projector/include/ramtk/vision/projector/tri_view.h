#pragma once
// Tri-view on a stereo rig: the projector as a third view. Left pixels that decoded but found no
// stereo match (the right camera does not see them, or the match was rejected) are triangulated
// against the projector instead (projector_triangulate.h), with their sigma, so a surface seen by
// the left camera and lit by the projector still gives points.

#include <opencv2/core.hpp>

#include "ramtk/vision/projector/projector_triangulate.h"

namespace ramtk::vision {

struct TriViewSummary {
  long stereo_points = 0;     // points the cloud held (the stereo pair's)
  long projector_points = 0;  // points added by the left camera and the projector
  ProjectorTriangulationSummary projector;  // the camera–projector triangulation of the empty pixels
};

// `calibration`: the left camera and the projector (projector_from_camera = projector_from_left).
// `cloud` (with left_pixels) and `depth` (CV_32F, the left image's size, NaN where the stereo pair
// gave no point) are the stereo scan's; the left pixels with a decoded coordinate and no point get
// one from the projector, appended to `cloud` and written into `depth`. InputError (field depth)
// for a depth map of another size.
TriViewSummary AddProjectorPoints(const ProjectorCalibration& calibration, FringeDirection direction,
                                  const DecodedCamera& left, const ProjectorTriangulationOptions& options,
                                  PointCloud* cloud, cv::Mat* depth);

}  // namespace ramtk::vision
