// The Cramér–Rao bound of the sphere centre (sphere_crlb.h): closed forms for evenly spread
// points on a full sphere and a hemisphere, and a Monte-Carlo check that the along-ray fit's
// scatter on noisy synthetic caps reaches the bound (efficiency ~ 1 for the ML fit).

#include "ramtk/vision/sphere/sphere_crlb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "ramtk/vision/sphere/sphere_fit.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

// n unit normals evenly spread (Fibonacci lattice) over the cap z >= z_min of the unit sphere:
// z uniform in [z_min, 1] is uniform in area.
std::vector<Eigen::Vector3d> FibonacciNormals(int n, double z_min) {
  std::vector<Eigen::Vector3d> out;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1 - (1 - z_min) * (k + 0.5) / n;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    out.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  return out;
}

std::vector<Eigen::Vector3f> OnSphere(const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& c, double r) {
  std::vector<Eigen::Vector3f> p;
  for (const Eigen::Vector3d& n : normals) p.push_back((c + r * n).cast<float>());
  return p;
}

TEST(SphereCrlb, FullSphereIsotropicIsThreeSigmaSquaredOverN) {
  const int n = 4000;
  const double sigma = 0.01, radius = 12.7;
  const Eigen::Vector3d c(5, -3, 400);
  const std::vector<Eigen::Vector3f> pts = OnSphere(FibonacciNormals(n, -1), c, radius);
  SphereCrlbOptions o;
  o.noise_model = PointNoiseModel::kIsotropic;
  const SphereCrlb b = SphereCramerRao(pts, std::vector<float>(n, sigma), {}, c, radius, o);
  ASSERT_TRUE(b.valid);
  EXPECT_EQ(b.num_points, n);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(b.centre_covariance_mm2(a, a), 3 * sigma * sigma / n, 0.01 * 3 * sigma * sigma / n);
  EXPECT_NEAR(b.radius_sigma_mm, sigma / std::sqrt(n), 0.01 * sigma / std::sqrt(n));
  // A correlation factor scales the covariance.
  o.correlation_factor = 2.5;
  const SphereCrlb b2 = SphereCramerRao(pts, std::vector<float>(n, sigma), {}, c, radius, o);
  EXPECT_NEAR(b2.centre_covariance_mm2(1, 1), 2.5 * b.centre_covariance_mm2(1, 1), 1e-12);
}

TEST(SphereCrlb, HemisphereClosedForm) {
  // Per point F = [n n^T, n; n^T, 1] / sigma^2 averaged over the hemisphere z >= 0:
  // <nx^2> = <nz^2> = 1/3, <nz> = 1/2, so var(cx) = 3 s^2/N, var(cz) = (1/(1/3 - 1/4)) s^2/N =
  // 12 s^2/N, var(R) = (1/3)/(1/12) s^2/N = 4 s^2/N; with the radius known var(cz) = 3 s^2/N.
  const int n = 5000;
  const double sigma = 0.004, radius = 19.05, s2n = sigma * sigma / n;
  const Eigen::Vector3d c(0, 0, 700);
  const std::vector<Eigen::Vector3f> pts = OnSphere(FibonacciNormals(n, 0), c, radius);
  const std::vector<float> sig(n, sigma);
  SphereCrlbOptions o;
  o.noise_model = PointNoiseModel::kIsotropic;
  const SphereCrlb b = SphereCramerRao(pts, sig, {}, c, radius, o);
  ASSERT_TRUE(b.valid);
  EXPECT_NEAR(b.centre_covariance_mm2(0, 0), 3 * s2n, 0.02 * 3 * s2n);
  EXPECT_NEAR(b.centre_covariance_mm2(1, 1), 3 * s2n, 0.02 * 3 * s2n);
  EXPECT_NEAR(b.centre_covariance_mm2(2, 2), 12 * s2n, 0.02 * 12 * s2n);
  EXPECT_NEAR(b.radius_sigma_mm * b.radius_sigma_mm, 4 * s2n, 0.02 * 4 * s2n);
  o.fix_radius = true;
  const SphereCrlb f = SphereCramerRao(pts, sig, {}, c, radius, o);
  ASSERT_TRUE(f.valid);
  EXPECT_NEAR(f.centre_covariance_mm2(2, 2), 3 * s2n, 0.02 * 3 * s2n);
  EXPECT_EQ(f.radius_sigma_mm, 0);
  // Seen along the axis from far away with noise along the sight line only and across-ratio 1,
  // the noise is isotropic: the same bound.
  o.fix_radius = false;
  o.noise_model = PointNoiseModel::kAlongLineOfSight;
  o.perpendicular_sigma_ratio = 1;
  o.viewpoint_mm = Eigen::Vector3d(0, 0, 1e7);
  const SphereCrlb s = SphereCramerRao(pts, sig, {}, c, radius, o);
  EXPECT_NEAR(s.centre_covariance_mm2(2, 2), b.centre_covariance_mm2(2, 2), 1e-6 * b.centre_covariance_mm2(2, 2));
}

