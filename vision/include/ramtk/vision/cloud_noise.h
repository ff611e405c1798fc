#pragma once
// Noise figure of an organised point cloud without ground truth: the RMS of a local surface fit
// on small patches, beside the noise the points' own sigma predicts there.

#include <opencv2/core.hpp>

#include "ramtk/vision/point_cloud.h"

namespace ramtk::vision {

struct LocalFitNoise {
  long patches = 0;                // complete patches fitted
  double median_rms_mm = 0;        // median over patches of the fit's z residual RMS (dof-corrected)
  double median_predicted_mm = 0;  // median over patches of the RMS predicted z sigma (sigma along the ray * |ray.z|)
  double ratio = 0;                // median over patches of observed / predicted
};

// Tiles the left image with non-overlapping window x window patches; every patch whose pixels all
// hold a point (the cloud's left_pixels) is fitted with z = quadratic(du, dv) (a "plane" that
// follows the surface's curvature: 6 parameters, so smooth curved surfaces fit to the noise) and
// its residual RMS compared with the points' predicted z sigma. Patches straddling a depth step
// have large residuals; the median ignores them as long as they are a minority.
LocalFitNoise MeasureLocalFitNoise(const PointCloud& cloud, cv::Size image_size, int window = 7);

}  // namespace ramtk::vision
