// The Cramér–Rao bound of a sphere's centre and radius (sphere_crlb.h).
#include "ramtk/vision/sphere/sphere_crlb.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

// Noise sigma of a point along the sphere normal n under the options' model.
double NormalSigma(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double sigma, const SphereCrlbOptions& o) {
  if (o.noise_model == PointNoiseModel::kIsotropic) return sigma;
  const Eigen::Vector3d sight = p - o.viewpoint_mm;
  const double length = sight.norm();
  if (!(length > 0)) return 0;
  const double c = n.dot(sight) / length;
  if (o.noise_model == PointNoiseModel::kAlongRay) return sigma * std::abs(c);
  const double ratio = o.perpendicular_sigma_ratio;
  return sigma * std::sqrt(c * c + ratio * ratio * std::max(0.0, 1 - c * c));
}

}  // namespace

std::string SphereCrlbOptions::Validate() const {
  if (!viewpoint_mm.allFinite()) return "viewpoint_mm: must be finite";
  if (!(std::isfinite(perpendicular_sigma_ratio) && perpendicular_sigma_ratio >= 0))
    return "perpendicular_sigma_ratio: must be >= 0";
  if (!(std::isfinite(correlation_factor) && correlation_factor >= 1)) return "correlation_factor: must be >= 1";
  return "";
}

Eigen::Vector3d SphereCrlb::CentreSigma() const { return centre_covariance_mm2.diagonal().cwiseMax(0).cwiseSqrt(); }

SphereCrlb SphereCramerRao(const std::vector<Eigen::Vector3f>& points_mm, const std::vector<float>& sigma_mm,
                           const std::vector<int>& indices, const Eigen::Vector3d& centre_mm, double radius_mm,
                           const SphereCrlbOptions& options) {
  ThrowIfInvalid(options.Validate(), "SphereCrlbOptions");
  if (sigma_mm.size() != points_mm.size())
    throw InputError({"", 0, "sigma_mm"}, "has " + std::to_string(sigma_mm.size()) + " values for " +
                                              std::to_string(points_mm.size()) + " points");
  SphereCrlb out;
  if (!(centre_mm.allFinite() && std::isfinite(radius_mm) && radius_mm > 0)) return out;
  const std::size_t count = indices.empty() ? points_mm.size() : indices.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = indices.empty() ? k : static_cast<std::size_t>(indices[k]);
    if (i >= points_mm.size()) throw InputError({"", 0, "indices"}, "index " + std::to_string(i) + " out of range");
    const Eigen::Vector3d p = points_mm[i].cast<double>();
    const Eigen::Vector3d d = p - centre_mm;
    const double dist = d.norm();
    if (!(p.allFinite() && dist > 0)) continue;
    const Eigen::Vector3d n = d / dist;
    const double sn = NormalSigma(p, n, sigma_mm[i], options);
    if (!(sn > 0 && std::isfinite(sn))) continue;
    const Eigen::Vector4d g(n.x(), n.y(), n.z(), 1.0);
    out.fisher.noalias() += g * g.transpose() / (sn * sn);
    ++out.num_points;
  }
  const int params = options.fix_radius ? 3 : 4;
  if (out.num_points < params) return out;
  if (options.fix_radius) {
    const Eigen::Matrix3d f = out.fisher.topLeftCorner<3, 3>();
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(f);
    if (!lu.isInvertible()) return out;
    out.centre_covariance_mm2 = lu.inverse() * options.correlation_factor;
  } else {
    const Eigen::FullPivLU<Eigen::Matrix4d> lu(out.fisher);
    if (!lu.isInvertible()) return out;
    const Eigen::Matrix4d cov = lu.inverse() * options.correlation_factor;
    out.centre_covariance_mm2 = cov.topLeftCorner<3, 3>();
    out.radius_sigma_mm = std::sqrt(std::max(0.0, cov(3, 3)));
  }
  out.valid = out.centre_covariance_mm2.allFinite();
  return out;
}

}  // namespace ramtk::vision
