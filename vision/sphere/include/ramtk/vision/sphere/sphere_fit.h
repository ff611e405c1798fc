#pragma once
// Sphere extraction and fitting in a point cloud: find sphere candidates by RANSAC (4-point
// closed-form spheres drawn from spatial neighbourhoods, gated by a radius prior, locally
// optimised), then a robust geometric least-squares fit (Ceres) weighted by each point's sigma,
// with free or known radius, and the centre covariance from the Jacobian at the solution.
// Several spheres (a ball bar): the inliers of each sphere are removed and the search repeats.
// No PCL or Ceres types appear here; points are plain vectors in millimetres.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/core/termination.h"

namespace ramtk::vision {

// How the per-point sigma handed to FindSpheres is to be read.
enum class PointNoiseModel {
  // sigma is the standard deviation of the point along any direction (in particular along the
  // surface normal): the residual of point i has sigma_i.
  kIsotropic,
  // sigma is the standard deviation along the line of sight from SphereFitOptions::viewpoint_mm
  // (the depth error of a triangulated point); across it the deviation is
  // sigma * perpendicular_sigma_ratio. The residual along the sphere normal n then has
  // sigma_i * sqrt(cos^2 a + ratio^2 sin^2 a), a the angle between n and the line of sight,
  // re-evaluated at the current centre.
  kAlongLineOfSight,
  // sigma is the standard deviation along the ray from SphereFitOptions::viewpoint_mm through the
  // point (a triangulated point's depth error). The final fit's residual of point i is the distance
  // along that ray from the point to where the ray meets the sphere, over sigma_i: exactly the
  // point's error when it was displaced along its ray. A distance fit along the normal with such
  // data is biased: noise along oblique rays, amplified by the cap geometry (radius and the
  // depth of the centre trade off), gave radius -24 um and z -34 um at sigma 0.19 mm on a 130 px
  // ball (docs/scan.md); along the ray the bias is gone. Robust pass and classification as
  // kAlongLineOfSight.
  kAlongRay,
};

// Robust loss of the geometric fit, applied to residuals in units of (robustly rescaled) sigma.
enum class SphereLoss { kNone, kHuber, kCauchy };

struct SphereFitOptions {
  // Radius prior (mm) for the search; 0 = unknown (candidates between min_radius_mm and
  // max_radius_mm are accepted).
  double radius_mm = 0.0;
  // true: fit the centre only, radius held at radius_mm (which must then be > 0).
  bool fix_radius = false;
  // RANSAC accepts a candidate sphere whose radius is within radius_mm +- this (mm).
  double radius_tolerance_mm = 2;
  // Radius bounds (mm) used when radius_mm = 0.
  double min_radius_mm = 1.0;
  double max_radius_mm = 200.0;
  // RANSAC inlier band (mm, |distance to the sphere surface|); 0 = automatic: 5 x the median
  // point sigma along the normal when sigmas are given, otherwise 0.1 mm; at least 1 um.
  double inlier_threshold_mm = 0;
  // Several spheres (a ball bar): search for up to this many, strongest first.
  int max_spheres = 1;
  // A candidate with fewer inliers than this is "no sphere found".
  int min_points = 200;
  // Robust loss scale in units of the point sigma (rescaled by the robust scatter of the
  // normalised residuals, so a wrong overall sigma level does not matter).
  double robust_loss_scale = 3.0;
  SphereLoss loss = SphereLoss::kHuber;
  // Final inliers: |residual| / (sigma * s) <= this, s the robust (MAD) scale of the normalised
  // residuals. The rest of the candidate points are counted as outliers.
  double outlier_threshold = 4.0;
  // RANSAC sampling seed, fixed for reproducibility.
  uint64_t seed = 1;
  // RANSAC: stop after this many samples, or earlier once a better candidate is unlikely
  // (probability 1 - confidence) given the best inlier share so far; never before min_iterations.
  int max_iterations = 2000;
  int min_iterations = 50;
  double confidence = 0.9999;
  // At most this many points of a neighbourhood score a RANSAC candidate (a strided subset);
  // the locally optimised winner is re-scored on all points.
  int max_scoring_points = 3000;
  // Reading of sigma_mm (see PointNoiseModel). Ignored when sigma_mm is empty.
  PointNoiseModel noise_model = PointNoiseModel::kIsotropic;
  // kAlongLineOfSight: where the lines of sight start (mm, same frame as the points), e.g. the
  // midpoint of the stereo baseline, and the across-sight/along-sight sigma ratio.
  Eigen::Vector3d viewpoint_mm = Eigen::Vector3d::Zero();
  double perpendicular_sigma_ratio = 0.25;
  // Drop points seen at a grazing angle from the final fit: the angle between the line of sight
  // from viewpoint_mm and the fitted surface normal (evaluated at the robust solution) must not
  // exceed this (degrees); 0 = keep every inlier. For triangulated points: near the limb the
  // depth along the ray comes from inverting a strongly curved phase map, and the noise biases it
  // to second order (points land ~4 um too deep at 70-90 deg on the simulated ball, 0 without
  // noise); their weight in a free-radius fit pulls the centre along the line of sight
  // (docs/scan.md). The dropped points are counted in SphereResult::num_grazing.
  double max_view_angle_deg = 0;
  // Scale the centre covariance by the a-posteriori variance factor (chi^2 / (n - p)). Keep it on:
  // the per-point sigmas from phase noise leave out other errors (calibration, surface finish),
  // and with thousands of points the factor is known to a few percent. Without sigmas the
  // covariance is always scaled (the residual scatter is then the only noise level there is).
  bool scale_covariance = true;
  // The robust fit (the per-point loss on all points in one Ceres residual block) runs on a strided
  // subset of at most this many candidate points; it only starts the final fit and sorts out the
  // outliers. The final weighted least-squares fit uses every inlier.
  int max_robust_points = 2000;
  // Maximum Ceres iterations of each geometric fit.
  int max_solver_iterations = 50;
  // Called after each sphere; returning false stops the search (termination "cancelled").
  ProgressCallback progress;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct SphereResult {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  double radius_mm = 0;
  double radius_sigma_mm = 0;  // 0 when the radius was held fixed
  // Centre covariance (mm^2) from the weighted Jacobian at the solution, (J^T W J)^-1, scaled by
  // variance_factor when SphereFitOptions::scale_covariance (see there).
  Eigen::Matrix3d centre_covariance_mm2 = Eigen::Matrix3d::Zero();
  double rms_mm = 0;           // RMS of the inliers' distances to the fitted surface
  double worst_mm = 0;         // largest |distance| among the inliers
  int num_points = 0;          // inliers used in the final fit
  int num_outliers = 0;        // candidate points near the sphere rejected by the robust fit
  int num_grazing = 0;         // inliers left out of the final fit by max_view_angle_deg
  double variance_factor = 1;  // chi^2 / (n - p) of the final fit (1 = sigmas honest)
  double robust_scale = 1;     // MAD scale of the normalised residuals before the final fit
  // Variance inflation for noise correlated between neighbouring points, already applied to
  // centre_covariance_mm2 and radius_sigma_mm. FindSpheres treats points as independent (1); a
  // caller that knows the points' pixel grid sets it (the scan: NeighbourCorrelationFactor).
  double correlation_factor = 1;
  // Cramér–Rao bound of the centre (sigma along x, y, z, mm) and of the radius (mm; 0 when held
  // fixed) on the final fit's points, their sigmas read by the options' noise model and the
  // fitted sphere standing in for the true one (sphere_crlb.h), times correlation_factor; not
  // scaled by variance_factor. Zero without per-point sigmas.
  Eigen::Vector3d crlb_centre_sigma_mm = Eigen::Vector3d::Zero();
  double crlb_radius_sigma_mm = 0;
  int ransac_iterations = 0;                // samples drawn to find this sphere
  int solver_iterations = 0;                // Ceres iterations of the final fit
  double initial_cost = 0, final_cost = 0;  // Ceres costs (0.5 sum z^2) of the final fit
  std::vector<int> inlier_indices;          // into the input cloud
  // Centre sigma along x, y, z (sqrt of the covariance diagonal).
  Eigen::Vector3d CentreSigma() const;
};

struct SphereFitSummary {
  std::vector<SphereResult> spheres;  // strongest first; empty = no sphere found
  // Why the search stopped: kSuccess "ok" (max_spheres found), kPartial "partial" (fewer, at
  // least one), kNoResult "no sphere found", kCancelled "cancelled". With fewer spheres than
  // max_spheres, no_sphere_reason says why the next one was not found.
  Termination termination = Termination::kSuccess;
  std::string message = "ok";
  std::string no_sphere_reason;
  int input_points = 0;
  int unassigned_points = 0;       // points not in any sphere
  double inlier_threshold_mm = 0;  // RANSAC band actually used
  std::string BriefReport() const;
};

// Finds up to options.max_spheres spheres in points_mm. sigma_mm: one sigma per point (mm), or
// empty (unweighted: every point has the same, estimated, sigma). Non-finite points are ignored.
// Throws InputError for invalid options or a sigma_mm of the wrong size / non-positive values.
SphereFitSummary FindSpheres(const std::vector<Eigen::Vector3f>& points_mm, const std::vector<float>& sigma_mm,
                             const SphereFitOptions& options);

// The sphere through four points (closed form); false if they are (nearly) coplanar.
bool SphereThroughFourPoints(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d, Eigen::Vector3d* centre, double* radius);

// Distance between two sphere centres and its sigma (first order, the two centres independent:
// they come from disjoint points), e.g. the length of a ball bar.
struct CentreDistance {
  double distance_mm = 0;
  double sigma_mm = 0;
};
CentreDistance ComputeCentreDistance(const SphereResult& a, const SphereResult& b);

// The "Sphere result" JSON (docs/formats.md): frame name, termination, and per sphere the
// centre, radius, sigmas, RMS, point and outlier counts and the 3x3 centre covariance; with two
// or more spheres also the centre distances. Pretty-printed with `indent` spaces.
std::string SphereFitToJson(const SphereFitSummary& summary, const std::string& frame, int indent = 2);
// Writes that JSON atomically (InputError naming the file on failure).
void WriteSphereFitJson(const std::string& path, const SphereFitSummary& summary, const std::string& frame);

}  // namespace ramtk::vision
