// FindSpheres: RANSAC candidate -> robust geometric fit -> inlier classification -> weighted
// least squares on the inliers -> covariance; repeated on the remaining points for several spheres.

#include "ramtk/vision/sphere/sphere_fit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <utility>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/kernels/rank_select.h"
#include "ramtk/vision/sphere/detail/sphere_fit_internal.h"
#include "ramtk/vision/sphere/sphere_crlb.h"

namespace ramtk::vision {
namespace {

using sphere_internal::Candidate;
using sphere_internal::ForEachIndex;
using sphere_internal::GeometricFit;

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string Format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, a);
  return buf;
}

std::string FormatVec(const Eigen::Vector3d& v, const char* fmt) {
  return "(" + Format(fmt, v.x()) + ", " + Format(fmt, v.y()) + ", " + Format(fmt, v.z()) + ")";
}

// Per-point values (a thesis frame's cloud: 6.4 M) written and read only at the indices in use:
// its elements are left uninitialised (two 51 MB fills, serial, were ~16 ms of a thesis fit), and
// every read below is of an index written first (the active points for sigma, the points near
// the current candidate for sigma_n).
template <class T>
struct NoInit : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = NoInit<U>;
  };
  NoInit() = default;
  template <class U>
  NoInit(const NoInit<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
using PointValues = std::vector<double, NoInit<double>>;

// The elements i of `indices` with keep(i), in their order (tested in parallel, joined in order).
template <class Keep>
std::vector<int> KeepInOrder(const std::vector<int>& indices, Keep keep) {
  std::vector<char> kept(indices.size());
  ForEachIndex(indices.size(), [&](std::size_t k) { kept[k] = keep(indices[k]) ? 1 : 0; });
  std::vector<int> out;
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (kept[k]) out.push_back(indices[k]);
  return out;
}

// The sigma of a point's distance to the sphere surface (along the normal at the point).
struct NormalSigma {
  const std::vector<Eigen::Vector3f>& points;
  const PointValues& sigma;  // as given (or 1 when unweighted), at the active points
  const SphereFitOptions& options;
  bool along_sight;

  // `indices` distinct (each writes its own element).
  void Evaluate(const std::vector<int>& indices, const Eigen::Vector3d& centre, PointValues* out) const {
    ForEachIndex(indices.size(), [&](std::size_t k) {
      const int i = indices[k];
      if (!along_sight) {
        (*out)[i] = sigma[i];
        return;
      }
      const Eigen::Vector3d sight = (points[i].cast<double>() - options.viewpoint_mm).normalized();
      const Eigen::Vector3d normal = (points[i].cast<double>() - centre).normalized();
      const double c = sight.dot(normal);
      const double ratio = options.perpendicular_sigma_ratio;
      (*out)[i] = sigma[i] * std::sqrt(c * c + ratio * ratio * std::max(0.0, 1.0 - c * c));
    });
  }
};

// Robust (MAD) scale of the normalised residuals of `indices`.
double RobustScale(const std::vector<Eigen::Vector3f>& points, const PointValues& sigma_n,
                   const std::vector<int>& indices, const Eigen::Vector3d& centre, double radius) {
  std::vector<double> z(indices.size());
  ForEachIndex(indices.size(), [&](std::size_t k) {
    const int i = indices[k];
    z[k] = std::abs((points[i].cast<double>() - centre).norm() - radius) / sigma_n[i];
  });
  return 1.4826 * Median(std::move(z));
}

// The finite points' indices in order, with their sigma in *sigma_out (1 unweighted); InputError
// naming the first point whose sigma is not finite and > 0.
std::vector<int> ActivePoints(const std::vector<Eigen::Vector3f>& points, const std::vector<float>& sigma_mm,
                              bool weighted, PointValues* sigma_out) {
  PointValues& sigma = *sigma_out;
  const int n = static_cast<int>(points.size());
  std::vector<int> active;
  active.reserve(points.size());
  // The finite points in order, in parallel chunks joined in order; a bad sigma is reported at
  // its first index, as one pass would.
  constexpr int kChunk = 1 << 16;
  const int chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<int>> chunk_active(chunks);
  std::vector<int> first_bad(chunks, -1);
  tbb::parallel_for(0, chunks, [&](int c) {
    const int end = std::min(n, (c + 1) * kChunk);
    chunk_active[c].reserve(static_cast<std::size_t>(end - c * kChunk));
    for (int i = c * kChunk; i < end; ++i) {
      if (!points[i].allFinite()) continue;
      if (weighted) {
        if (!(std::isfinite(sigma_mm[i]) && sigma_mm[i] > 0)) {
          first_bad[c] = i;
          return;
        }
        sigma[i] = sigma_mm[i];
      } else {
        sigma[i] = 1.0;
      }
      chunk_active[c].push_back(i);
    }
  });
  for (int c = 0; c < chunks; ++c) {
    if (first_bad[c] >= 0) {
      const int i = first_bad[c];
      throw InputError({"", 0, "sigma_mm[" + std::to_string(i) + "]"},
                       "must be finite and > 0, got " + std::to_string(sigma_mm[i]));
    }
    active.insert(active.end(), chunk_active[c].begin(), chunk_active[c].end());
  }
  std::vector<std::vector<int>>().swap(chunk_active);
  return active;
}

// The active points' median sigma (0 unweighted).
double MedianSigma(const std::vector<float>& sigma_mm, const std::vector<int>& active, bool weighted) {
  // The element nth_element would put in the middle, from a parallel histogram of the float
  // sigmas (rank_select.h): of all of them when every point is active (a scan's cloud), else of
  // the active points' copy.
  double median_sigma = 0;
  if (weighted && !active.empty()) {
    std::vector<float> subset;
    if (active.size() != sigma_mm.size())
      for (int i : active) subset.push_back(sigma_mm[i]);
    const std::vector<float>& s = subset.empty() ? sigma_mm : subset;
    median_sigma = detail::ValuesAtRanks(s, {s.size() / 2})[0];
  }
  return median_sigma;
}

// The active points near `candidate`, in order: those within `band` of it (*in_band) and those
// within 5 band (*near).
void PointsNear(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& active, const Candidate& candidate,
                double band, std::vector<int>* in_band_out, std::vector<int>* near_out) {
  constexpr int kChunk = 1 << 16;
  std::vector<int>& in_band = *in_band_out;
  std::vector<int>& near = *near_out;
  // The RANSAC band and a wider shell the robust fit sorts out, in parallel chunks of the active
  // list, joined in order.
  const int count = static_cast<int>(active.size());
  const int parts = (count + kChunk - 1) / kChunk;
  std::vector<std::vector<int>> part_near(parts), part_band(parts);
  tbb::parallel_for(0, parts, [&](int c) {
    const int end = std::min(count, (c + 1) * kChunk);
    sphere_internal::SplitByDistance(points, active.data() + c * kChunk, end - c * kChunk, candidate.centre,
                                     candidate.radius, 5 * band, band, &part_near[c], &part_band[c]);
  });
  for (int c = 0; c < parts; ++c) {
    near.insert(near.end(), part_near[c].begin(), part_near[c].end());
    in_band.insert(in_band.end(), part_band[c].begin(), part_band[c].end());
  }
}

// The inliers seen within max_view_angle_deg of the sphere's normal from the viewpoint, in order
// (along_ray: the normal where the point's ray meets the sphere).
std::vector<int> SeenInliers(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& inliers,
                             const GeometricFit& rough, const SphereFitOptions& options, bool along_ray) {
  const double min_cos = std::cos(options.max_view_angle_deg * M_PI / 180.0);
  std::vector<int> kept = KeepInOrder(inliers, [&](int i) {
    const Eigen::Vector3d sight = (points[i].cast<double>() - options.viewpoint_mm).normalized();
    Eigen::Vector3d normal = (points[i].cast<double>() - rough.centre).normalized();
    if (along_ray) {
      // The angle where the point's ray meets the sphere: it depends on the ray only, not on
      // how far along it the noise put the point. A cut on the noisy point's own normal keeps
      // points by the sign of their noise near the limit, which biased the fit (+17 um radius
      // in SphereFitAlongRay.*).
      const Eigen::Vector3d w = rough.centre - options.viewpoint_mm;
      const double b = sight.dot(w);
      const double disc = b * b - w.squaredNorm() + rough.radius * rough.radius;
      if (disc <= 0) return false;  // the ray misses the sphere: grazing
      normal = (options.viewpoint_mm + (b - std::sqrt(disc)) * sight - rough.centre).normalized();
    }
    return -sight.dot(normal) >= min_cos;
  });
  return kept;
}

// The fit's figures at its solution: RMS, worst residual, variance factor, covariance.
void SetFitFigures(const std::vector<Eigen::Vector3f>& points, const PointValues& sigma, const PointValues& sigma_n,
                   const std::vector<int>& inliers, const GeometricFit& fit, const SphereFitOptions& options,
                   bool weighted, bool along_ray, SphereResult* result_out) {
  SphereResult& result = *result_out;
  const int num_params = options.fix_radius ? 3 : 4;
  // Normal matrix J^T W J at the solution; residual derivative wrt (c, R) is -(u, 1) / sigma.
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  double chi2 = 0, sum_r2 = 0, worst = 0;
  for (int i : inliers) {
    const Eigen::Vector3d d = points[i].cast<double>() - fit.centre;
    const double dist = d.norm();
    const double r = dist - fit.radius;
    Eigen::Vector4d g = Eigen::Vector4d(d.x() / dist, d.y() / dist, d.z() / dist, 1.0) / sigma_n[i];
    double z = r / sigma_n[i];
    if (along_ray)
      z = sphere_internal::AlongRayResidual(points[i].cast<double>(), sigma[i], options.viewpoint_mm, fit.centre,
                                            fit.radius, &g);
    normal.noalias() += g * g.transpose();
    chi2 += z * z;
    sum_r2 += r * r;
    worst = std::max(worst, std::abs(r));
  }
  result.rms_mm = std::sqrt(sum_r2 / static_cast<double>(inliers.size()));
  result.worst_mm = worst;
  result.variance_factor = chi2 / static_cast<double>(inliers.size() - num_params);
  const double factor = (options.scale_covariance || !weighted) ? result.variance_factor : 1.0;
  if (options.fix_radius) {
    result.centre_covariance_mm2 = normal.topLeftCorner<3, 3>().inverse() * factor;
  } else {
    const Eigen::Matrix4d cov = normal.inverse() * factor;
    result.centre_covariance_mm2 = cov.topLeftCorner<3, 3>();
    result.radius_sigma_mm = std::sqrt(std::max(0.0, cov(3, 3)));
  }
}

// The Cramér–Rao bound on the final fit's points at the fitted sphere (SphereResult::crlb_*).
void SetCrlb(const std::vector<Eigen::Vector3f>& points, const std::vector<float>& sigma_mm,
             const SphereFitOptions& options, SphereResult* result) {
  SphereCrlbOptions co;
  co.noise_model = options.noise_model;
  co.viewpoint_mm = options.viewpoint_mm;
  co.perpendicular_sigma_ratio = options.perpendicular_sigma_ratio;
  co.fix_radius = options.fix_radius;
  const SphereCrlb crlb =
      SphereCramerRao(points, sigma_mm, result->inlier_indices, result->centre_mm, result->radius_mm, co);
  if (!crlb.valid) return;
  result->crlb_centre_sigma_mm = crlb.CentreSigma();
  result->crlb_radius_sigma_mm = crlb.radius_sigma_mm;
}

}  // namespace

