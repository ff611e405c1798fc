// Sphere fit against truth: closed-form spheres (exact points -> error at machine precision),
// synthetic caps of a 38.1 mm ball seen from 700 mm with anisotropic noise, a backdrop plane and
// outliers (error against the simulated truth), known vs free radius, a ball bar, no-sphere and
// too-few-points cases, bad input and the JSON result.

#include "ramtk/vision/sphere/sphere_fit.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>

#include "ramtk/vision/sphere/detail/sphere_fit_internal.h"  // AlongRayResidual, FitGeometric
#include "ramtk/core/error.h"
#include "sphere_synth.h"

namespace ramtk::vision {
namespace {

using test::CapScene;
using test::MakeCapCloud;
using test::SynthCloud;

SphereFitOptions BallOptions(const SynthCloud& cloud) {
  SphereFitOptions o;
  o.radius_mm = 19.05;
  o.noise_model = PointNoiseModel::kAlongLineOfSight;
  o.viewpoint_mm = cloud.viewpoint;
  o.perpendicular_sigma_ratio = 0.25;
  return o;
}

TEST(SphereThroughFourPoints, ClosedFormRecoversTheSphere) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  const Eigen::Vector3d centre(12.5, -40.25, 701.0);
  const double radius = 19.05;
  Eigen::Vector3d p[4];
  for (auto& x : p) x = centre + radius * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  Eigen::Vector3d c;
  double r = 0;
  ASSERT_TRUE(SphereThroughFourPoints(p[0], p[1], p[2], p[3], &c, &r));
  EXPECT_LT((c - centre).norm(), 1e-10);
  EXPECT_NEAR(r, radius, 1e-10);
  // Four coplanar points have no sphere.
  EXPECT_FALSE(SphereThroughFourPoints({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, &c, &r));
}

// Integer points on a sphere of integer radius about an integer centre are exact in float:
// a noise-free cap, fitted free and with known radius, must come back to rounding error.
TEST(FindSpheres, ExactIntegerCapToMachinePrecision) {
  const Eigen::Vector3d centre(100, -50, 700);
  const int radius = 45;  // 261 integer points on the half sphere
  std::vector<Eigen::Vector3f> points;
  for (int x = -radius; x <= radius; ++x)
    for (int y = -radius; y <= radius; ++y)
      for (int z = -radius; z <= 0; ++z)  // the half facing the camera (z towards it is negative)
        if (x * x + y * y + z * z == radius * radius)
          points.push_back((centre + Eigen::Vector3d(x, y, z)).cast<float>());
  ASSERT_EQ(points.size(), 261u);
  for (bool fix : {false, true}) {
    SphereFitOptions o;
    o.radius_mm = radius + 0.5;  // a prior, not the truth
    o.radius_tolerance_mm = 1.0;
    o.min_points = 50;
    if (fix) o.radius_mm = radius;
    o.fix_radius = fix;
    const SphereFitSummary s = FindSpheres(points, {}, o);
    ASSERT_EQ(s.spheres.size(), 1u) << s.BriefReport();
    EXPECT_LT((s.spheres[0].centre_mm - centre).norm(), 1e-9) << "fix_radius " << fix;
    EXPECT_NEAR(s.spheres[0].radius_mm, radius, 1e-9);
    EXPECT_EQ(s.spheres[0].num_points, static_cast<int>(points.size()));
    EXPECT_LT(s.spheres[0].rms_mm, 1e-9);
  }
}

TEST(FindSpheres, NoisyCapWithBackdropAndOutliersMatchesTruth) {
  const CapScene scene;
  const SynthCloud cloud = MakeCapCloud(scene, 11);
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, BallOptions(cloud));
  ASSERT_EQ(s.spheres.size(), 1u) << s.BriefReport();
  const SphereResult& r = s.spheres[0];
  const Eigen::Vector3d err = r.centre_mm - scene.centre;
  const Eigen::Vector3d sig = r.CentreSigma();
  // Within 4 predicted sigma per axis, and the sigmas are micrometre-level (noise 5..30 um).
  for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(err[k]), 4 * sig[k]) << "axis " << k << " " << s.BriefReport();
  EXPECT_LT(sig.maxCoeff(), 0.005);
  EXPECT_LT(std::abs(r.radius_mm - scene.radius), 4 * r.radius_sigma_mm);
  // The honest sigmas give a variance factor near 1.
  EXPECT_NEAR(r.variance_factor, 1.0, 0.15);
  // Inliers: nearly every true sphere point, and no backdrop, spike or outlier point.
  // (A uniform outlier may land within the 4-sigma shell: ~0.4 expected, allow 2.)
  int true_in = 0;
  for (int i : r.inlier_indices) true_in += cloud.on_sphere[i];
  EXPECT_LE(r.num_points - true_in, 2);
  EXPECT_GT(r.num_points, 0.99 * cloud.sphere_points);
  EXPECT_GT(r.num_outliers, 0);  // the spikes near the surface
}

