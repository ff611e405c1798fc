// The projector as a third view of a stereo rig (tri_view.h).
#include "ramtk/vision/projector/tri_view.h"

#include <cmath>
#include <limits>

#include "ramtk/core/error.h"

namespace ramtk::vision {

TriViewSummary AddProjectorPoints(const ProjectorCalibration& calibration, FringeDirection direction,
                                  const DecodedCamera& left, const ProjectorTriangulationOptions& options,
                                  PointCloud* cloud, cv::Mat* depth) {
  if (depth->type() != CV_32F || depth->size() != left.coordinate.size())
    throw InputError({"", 0, "depth"}, "expected a CV_32F depth map of the left image's size");
  TriViewSummary sum;
  sum.stereo_points = static_cast<long>(cloud->size());
  // The left camera's coordinates where the stereo pair gave no point.
  DecodedCamera empty = left;
  empty.coordinate = left.coordinate.clone();
  for (int y = 0; y < depth->rows; ++y) {
    const float* z = depth->ptr<float>(y);
    float* c = empty.coordinate.ptr<float>(y);
    for (int x = 0; x < depth->cols; ++x)
      if (std::isfinite(z[x])) c[x] = std::numeric_limits<float>::quiet_NaN();
  }
  ProjectorTriangulationOptions o = options;
  o.keep_pixels = true;
  cv::Mat added_depth;
  const PointCloud added = TriangulateProjectorPlanes(calibration, direction, empty, o, &sum.projector, &added_depth);
  sum.projector_points = static_cast<long>(added.size());
  const bool pixels = cloud->left_pixels.size() == cloud->size();
  cloud->points_in_left.insert(cloud->points_in_left.end(), added.points_in_left.begin(), added.points_in_left.end());
  cloud->sigma_mm.insert(cloud->sigma_mm.end(), added.sigma_mm.begin(), added.sigma_mm.end());
  cloud->quality.insert(cloud->quality.end(), added.quality.begin(), added.quality.end());
  if (pixels) cloud->left_pixels.insert(cloud->left_pixels.end(), added.left_pixels.begin(), added.left_pixels.end());
  for (const Eigen::Vector2f& p : added.left_pixels) {
    const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
    depth->at<float>(y, x) = added_depth.at<float>(y, x);
  }
  return sum;
}

}  // namespace ramtk::vision
