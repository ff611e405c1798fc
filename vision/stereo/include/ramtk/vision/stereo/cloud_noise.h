#pragma once
// Noise figure of an organised point cloud without ground truth: the RMS of a local surface fit
// on small patches, beside the noise the points' own sigma predicts there.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "ramtk/vision/stereo/point_cloud.h"

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

namespace ramtk::vision {

// Variance inflation of a least-squares estimate from residuals that are correlated between
// neighbouring pixels (camera blur, and left pixels sharing right pixels through the matcher's
// bilinear interpolation), estimated from the residuals themselves:
//   factor = 1 + sum over lags (du, dv) != 0, |du|, |dv| <= max_lag of rho(du, dv),
// rho the correlation coefficient of the normalised residuals of point pairs at that pixel lag.
// For noise correlated over a few pixels and weights that vary slowly across the surface this is
// the factor by which the variance of the fit (which assumes independent points) is too small.
struct NeighbourCorrelation {
  double factor = 1;     // 1 + sum of rho; at least 1/4 (noise cannot cancel more than that here)
  double rho_right = 0;  // rho(1, 0), rho(0, 1): nearest neighbours along a row and a column
  double rho_down = 0;
  long pairs = 0;  // point pairs used over all lags
};
// `pixels` and `normalised_residuals` index the same points (residual / its sigma); pixels are
// integer left-image positions inside image_size. Points without a neighbour contribute nothing.
NeighbourCorrelation EstimateNeighbourCorrelation(const std::vector<Eigen::Vector2f>& pixels,
                                                  const std::vector<double>& normalised_residuals, cv::Size image_size,
                                                  int max_lag = 2);

}  // namespace ramtk::vision