TEST(FindSpheres, KnownRadiusTightensTheCentreAlongTheSight) {
  const CapScene scene;
  const SynthCloud cloud = MakeCapCloud(scene, 12);
  SphereFitOptions free_radius = BallOptions(cloud);
  SphereFitOptions known = free_radius;
  known.fix_radius = true;
  const SphereFitSummary a = FindSpheres(cloud.points, cloud.sigma, free_radius);
  const SphereFitSummary b = FindSpheres(cloud.points, cloud.sigma, known);
  ASSERT_EQ(a.spheres.size(), 1u);
  ASSERT_EQ(b.spheres.size(), 1u);
  EXPECT_EQ(b.spheres[0].radius_mm, scene.radius);
  EXPECT_EQ(b.spheres[0].radius_sigma_mm, 0.0);
  // A cap fixes the centre along the sight line only together with the radius: the known radius
  // makes the depth sigma several times smaller, and the error stays within it.
  const double free_z = a.spheres[0].CentreSigma().z(), known_z = b.spheres[0].CentreSigma().z();
  EXPECT_LT(known_z, 0.5 * free_z);
  const Eigen::Vector3d err = b.spheres[0].centre_mm - scene.centre;
  for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(err[k]), 4 * b.spheres[0].CentreSigma()[k]);
  // A wrong known radius moves the centre along the sight line by about the radius error.
  SphereFitOptions wrong = known;
  wrong.radius_mm = scene.radius + 0.05;
  const SphereFitSummary c = FindSpheres(cloud.points, cloud.sigma, wrong);
  ASSERT_EQ(c.spheres.size(), 1u);
  EXPECT_GT((c.spheres[0].centre_mm - scene.centre).z(), 0.03);
}

TEST(FindSpheres, BallBarCentreDistance) {
  CapScene scene;
  scene.centre = Eigen::Vector3d(100, 0, 700);
  Eigen::Vector3d ca, cb;
  const double length = 150.0;
  const SynthCloud cloud = test::MakeBallBarCloud(scene, length, Eigen::Vector3d(1, 0.3, 0.2), 21, &ca, &cb);
  SphereFitOptions o = BallOptions(cloud);
  o.max_spheres = 2;
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
  ASSERT_EQ(s.spheres.size(), 2u) << s.BriefReport();
  EXPECT_EQ(s.termination, Termination::kSuccess);
  // Match found spheres to the truth by proximity.
  const SphereResult& a = (s.spheres[0].centre_mm - ca).norm() < 1 ? s.spheres[0] : s.spheres[1];
  const SphereResult& b = (s.spheres[0].centre_mm - ca).norm() < 1 ? s.spheres[1] : s.spheres[0];
  EXPECT_LT((a.centre_mm - ca).norm(), 0.01);
  EXPECT_LT((b.centre_mm - cb).norm(), 0.01);
  const CentreDistance d = ComputeCentreDistance(a, b);
  EXPECT_GT(d.sigma_mm, 0);
  EXPECT_LT(d.sigma_mm, 0.005);
  EXPECT_LT(std::abs(d.distance_mm - length), 4 * d.sigma_mm) << s.BriefReport();
  // No point is claimed by both spheres.
  std::vector<int> seen(cloud.points.size(), 0);
  for (const SphereResult& r : s.spheres)
    for (int i : r.inlier_indices) EXPECT_EQ(seen[i]++, 0);
}

