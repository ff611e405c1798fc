#pragma once
// The Cramér–Rao bound of a sphere's centre and radius: the Fisher information of (centre,
// radius) carried by a set of points with Gaussian noise, and its inverse, the smallest
// covariance an unbiased estimator can reach on those points.
//
// Each point constrains the sphere through its distance to the surface along the normal n: a
// point displaced by noise of covariance S moves off the surface by n^T S n, and the gradient of
// that distance with respect to (centre, radius) is -(n, 1). The tangential part of the noise
// only slides the point along the surface and carries no information to first order. With
// sigma_n,i the noise along the normal of point i:
//   F = sum_i (n_i, 1) (n_i, 1)^T / sigma_n,i^2,   cov >= F^-1 (times the correlation factor).
// sigma_n,i from the point's sigma and noise model (PointNoiseModel, a the angle between the
// normal and the line of sight from the viewpoint):
//   kIsotropic          sigma
//   kAlongLineOfSight   sigma sqrt(cos^2 a + ratio^2 sin^2 a)
//   kAlongRay           sigma |cos a|   (displacement along the ray only; a point seen exactly
//                                         edge-on, sigma_n = 0, is left out)
// Closed forms: a full sphere of N uniformly spread points with isotropic sigma gives 3 sigma^2 / N
// per centre axis and sigma^2 / N for the radius; a hemisphere gives 3 sigma^2 / N across the
// axis, 12 sigma^2 / N along it, 4 sigma^2 / N for the radius.
// Noise correlated between neighbouring points (a pixel grid's blur, shared interpolation) makes
// fewer independent measurements than points; correlation_factor (>= 1, as
// SphereResult::correlation_factor) scales the bound's covariance.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/vision/sphere/sphere_fit.h"

namespace ramtk::vision {

struct SphereCrlbOptions {
  // How each point's sigma is read (see PointNoiseModel and the table above).
  PointNoiseModel noise_model = PointNoiseModel::kAlongRay;
  // Where the lines of sight / rays start (mm, the points' frame); unused for kIsotropic.
  Eigen::Vector3d viewpoint_mm = Eigen::Vector3d::Zero();
  // kAlongLineOfSight: across-sight over along-sight sigma.
  double perpendicular_sigma_ratio = 0.25;
  // true: the radius is known (not estimated); the bound is then that of the centre alone.
  bool fix_radius = false;
  // Variance inflation for noise correlated between neighbouring points (>= 1; 1 = independent).
  double correlation_factor = 1;
  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

struct SphereCrlb {
  bool valid = false;  // false: fewer than 4 usable points or a singular Fisher information
  int num_points = 0;  // points that entered the information (finite, sigma > 0, off the centre)
  // Fisher information of (centre x, y, z, radius), 1/mm^2, for independent points.
  Eigen::Matrix4d fisher = Eigen::Matrix4d::Zero();
  // The bound: centre covariance (mm^2) and radius sigma (mm; 0 when fix_radius), including the
  // correlation factor.
  Eigen::Matrix3d centre_covariance_mm2 = Eigen::Matrix3d::Zero();
  double radius_sigma_mm = 0;
  // sqrt of the centre covariance's diagonal (mm).
  Eigen::Vector3d CentreSigma() const;
};

// The bound for the sphere (centre_mm, radius_mm) — the true sphere, or the fitted one as its
// estimate — from the points `indices` of points_mm with sigmas sigma_mm (mm, indexed like
// points_mm; empty indices = every point). Throws InputError for invalid options or a sigma_mm
// of the wrong size.
SphereCrlb SphereCramerRao(const std::vector<Eigen::Vector3f>& points_mm, const std::vector<float>& sigma_mm,
                           const std::vector<int>& indices, const Eigen::Vector3d& centre_mm, double radius_mm,
                           const SphereCrlbOptions& options);

}  // namespace ramtk::vision