std::string SphereFitOptions::Validate() const {
  std::string problem;  // the first one
  auto Require = [&problem](bool ok, const char* field, const std::string& message) {
    if (!ok && problem.empty()) problem = std::string(field) + ": " + message;
  };
  Require(std::isfinite(radius_mm) && radius_mm >= 0, "radius_mm", "must be >= 0 (0 = unknown)");
  Require(!fix_radius || radius_mm > 0, "fix_radius", "needs radius_mm > 0");
  Require(std::isfinite(radius_tolerance_mm) && radius_tolerance_mm > 0, "radius_tolerance_mm", "must be > 0");
  Require(std::isfinite(min_radius_mm) && min_radius_mm > 0, "min_radius_mm", "must be > 0");
  Require(std::isfinite(max_radius_mm) && max_radius_mm > min_radius_mm, "max_radius_mm", "must be > min_radius_mm");
  Require(std::isfinite(inlier_threshold_mm) && inlier_threshold_mm >= 0, "inlier_threshold_mm",
          "must be >= 0 (0 = automatic)");
  Require(max_spheres >= 1, "max_spheres", "must be >= 1");
  Require(min_points >= 5, "min_points", "must be >= 5 (a sphere has 4 parameters)");
  Require(std::isfinite(robust_loss_scale) && robust_loss_scale > 0, "robust_loss_scale", "must be > 0");
  Require(std::isfinite(outlier_threshold) && outlier_threshold >= 1, "outlier_threshold", "must be >= 1");
  Require(max_iterations >= 1, "max_iterations", "must be >= 1");
  Require(min_iterations >= 0 && min_iterations <= max_iterations, "min_iterations", "must be in [0, max_iterations]");
  Require(confidence > 0 && confidence < 1, "confidence", "must be in (0, 1)");
  Require(max_scoring_points >= 100, "max_scoring_points", "must be >= 100");
  Require(viewpoint_mm.allFinite(), "viewpoint_mm", "must be finite");
  Require(std::isfinite(perpendicular_sigma_ratio) && perpendicular_sigma_ratio > 0 && perpendicular_sigma_ratio <= 1,
          "perpendicular_sigma_ratio", "must be in (0, 1]");
  Require(std::isfinite(max_view_angle_deg) && max_view_angle_deg >= 0 && max_view_angle_deg <= 90,
          "max_view_angle_deg", "must be in [0, 90] (0 = off)");
  Require(max_robust_points >= 100, "max_robust_points", "must be >= 100");
  Require(max_solver_iterations >= 1, "max_solver_iterations", "must be >= 1");
  return problem;
}