// Points of a sphere seen from the origin on a grid of viewing angles; those beyond 60 deg are
// pushed 50 um inward (a grazing-angle depth bias). With max_view_angle_deg = 60 they leave the
// final fit, which is then exact; without it the centre moves along the line of sight.
TEST(FindSpheres, ViewAngleCutDropsGrazingPoints) {
  const Eigen::Vector3d centre(3, -2, 700);
  const double radius = 19.05;
  std::vector<Eigen::Vector3f> points;
  int beyond = 0;
  const Eigen::Vector3d to_camera = -centre.normalized();
  const Eigen::Vector3d e1 = to_camera.cross(Eigen::Vector3d::UnitX()).normalized(), e2 = to_camera.cross(e1);
  for (int i = 0; i < 40; ++i)      // polar angle from the direction to the camera, 1..79 deg
    for (int k = 0; k < 72; ++k) {  // azimuth
      const double polar = (1 + 2 * i) * M_PI / 180, azimuth = k * 5 * M_PI / 180;
      const Eigen::Vector3d n =
          std::cos(polar) * to_camera + std::sin(polar) * (std::cos(azimuth) * e1 + std::sin(azimuth) * e2);
      Eigen::Vector3d p = centre + radius * n;
      const double view = std::acos(-n.dot(p.normalized())) * 180 / M_PI;
      // Stay clear of the threshold, where float rounding decides.
      if (std::abs(view - 60) < 0.5) continue;
      if (view > 60) p -= 0.05 * n, ++beyond;
      points.push_back(p.cast<float>());
    }
  SphereFitOptions o;
  o.radius_mm = radius;
  o.inlier_threshold_mm = 0.2;
  o.loss = SphereLoss::kNone;
  o.max_view_angle_deg = 60;
  const SphereFitSummary cut = FindSpheres(points, {}, o);
  ASSERT_EQ(cut.spheres.size(), 1u);
  EXPECT_EQ(cut.spheres[0].num_grazing, beyond);
  EXPECT_LT((cut.spheres[0].centre_mm - centre).norm(), 1e-5);  // float storage of the points
  EXPECT_NEAR(cut.spheres[0].radius_mm, radius, 1e-5);
  o.max_view_angle_deg = 0;
  const SphereFitSummary all = FindSpheres(points, {}, o);
  ASSERT_EQ(all.spheres.size(), 1u);
  EXPECT_EQ(all.spheres[0].num_grazing, 0);
  EXPECT_GT((all.spheres[0].centre_mm - centre).norm(), 0.005);
}

TEST(FindSpheres, PlaneAndClutterAloneIsNoSphere) {
  CapScene scene;
  SynthCloud cloud;
  std::mt19937_64 rng(3);
  test::AddBackdrop({scene}, rng, &cloud);
  std::uniform_real_distribution<double> u(-40, 40);
  for (int k = 0; k < 2000; ++k)
    cloud.points.push_back((scene.centre + Eigen::Vector3d(u(rng), u(rng), u(rng))).cast<float>());
  cloud.sigma.assign(cloud.points.size(), 0.02f);
  SphereFitOptions o = BallOptions(cloud);
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
  EXPECT_TRUE(s.spheres.empty()) << s.BriefReport();
  EXPECT_EQ(s.termination, Termination::kNoResult);
  EXPECT_FALSE(s.no_sphere_reason.empty());
  // The plane alone: no 4-point sample gives a sphere anywhere near the prior radius.
  SynthCloud plane;
  test::AddBackdrop({scene}, rng, &plane);
  for (auto& p : plane.points) p.z() = static_cast<float>(scene.centre.z() + 60);  // exactly flat
  const SphereFitSummary t = FindSpheres(plane.points, {}, o);
  EXPECT_TRUE(t.spheres.empty());
  EXPECT_NE(t.no_sphere_reason.find("no candidate sphere with radius in"), std::string::npos) << t.no_sphere_reason;
}

