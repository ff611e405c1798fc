// The sphere fit on the scan's cloud and its gates (scan_pass.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/parallel_invoke.h>

#include "ramtk/core/log.h"
#include "ramtk/vision/stereo/cloud_noise.h"
#include "scan_fit.h"
#include "scan_pass.h"

namespace ramtk::vision::detail {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The fitted spheres that pass the gates; *why_out: why the last rejected one was.
std::vector<SphereResult> GatedSpheres(const ScanSummary& sum, const ScanOptions& options, const SphereFitOptions& so,
                                       std::string* why_out) {
  std::string& why = *why_out;
  // A "sphere" that does not fit its points at their noise level, or whose radius is off the
  // prior, is not reported as a centre.
  std::vector<SphereResult> kept;
  for (const SphereResult& r : sum.spheres.spheres) {
    std::ostringstream reason;
    reason.precision(4);
    if (!(r.radius_mm > 0 && r.centre_mm.allFinite() && r.centre_covariance_mm2.allFinite())) {
      reason << "rejected a sphere candidate: its fit is not finite (radius " << r.radius_mm << " mm)";
    } else if (!(r.variance_factor <= options.max_sphere_variance_factor)) {
      reason << "rejected a sphere candidate (radius " << r.radius_mm << " mm): surface RMS " << r.rms_mm * 1000
             << " um is " << std::sqrt(r.variance_factor) << "x the points' predicted noise (variance factor "
             << r.variance_factor << " > " << options.max_sphere_variance_factor << ")";
    } else if (so.radius_mm > 0 && !so.fix_radius && std::abs(r.radius_mm - so.radius_mm) > so.radius_tolerance_mm) {
      reason << "rejected a sphere candidate: radius " << r.radius_mm << " mm is off the prior " << so.radius_mm
             << " +- " << so.radius_tolerance_mm << " mm";
    } else {
      kept.push_back(r);
      continue;
    }
    why = reason.str();
    RAMTK_LOG(kInfo) << why;
  }
  return kept;
}

// Inflates each kept sphere's covariance by its residuals' neighbour correlation.
void InflateForCorrelatedNoise(const PointCloud& cloud, const ScanOptions& options, const SphereFitOptions& so,
                               const ScanSummary& sum, std::vector<SphereResult>* kept_spheres) {
  std::vector<SphereResult>& kept = *kept_spheres;
  // Neighbouring pixels' noise is correlated (blur; right pixels shared through the bilinear
  // interpolation), which the fit's independent-point covariance leaves out: inflate it by the
  // factor estimated from the residuals' correlation at pixel lags <= 2.
  if (cloud.left_pixels.size() == cloud.size() && !cloud.sigma_mm.empty()) {
    for (SphereResult& r : kept) {
      std::vector<Eigen::Vector2f> px;
      std::vector<double> z;
      for (int i : r.inlier_indices) {
        const Eigen::Vector3d p = cloud.points_in_left[i].cast<double>();
        const Eigen::Vector3d normal = (p - r.centre_mm).normalized();
        const double c = normal.dot((p - so.viewpoint_mm).normalized());
        const double ratio = so.noise_model != PointNoiseModel::kIsotropic ? so.perpendicular_sigma_ratio : 1.0;
        const double sigma_n = cloud.sigma_mm[i] * std::sqrt(c * c + ratio * ratio * std::max(0.0, 1 - c * c));
        if (!(sigma_n > 0)) continue;
        px.push_back(cloud.left_pixels[i]);
        z.push_back(((p - r.centre_mm).norm() - r.radius_mm) / sigma_n);
      }
      // A phase filter of radius R shares noise between pixels up to 2R apart.
      const int lag = 2 + 2 * options.decode.coordinate_filter.radius_px;
      const NeighbourCorrelation nc = EstimateNeighbourCorrelation(px, z, cv::Size(sum.width, sum.height), lag);
      // Never below 1: on white residuals the estimate scatters around 1 and would shrink the
      // independent-point covariance half the time.
      const double factor = std::max(1.0, nc.factor);
      r.correlation_factor = factor;
      r.centre_covariance_mm2 *= factor;
      r.radius_sigma_mm *= std::sqrt(factor);
      r.crlb_centre_sigma_mm *= std::sqrt(factor);
      r.crlb_radius_sigma_mm *= std::sqrt(factor);
    }
  }
}

}  // namespace

void FitScanSpheres(const PointCloud& cloud, const ScanOptions& options, const SphereFitOptions& so,
                    ScanSummary* summary) {
  ScanSummary& sum = *summary;
  const auto fit_t0 = std::chrono::steady_clock::now();
  if (cloud.size() < static_cast<std::size_t>(so.min_points)) {
    sum.spheres.termination = Termination::kNoResult;
    sum.spheres.message = "no sphere found";
    sum.spheres.input_points = static_cast<int>(cloud.size());
    sum.spheres.no_sphere_reason = "too few points: the cloud has " + std::to_string(cloud.size()) +
                                   ", a sphere needs at least " + std::to_string(so.min_points);
  } else {
    sum.spheres = FindSpheres(cloud.points_in_left, cloud.sigma_mm, so);
  }
  std::string why;
  std::vector<SphereResult> kept = GatedSpheres(sum, options, so, &why);
  InflateForCorrelatedNoise(cloud, options, so, sum, &kept);
  if (kept.size() != sum.spheres.spheres.size()) {
    if (kept.empty()) {
      sum.spheres.termination = Termination::kNoResult;
      sum.spheres.message = "no sphere found";
      sum.spheres.no_sphere_reason = why;
    }
  }
  sum.spheres.spheres = kept;
  sum.fit_s = Seconds(fit_t0);
  if (sum.spheres.spheres.empty()) {
    sum.termination = Termination::kNoResult;
    sum.message = "no sphere found";
  }
}

}  // namespace ramtk::vision::detail

namespace ramtk::vision {

void FitSpheresBesideCloud(ScanResult& result, const ScanOptions& options) {
  const SphereFitOptions so = detail::StageOptionsOf(options).sphere;
  // The outputs' writer (ScanOptions::on_cloud) beside the fit, whose serial parts leave a core idle.
  tbb::parallel_invoke(
      [&] {
        if (options.fit_spheres) detail::FitScanSpheres(result.cloud, options, so, &result.summary);
      },
      [&] {
        if (options.on_cloud) options.on_cloud(result.cloud, result.depth);
      });
  if (options.fit_spheres && options.progress) options.progress({"fit", 5, 5});
}

}  // namespace ramtk::vision