Eigen::Vector3d SphereResult::CentreSigma() const { return centre_covariance_mm2.diagonal().cwiseMax(0).cwiseSqrt(); }

SphereFitSummary FindSpheres(const std::vector<Eigen::Vector3f>& points_mm, const std::vector<float>& sigma_mm,
                             const SphereFitOptions& options) {
  ThrowIfInvalid(options.Validate(), "SphereFitOptions");
  const bool weighted = !sigma_mm.empty();
  if (weighted && sigma_mm.size() != points_mm.size())
    throw InputError({"", 0, "sigma_mm"}, "has " + std::to_string(sigma_mm.size()) + " values for " +
                                              std::to_string(points_mm.size()) + " points");
  SphereFitSummary summary;
  summary.input_points = static_cast<int>(points_mm.size());
  // The points are read as given (float; each use casts to double, exactly): a double copy of
  // a thesis frame's 6.4 M points was 150 MB.
  const std::vector<Eigen::Vector3f>& points = points_mm;
  PointValues sigma(points_mm.size());  // set at the active points below
  std::vector<int> active = ActivePoints(points, sigma_mm, weighted, &sigma);

  double radius_lo = options.min_radius_mm, radius_hi = options.max_radius_mm;
  if (options.radius_mm > 0) {
    radius_lo = std::max(0.1 * options.radius_mm, options.radius_mm - options.radius_tolerance_mm);
    radius_hi = options.radius_mm + options.radius_tolerance_mm;
  }
  // The points' median sigma (once: a thesis frame has 6.4 M points).
  const double median_sigma = MedianSigma(sigma_mm, active, weighted);
  double band = options.inlier_threshold_mm;
  if (band <= 0) {
    band = weighted ? 5.0 * median_sigma : 0.1;
    band = std::max(band, 1e-3);
  }
  summary.inlier_threshold_mm = band;
  // Floor of the robust scale: residuals of 1 nm are as good as exact (noise-free data).
  const double sigma_median = weighted ? std::max(median_sigma, 1e-12) : 1.0;
  const double min_scale = 1e-6 / sigma_median;
  const bool along_ray = weighted && options.noise_model == PointNoiseModel::kAlongRay;
  const NormalSigma normal_sigma{points, sigma, options,
                                 weighted && options.noise_model != PointNoiseModel::kIsotropic};
  PointValues sigma_n(points.size());  // set at the points near each candidate (Evaluate)
  std::mt19937_64 rng(options.seed);

  while (static_cast<int>(summary.spheres.size()) < options.max_spheres) {
    const Candidate candidate =
        sphere_internal::FindCandidate(points, active, band, radius_lo, radius_hi, options, rng);
    if (!candidate.found) {
      summary.no_sphere_reason = candidate.reason;
      break;
    }
    if (candidate.inliers < options.min_points) {
      summary.no_sphere_reason = "best candidate (radius " + Format("%.3f", candidate.radius) + " mm) has " +
                                 std::to_string(candidate.inliers) + " points within " + Format("%.4f", band) +
                                 " mm, fewer than min_points " + std::to_string(options.min_points);
      break;
    }
    std::vector<int> in_band, near;
    PointsNear(points, active, candidate, band, &in_band, &near);
    double radius0 = options.fix_radius ? options.radius_mm : candidate.radius;
    normal_sigma.Evaluate(near, candidate.centre, &sigma_n);
    double scale = std::max(RobustScale(points, sigma_n, in_band, candidate.centre, candidate.radius), min_scale);
    const bool robust = options.loss != SphereLoss::kNone;
    // The robust pass only starts and classifies: a strided subset of at most max_robust_points.
    std::vector<int> subset = robust ? near : in_band;
    if (static_cast<int>(subset.size()) > options.max_robust_points) {
      const double step = static_cast<double>(subset.size()) / options.max_robust_points;
      std::vector<int> thinned;
      for (int k = 0; k < options.max_robust_points; ++k) thinned.push_back(subset[static_cast<size_t>(k * step)]);
      subset.swap(thinned);
    }
    const GeometricFit rough = sphere_internal::FitGeometric(
        points, sigma_n.data(), subset, candidate.centre, radius0, options.fix_radius, options.loss,
        options.robust_loss_scale * scale, options.max_solver_iterations, false);
    // Classify with the robust scale at the robust solution.
    normal_sigma.Evaluate(near, rough.centre, &sigma_n);
    scale = std::max(RobustScale(points, sigma_n, near, rough.centre, rough.radius), min_scale);
    std::vector<int> inliers = KeepInOrder(near, [&](int i) {
      return std::abs((points[i].cast<double>() - rough.centre).norm() - rough.radius) / sigma_n[i] <=
             options.outlier_threshold * scale;
    });
    if (static_cast<int>(inliers.size()) < options.min_points) {
      summary.no_sphere_reason = "the robust fit keeps " + std::to_string(inliers.size()) +
                                 " points, fewer than min_points " + std::to_string(options.min_points);
      break;
    }
    // Grazing points (seen nearly edge-on from the viewpoint) stay out of the final fit; they
    // still belong to this sphere (removed from the search for the next one).
    const std::vector<int> classified = inliers;
    int grazing = 0;
    if (options.max_view_angle_deg > 0) {
      std::vector<int> kept = SeenInliers(points, inliers, rough, options, along_ray);
      grazing = static_cast<int>(inliers.size() - kept.size());
      if (static_cast<int>(kept.size()) < options.min_points) {
        summary.no_sphere_reason = "only " + std::to_string(kept.size()) + " of the sphere's points are seen within " +
                                   Format("%.0f", options.max_view_angle_deg) +
                                   " deg of the normal, fewer than min_points " + std::to_string(options.min_points);
        break;
      }
      inliers.swap(kept);
    }
    // Final: weighted least squares on the inliers (distances along the normal, or along the rays).
    const GeometricFit fit =
        along_ray ? sphere_internal::FitAlongRay(points, sigma.data(), inliers, options.viewpoint_mm, rough.centre,
                                                 rough.radius, options.fix_radius, options.max_solver_iterations)
                  : sphere_internal::FitGeometric(points, sigma_n.data(), inliers, rough.centre, rough.radius,
                                                  options.fix_radius, SphereLoss::kNone, 1.0,
                                                  options.max_solver_iterations, true);
    if (!fit.converged) {
      RAMTK_LOG(kWarning) << "sphere fit: Ceres did not report convergence";
    }

    SphereResult result;
    result.centre_mm = fit.centre;
    result.radius_mm = fit.radius;
    result.num_points = static_cast<int>(inliers.size());
    result.num_outliers = static_cast<int>(near.size() - classified.size());
    result.num_grazing = grazing;
    result.robust_scale = scale;
    result.ransac_iterations = candidate.iterations;
    result.solver_iterations = fit.iterations;
    result.initial_cost = fit.initial_cost;
    result.final_cost = fit.final_cost;
    SetFitFigures(points, sigma, sigma_n, inliers, fit, options, weighted, along_ray, &result);
    result.inlier_indices = inliers;
    if (weighted) SetCrlb(points, sigma_mm, options, &result);
    // Remove this sphere's inliers and look for the next.
    std::vector<char> used(points.size(), 0);
    for (int i : classified) used[i] = 1;
    active.erase(std::remove_if(active.begin(), active.end(), [&](int i) { return used[i] != 0; }), active.end());
    summary.spheres.push_back(std::move(result));
    if (options.progress &&
        !options.progress({"sphere fit", summary.spheres.size(), static_cast<size_t>(options.max_spheres)})) {
      summary.termination = Termination::kCancelled;
      summary.message = "cancelled";
      break;
    }
  }
  summary.unassigned_points = static_cast<int>(active.size());
  if (summary.termination != Termination::kCancelled) {
    if (summary.spheres.empty()) {
      summary.termination = Termination::kNoResult;
      summary.message = "no sphere found";
    } else if (static_cast<int>(summary.spheres.size()) < options.max_spheres) {
      summary.termination = Termination::kPartial;
      summary.message = "partial";
    }
  }
  return summary;
}