TEST(FindSpheres, TooFewPointsIsNoSphere) {
  CapScene scene;
  scene.pitch_mm = 3.0;  // a sparse cap: about 100 points
  scene.backdrop = false;
  const SynthCloud cloud = MakeCapCloud(scene, 5);
  ASSERT_LT(cloud.sphere_points, 200);
  ASSERT_GT(cloud.sphere_points, 40);
  SphereFitOptions o = BallOptions(cloud);
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
  EXPECT_TRUE(s.spheres.empty());
  EXPECT_NE(s.no_sphere_reason.find("fewer than min_points 200"), std::string::npos) << s.no_sphere_reason;
  EXPECT_NE(s.BriefReport().find("no sphere found"), std::string::npos);
  // With a lower threshold the same points give the right sphere.
  o.min_points = 30;
  const SphereFitSummary t = FindSpheres(cloud.points, cloud.sigma, o);
  ASSERT_EQ(t.spheres.size(), 1u) << t.BriefReport();
  EXPECT_LT((t.spheres[0].centre_mm - scene.centre).norm(), 0.05);
}

TEST(FindSpheres, UnweightedFitEstimatesTheNoiseLevel) {
  CapScene scene;
  scene.sigma_min_mm = scene.sigma_max_mm = 0.02;
  scene.perpendicular_ratio = 1.0;  // isotropic noise of 20 um
  const SynthCloud cloud = MakeCapCloud(scene, 9);
  SphereFitOptions o;
  o.radius_mm = 19.05;
  o.inlier_threshold_mm = 0.1;
  const SphereFitSummary s = FindSpheres(cloud.points, {}, o);
  ASSERT_EQ(s.spheres.size(), 1u) << s.BriefReport();
  // Without sigmas the covariance comes from the residual scatter: rms ~ 20 um.
  EXPECT_NEAR(s.spheres[0].rms_mm, 0.02, 0.002);
  const Eigen::Vector3d err = s.spheres[0].centre_mm - scene.centre;
  for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(err[k]), 4 * s.spheres[0].CentreSigma()[k]);
}

// The robust fit holds all residuals in one block, each r as sign(r) sqrt(rho(r^2)). Its cost is
// Ceres' robust cost with one block per point and the loss on each (the formulation it
// replaced), here with an autodiff residual. On the points within 2 mm of a noisy cap's surface
// (as FindSpheres hands the robust fit its candidate's shell: sphere points, spikes 0.2-1 mm
// off it, the outliers that fall there) both reach the same cost and the same centre and radius,
// for Huber and Cauchy, to 1 nm: a thousandth of the centre's sigma (~1 um), the scale of the
// solvers' stopping rules (1e-12 relative cost change).
struct PerPointResidual {
  PerPointResidual(const Eigen::Vector3d& p, double sigma) : p_(p), sigma_(sigma) {}
  template <typename T>
  bool operator()(const T* centre, const T* radius, T* residual) const {
    const T dx = T(p_.x()) - centre[0], dy = T(p_.y()) - centre[1], dz = T(p_.z()) - centre[2];
    residual[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz) - radius[0]) / T(sigma_);
    return true;
  }
  Eigen::Vector3d p_;
  double sigma_;
};

