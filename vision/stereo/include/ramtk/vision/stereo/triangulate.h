#pragma once
// Triangulation of stereo matches into a point cloud in the left-camera frame, with each
// point's standard deviation carried from the decoder's phase sigma through the matching
// (stereo_match.h: sigma of the match along the epipolar curve) and the triangulation Jacobian.

#include <opencv2/core.hpp>

#include "ramtk/vision/kernels/camera.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/stereo/point_cloud.h"
#include "ramtk/vision/stereo/stereo_match.h"

namespace ramtk::vision {

// Midpoint of the common perpendicular of the two undistorted pixel rays, in the left-camera
// frame (mm). `gap_mm` (optional) receives the rays' closest distance. Returns NaNs for
// parallel rays.
Vec3 TriangulateMidpoint(const StereoCalibration& calibration, const Vec2& left_pixel, const Vec2& right_pixel,
                         double* gap_mm = nullptr);

struct TriangulationOptions {
  // Matches whose rays pass farther apart than this are dropped (mm). The epipolar search makes
  // the gap ~1e-9 mm; a large gap means a calibration/image mismatch.
  double max_ray_gap_mm = 0.01;
  // Keep each point's left pixel in PointCloud::left_pixels.
  bool keep_pixels = true;
  std::string Validate() const;
};

struct TriangulationSummary {
  long points = 0;                            // points written to the cloud
  long rejected_gap = 0;                      // matches dropped by max_ray_gap_mm
  double median_sigma_mm = 0;                 // median point sigma
  double depth_min_mm = 0, depth_max_mm = 0;  // z range of the cloud
  std::string BriefReport() const;
};

// Triangulates every matched left pixel. Per point: position (mm, left frame), sigma (mm, along
// the point's left ray: |dX/ds|·sigma_s with s the right position along the epipolar curve) and
// quality (left modulation / sigma_I). `depth` (optional) receives a CV_32F left-image map of z
// (mm, NaN where there is no point). A match carrying its depths (StereoMatch::depth_mm, as
// MatchStereo writes) places each point on its left pixel's ray at that depth: no ray is
// intersected again and no gap is measured; with its points' x and y too (StereoMatch::x_mm,
// y_mm) the points are copied, and `depth` shares the match's depth map. InputError (field
// depth_mm, x_mm, right_u or modulation) if the maps are of the wrong type or size.
PointCloud TriangulateMatches(const StereoCalibration& calibration, const DecodedCamera& left, const StereoMatch& match,
                              const TriangulationOptions& options, TriangulationSummary* summary = nullptr,
                              cv::Mat* depth = nullptr);

}  // namespace ramtk::vision