std::string SphereFitSummary::BriefReport() const {
  std::string out;
  if (spheres.empty()) {
    out = "no sphere found (" + std::to_string(input_points) + " points): " + no_sphere_reason;
    return out;
  }
  out = std::to_string(spheres.size()) + (spheres.size() == 1 ? " sphere" : " spheres");
  for (size_t k = 0; k < spheres.size(); ++k) {
    const SphereResult& s = spheres[k];
    out += (k == 0 ? ": " : "; ") + std::string("centre ") + FormatVec(s.centre_mm, "%.4f") + " mm ± " +
           FormatVec(s.CentreSigma() * 1000.0, "%.2f") + " um, radius " + Format("%.4f", s.radius_mm) + " mm";
    if (s.radius_sigma_mm > 0) out += " ± " + Format("%.2f", s.radius_sigma_mm * 1000.0) + " um";
    out += ", rms " + Format("%.2f", s.rms_mm * 1000.0) + " um, " + std::to_string(s.num_points) + " points, " +
           std::to_string(s.num_outliers) + " outliers";
  }
  if (spheres.size() >= 2) {
    const CentreDistance d = ComputeCentreDistance(spheres[0], spheres[1]);
    out += "; centre distance " + Format("%.4f", d.distance_mm) + " ± " + Format("%.2f", d.sigma_mm * 1000.0) + " um";
  }
  if (!no_sphere_reason.empty() && termination != Termination::kSuccess)
    out += " (" + message + ": " + no_sphere_reason + ")";
  return out;
}

CentreDistance ComputeCentreDistance(const SphereResult& a, const SphereResult& b) {
  const Eigen::Vector3d d = a.centre_mm - b.centre_mm;
  CentreDistance out;
  out.distance_mm = d.norm();
  if (out.distance_mm > 0) {
    const Eigen::Vector3d u = d / out.distance_mm;
    out.sigma_mm = std::sqrt(std::max(0.0, u.dot((a.centre_covariance_mm2 + b.centre_covariance_mm2) * u)));
  } else {
    // Zero distance: the first-order sigma is undefined; report the larger centre sigma.
    out.sigma_mm = std::sqrt(std::max((a.centre_covariance_mm2 + b.centre_covariance_mm2).diagonal().maxCoeff(), 0.0));
  }
  return out;
}

}  // namespace ramtk::vision