TEST(SphereFitRobust, OneBlockReachesCeresPerPointRobustMinimum) {
  const CapScene scene;
  const SynthCloud cloud = MakeCapCloud(scene, 5);
  std::vector<int> indices;
  for (int i = 0; i < static_cast<int>(cloud.points.size()); ++i)
    if (std::abs((cloud.points[i].cast<double>() - scene.centre).norm() - scene.radius) < 2.0) indices.push_back(i);
  ASSERT_GT(indices.size(), 1000u);
  ASSERT_LT(indices.size(), cloud.points.size());  // the backdrop is left out
  std::vector<double> sigma(cloud.sigma.begin(), cloud.sigma.end());
  const Eigen::Vector3d start = scene.centre + Eigen::Vector3d(0.3, -0.2, 0.4);
  const double start_radius = scene.radius + 0.2;
  for (const SphereLoss loss : {SphereLoss::kHuber, SphereLoss::kCauchy}) {
    const double scale = 3.0;
    const sphere_internal::GeometricFit one = sphere_internal::FitGeometric(
        cloud.points, sigma.data(), indices, start, start_radius, false, loss, scale, 200, true);
    double centre[3] = {start.x(), start.y(), start.z()}, radius = start_radius;
    ceres::Problem problem;
    for (int i : indices) {
      ceres::LossFunction* rho = loss == SphereLoss::kHuber
                                     ? static_cast<ceres::LossFunction*>(new ceres::HuberLoss(scale))
                                     : new ceres::CauchyLoss(scale);
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PerPointResidual, 1, 3, 1>(
                                   new PerPointResidual(cloud.points[i].cast<double>(), sigma[i])),
                               rho, centre, &radius);
    }
    ceres::Solver::Options o;
    o.linear_solver_type = ceres::DENSE_QR;
    o.max_num_iterations = 200;
    o.function_tolerance = 1e-14;
    o.parameter_tolerance = 1e-14;
    o.gradient_tolerance = 1e-16;
    ceres::Solver::Summary summary;
    ceres::Solve(o, &problem, &summary);
    const char* name = loss == SphereLoss::kHuber ? "Huber" : "Cauchy";
    EXPECT_LT((one.centre - Eigen::Vector3d(centre[0], centre[1], centre[2])).norm(), 1e-6) << name;
    EXPECT_NEAR(one.radius, radius, 1e-6) << name;
    EXPECT_NEAR(one.final_cost, summary.final_cost, 1e-9 * summary.final_cost) << name;
    // And both well away from the start: the outliers were down-weighted, not fitted.
    EXPECT_LT((one.centre - scene.centre).norm(), 0.01) << name;
  }
}

TEST(FindSpheres, BadInputNamesTheField) {
  std::vector<Eigen::Vector3f> points(10, Eigen::Vector3f::Zero());
  SphereFitOptions o;
  try {
    FindSpheres(points, std::vector<float>(9, 0.01f), o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "sigma_mm");
  }
  try {
    FindSpheres(points, std::vector<float>(10, -1.0f), o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "sigma_mm[0]");
  }
  {
    // The first bad sigma is named, also when the points are checked in parallel chunks (of
    // 65 536): two bad ones in later chunks, and a NaN point (skipped) before them.
    std::vector<Eigen::Vector3f> many(200000, Eigen::Vector3f(1, 2, 3));
    std::vector<float> sigma(many.size(), 0.01f);
    many[120000].x() = std::numeric_limits<float>::quiet_NaN();
    sigma[120000] = -1.0f;
    sigma[150001] = 0.0f;
    sigma[190000] = -2.0f;
    try {
      FindSpheres(many, sigma, SphereFitOptions{});
      FAIL();
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().field, "sigma_mm[150001]");
    }
  }
  o.fix_radius = true;  // without a radius
  try {
    FindSpheres(points, {}, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "fix_radius");
  }
  SphereFitOptions p;
  p.min_points = 3;
  EXPECT_EQ(SplitOptionsProblem(p.Validate()).field, "min_points");
  // Non-finite points are skipped, not fitted.
  const CapScene scene;
  SynthCloud cloud = MakeCapCloud(scene, 4);
  cloud.points.push_back(Eigen::Vector3f(NAN, 0, 700));
  cloud.sigma.push_back(0.01f);
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, BallOptions(cloud));
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_LT((s.spheres[0].centre_mm - scene.centre).norm(), 0.01);
}

