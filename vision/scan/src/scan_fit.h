#pragma once
// The scan's last stage, shared by the stereo and the monocular pipelines (scan.cpp).

#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {

// Fits the spheres of result.cloud (ScanOptions::sphere, the variance and radius gates, the
// inflation of each centre's covariance by its residuals' neighbour correlation) into
// result.summary, beside ScanOptions::on_cloud (called with the cloud and depth map), and reports
// the "fit" stage.
void FitSpheresBesideCloud(ScanResult& result, const ScanOptions& options);

}  // namespace ramtk::vision