TEST(SphereCrlb, DegenerateAndInvalidInputs) {
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 10}, {10, 0, 0}, {0, 10, 0}};
  SphereCrlbOptions o;
  EXPECT_FALSE(SphereCramerRao(pts, {0.01f, 0.01f, 0.01f}, {}, Eigen::Vector3d::Zero(), 10, o).valid);
  EXPECT_THROW(SphereCramerRao(pts, {0.01f}, {}, Eigen::Vector3d::Zero(), 10, o), std::exception);
  o.correlation_factor = 0.5;
  EXPECT_NE(o.Validate(), "");
}

// A cap of the ball seen from a camera at the origin, each point displaced along its ray by its
// sigma times a standard normal (the scan's noise model), sigma growing toward the limb.
struct Cap {
  std::vector<Eigen::Vector3f> truth_points;
  std::vector<float> sigma;
};
Cap MakeCap(const Eigen::Vector3d& c, double radius) {
  Cap cap;
  for (const Eigen::Vector3d& n : FibonacciNormals(12000, -1)) {
    const Eigen::Vector3d p = c + radius * n;
    const double cos_view = -n.dot(p.normalized());
    if (cos_view < std::cos(60 * kPi / 180)) continue;
    cap.truth_points.push_back(p.cast<float>());
    cap.sigma.push_back(static_cast<float>(0.01 / cos_view));
  }
  return cap;
}

TEST(SphereCrlb, AlongRayFitReachesTheBound) {
  const Eigen::Vector3d c(10, -5, 500);
  const double radius = 19.05;
  const Cap cap = MakeCap(c, radius);
  ASSERT_GT(cap.truth_points.size(), 1000u);
  SphereCrlbOptions co;  // kAlongRay from the origin
  const SphereCrlb bound = SphereCramerRao(cap.truth_points, cap.sigma, {}, c, radius, co);
  ASSERT_TRUE(bound.valid);
  const int draws = 200;
  std::mt19937_64 rng(20261129);
  std::normal_distribution<double> gauss(0, 1);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), ms = Eigen::Vector3d::Zero();
  double radius_ms = 0;
  Eigen::Vector3d reported = Eigen::Vector3d::Zero();
  int fitted = 0;
  for (int k = 0; k < draws; ++k) {
    std::vector<Eigen::Vector3f> pts = cap.truth_points;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d p = pts[i].cast<double>();
      pts[i] = (p + cap.sigma[i] * gauss(rng) * p.normalized()).cast<float>();
    }
    SphereFitOptions o;
    o.radius_mm = radius;
    o.noise_model = PointNoiseModel::kAlongRay;
    o.seed = static_cast<uint64_t>(k) + 1;
    const SphereFitSummary s = FindSpheres(pts, cap.sigma, o);
    ASSERT_EQ(s.spheres.size(), 1u) << s.BriefReport();
    const SphereResult& r = s.spheres[0];
    const Eigen::Vector3d e = r.centre_mm - c;
    mean += e / draws;
    ms += e.cwiseAbs2() / draws;
    radius_ms += std::pow(r.radius_mm - radius, 2) / draws;
    reported += r.crlb_centre_sigma_mm / draws;
    ++fitted;
  }
  ASSERT_EQ(fitted, draws);
  const Eigen::Vector3d observed = ms.cwiseSqrt(), crlb = bound.CentreSigma();
  // A standard deviation from `draws` Gaussian draws scatters by 1/sqrt(2 draws) = 5%: 4 of those.
  const double tol = 4 / std::sqrt(2.0 * draws);
  std::printf("CRLB centre sigma (%.3f, %.3f, %.3f) um, observed (%.3f, %.3f, %.3f) um, radius %.3f vs %.3f um\n",
              1e3 * crlb.x(), 1e3 * crlb.y(), 1e3 * crlb.z(), 1e3 * observed.x(), 1e3 * observed.y(),
              1e3 * observed.z(), 1e3 * bound.radius_sigma_mm, 1e3 * std::sqrt(radius_ms));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(observed[a] / crlb[a], 1.0, tol) << "axis " << a;
    // Unbiased: the mean error within 4 standard errors.
    EXPECT_LT(std::abs(mean[a]), 4 * crlb[a] / std::sqrt(draws)) << "axis " << a;
    // The fit reports the bound at its own solution: within a few percent of the bound at the truth.
    EXPECT_NEAR(reported[a] / crlb[a], 1.0, 0.02) << "axis " << a;
  }
  EXPECT_NEAR(std::sqrt(radius_ms) / bound.radius_sigma_mm, 1.0, tol);
  // The cap is seen along +z: the centre is worst determined along the line of sight.
  EXPECT_GT(crlb.z(), 1.5 * crlb.x());
}

}  // namespace
}  // namespace ramtk::vision