TEST(SphereFitJson, CarriesTheResult) {
  CapScene scene;
  Eigen::Vector3d ca, cb;
  const SynthCloud cloud = test::MakeBallBarCloud(scene, 120.0, Eigen::Vector3d::UnitX(), 2, &ca, &cb);
  SphereFitOptions o = BallOptions(cloud);
  o.max_spheres = 2;
  const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
  ASSERT_EQ(s.spheres.size(), 2u);
  const auto path = std::filesystem::temp_directory_path() / "ramtk_sphere_fit_test.json";
  WriteSphereFitJson(path.string(), s, "left_camera");
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  std::filesystem::remove(path);
  EXPECT_EQ(j["format"], "ramtk-sphere-fit");
  EXPECT_EQ(j["frame"], "left_camera");
  ASSERT_EQ(j["spheres"].size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const auto& js = j["spheres"][k];
    const SphereResult& r = s.spheres[k];
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(js["centre_mm"][a].get<double>(), r.centre_mm[a]);
      for (int b = 0; b < 3; ++b)
        EXPECT_EQ(js["centre_covariance_mm2"][a][b].get<double>(), r.centre_covariance_mm2(a, b));
    }
    EXPECT_EQ(js["radius_mm"].get<double>(), r.radius_mm);
    EXPECT_EQ(js["rms_mm"].get<double>(), r.rms_mm);
    EXPECT_EQ(js["num_points"].get<int>(), r.num_points);
    EXPECT_EQ(js["num_outliers"].get<int>(), r.num_outliers);
    ASSERT_GT(r.crlb_centre_sigma_mm.minCoeff(), 0);  // the bound is computed by the fit
    for (int a = 0; a < 3; ++a) EXPECT_EQ(js["crlb_centre_sigma_mm"][a].get<double>(), r.crlb_centre_sigma_mm[a]);
    EXPECT_EQ(js["crlb_radius_sigma_mm"].get<double>(), r.crlb_radius_sigma_mm);
  }
  EXPECT_NEAR(j["centre_distances"][0]["distance_mm"].get<double>(), 120.0, 0.01);
  // The covariance is symmetric and positive definite.
  const Eigen::Matrix3d& cov = s.spheres[0].centre_covariance_mm2;
  EXPECT_LT((cov - cov.transpose()).norm(), 1e-15);
  EXPECT_GT(cov.llt().matrixL().toDenseMatrix().diagonal().minCoeff(), 0);
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

// A cap of the 38.1 mm ball as a coarse camera sees it (pixel rays from the left camera at the
// origin, 0.29 mm apart at 700 mm: the 2048x1536 rig of docs/scan.md), each point moved along its
// own ray by Gaussian noise of sigma 0.19 mm, as a triangulated point moves. Truth by construction.
std::vector<Eigen::Vector3f> NoisyRayCap(const Eigen::Vector3d& centre, double radius, double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3f> points;
  const double pitch = 0.29;
  for (double y = -radius; y <= radius; y += pitch)
    for (double x = -radius; x <= radius; x += pitch) {
      const Eigen::Vector3d u = Eigen::Vector3d(centre.x() + x, centre.y() + y, centre.z()).normalized();
      const double b = u.dot(centre);
      const double disc = b * b - centre.squaredNorm() + radius * radius;
      if (disc <= 0) continue;
      const double t = b - std::sqrt(disc) + sigma * gauss(rng);
      points.push_back((t * u).cast<float>());
    }
  return points;
}

// Noise along oblique rays biases a distance-along-the-normal fit: the cap leaves radius and the
// centre's depth nearly interchangeable, and the fit trades them (docs/scan.md: -24 um radius on
// the 2048 rig). Measuring each residual along the point's ray removes it. Mean over 30 seeds
// against truth; the gates are 3 standard errors of that mean (from the draws' own scatter).
TEST(SphereFitAlongRay, NoiseAlongTheRaysDoesNotBiasRadiusOrDepth) {
  const Eigen::Vector3d centre(0.0, 0.0, 700.0);
  const double radius = 19.05, sigma = 0.19;
  const int seeds = 30;
  std::vector<double> dz_ray, dr_ray, dz_normal, dr_normal;
  for (int s = 0; s < seeds; ++s) {
    const std::vector<Eigen::Vector3f> pts = NoisyRayCap(centre, radius, sigma, 100u + static_cast<unsigned>(s));
    const std::vector<float> sig(pts.size(), static_cast<float>(sigma));
    SphereFitOptions o;
    o.radius_mm = radius;
    o.viewpoint_mm = Eigen::Vector3d::Zero();
    o.perpendicular_sigma_ratio = 0.02;
    o.max_view_angle_deg = 60;  // as the scan fits
    o.noise_model = PointNoiseModel::kAlongRay;
    const SphereFitSummary a = FindSpheres(pts, sig, o);
    o.noise_model = PointNoiseModel::kAlongLineOfSight;
    const SphereFitSummary n = FindSpheres(pts, sig, o);
    ASSERT_EQ(a.spheres.size(), 1u);
    ASSERT_EQ(n.spheres.size(), 1u);
    dz_ray.push_back(a.spheres[0].centre_mm.z() - centre.z());
    dr_ray.push_back(a.spheres[0].radius_mm - radius);
    dz_normal.push_back(n.spheres[0].centre_mm.z() - centre.z());
    dr_normal.push_back(n.spheres[0].radius_mm - radius);
  }
  const auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); };
  const auto se = [&](const std::vector<double>& v) {
    const double m = mean(v);
    double ss = 0;
    for (double x : v) ss += (x - m) * (x - m);
    return std::sqrt(ss / (v.size() - 1) / v.size());
  };
  // Along the ray: unbiased within 3 standard errors.
  EXPECT_LT(std::abs(mean(dz_ray)), 3 * se(dz_ray)) << "z bias " << 1000 * mean(dz_ray) << " um";
  EXPECT_LT(std::abs(mean(dr_ray)), 3 * se(dr_ray)) << "radius bias " << 1000 * mean(dr_ray) << " um";
  // Along the normal: the bias this model exists for, far beyond its standard error (so the
  // scene is one where the choice matters).
  EXPECT_LT(mean(dr_normal), -5 * se(dr_normal)) << "radius bias " << 1000 * mean(dr_normal) << " um";
  EXPECT_LT(mean(dz_normal), -5 * se(dz_normal)) << "z bias " << 1000 * mean(dz_normal) << " um";
  std::printf(
      "along the ray: z %+.1f +- %.1f um, radius %+.1f +- %.1f um; along the normal: z %+.1f, radius %+.1f um\n",
      1000 * mean(dz_ray), 1000 * se(dz_ray), 1000 * mean(dr_ray), 1000 * se(dr_ray), 1000 * mean(dz_normal),
      1000 * mean(dr_normal));
}

// The along-ray residual's analytic gradient (it drives the fit and gives the covariance)
// against central differences, at points facing the viewpoint and near the limb.
TEST(SphereFitAlongRay, ResidualGradientMatchesCentralDifferences) {
  const Eigen::Vector3d v(10.0, -5.0, 0.0), c(0.5, 0.25, 700.0);
  const double sigma = 0.1, r = 19.05;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(3.0, -2.0, 684.0), Eigen::Vector3d(17.0, 1.0, 695.0), Eigen::Vector3d(-12.0, 9.0, 688.0)}) {
    Eigen::Vector4d g;
    sphere_internal::AlongRayResidual(p, sigma, v, c, r, &g);
    // Step 1e-4 mm: the residual subtracts two ~700 mm lengths (rounding ~1e-13 mm, ~1e-9
    // relative in the difference quotient); the truncation error h^2 f'''/6 grows near the limb,
    // where the root b - sqrt(disc) bends (~1e-7 relative at the third point).
    const double h = 1e-4;
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d cp = c, cm = c;
      double rp = r, rm = r;
      if (k < 3) {
        cp[k] += h;
        cm[k] -= h;
      } else {
        rp += h;
        rm -= h;
      }
      const double numeric = (sphere_internal::AlongRayResidual(p, sigma, v, cp, rp, nullptr) -
                              sphere_internal::AlongRayResidual(p, sigma, v, cm, rm, nullptr)) /
                             (2 * h);
      EXPECT_NEAR(g[k], numeric, 1e-6 * std::max(1.0, std::abs(numeric))) << "parameter " << k;
    }
  }
  // A point on the sphere along its ray has residual 0.
  const Eigen::Vector3d u = Eigen::Vector3d(1.0, 2.0, 700.0).normalized();
  const double b = u.dot(c - v);
  const double t = b - std::sqrt(b * b - (c - v).squaredNorm() + r * r);
  EXPECT_NEAR(sphere_internal::AlongRayResidual(v + t * u, sigma, v, c, r, nullptr), 0.0, 1e-9);
}

}  // namespace
}  // namespace ramtk::vision
