// Camera–projector triangulation (vision/projector) against closed-form truth: points projected
// into a distorted camera and a distorted projector come back to 1e-6 mm (ray–plane and ray–ray),
// each point's sigma equals the finite-difference sensitivity of the truth's projection, and the
// calibration files (ramtk's layout, SLMaster's M1 D1 M4 D4 Rlp Tlp) read to their numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/vision/projector/projector_calibration.h"
#include "ramtk/vision/projector/projector_triangulate.h"

namespace ramtk::vision {
namespace {

ProjectorCalibration Rig() {
  ProjectorCalibration c;
  c.camera = {1750.0, 1748.0, 322.0, 251.0, {-0.07, -0.18, 2e-4, 5e-4, 0.3}, 640, 512};
  c.projector = {2500.0, 2496.0, 990.0, 547.0, {-0.04, -0.3, -7e-4, 1e-3, 0.5}, 1920, 1080};
  c.projector_from_camera.linear() = (Eigen::AngleAxisd(0.09, Vec3(0.05, 1, 0.01).normalized())).toRotationMatrix();
  c.projector_from_camera.translation() = Vec3(-108.0, -5.2, -15.7);
  return c;
}

// Maps of the camera's size, NaN everywhere, for coordinates and their sigma.
DecodedCamera EmptyMaps(const CameraIntrinsics& cam, double sigma_intensity = 2.0) {
  DecodedCamera d;
  d.coordinate = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  d.sigma_coordinate = d.coordinate.clone();
  d.modulation = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(40.0));
  d.summary.sigma_intensity_dn = sigma_intensity;
  return d;
}

struct TruthPoint {
  int x, y;
  Vec3 point;  // camera frame, mm
  Vec2 projector;
};

// Random camera pixels at random depths 500..900 mm, kept where the projector sees them.
std::vector<TruthPoint> TruthPoints(const ProjectorCalibration& c, int n) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ux(0, c.camera.width - 1), uy(0, c.camera.height - 1);
  std::uniform_real_distribution<double> uz(500, 900);
  std::vector<TruthPoint> out;
  cv::Mat used(c.camera.height, c.camera.width, CV_8U, cv::Scalar(0));
  while (static_cast<int>(out.size()) < n) {
    const int x = ux(rng), y = uy(rng);
    if (used.at<uchar>(y, x)) continue;
    const Vec3 ray = PixelRay(c.camera, Vec2(x, y));
    const Vec3 X = ray / ray.z() * uz(rng);
    const Vec2 p = ProjectPoint(c.projector, c.projector_from_camera * X);
    if (p.x() < 0 || p.y() < 0 || p.x() > c.projector.width - 1 || p.y() > c.projector.height - 1) continue;
    used.at<uchar>(y, x) = 1;
    out.push_back({x, y, X, p});
  }
  return out;
}

// The cloud's point at camera pixel (x, y), or NaNs.
Vec3 PointAt(const PointCloud& cloud, int x, int y, double* sigma = nullptr) {
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (cloud.left_pixels[i].x() == x && cloud.left_pixels[i].y() == y) {
      if (sigma) *sigma = cloud.sigma_mm[i];
      return cloud.points_in_left[i].cast<double>();
    }
  return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

TEST(ProjectorTriangulate, RayPlaneRecoversDistortedTruth) {
  const ProjectorCalibration c = Rig();
  const std::vector<TruthPoint> truth = TruthPoints(c, 300);
  for (FringeDirection dir : {FringeDirection::kVertical, FringeDirection::kHorizontal}) {
    DecodedCamera d = EmptyMaps(c.camera);
    for (const TruthPoint& t : truth) {
      d.coordinate.at<float>(t.y, t.x) =
          static_cast<float>(dir == FringeDirection::kVertical ? t.projector.x() : t.projector.y());
      d.sigma_coordinate.at<float>(t.y, t.x) = 0.1f;
    }
    ProjectorTriangulationSummary sum;
    cv::Mat depth;
    const PointCloud cloud = TriangulateProjectorPlanes(c, dir, d, {}, &sum, &depth);
    EXPECT_EQ(sum.coded_pixels, 300);
    EXPECT_EQ(sum.points, 300) << sum.BriefReport();
    double worst = 0;
    for (const TruthPoint& t : truth) {
      const Vec3 p = PointAt(cloud, t.x, t.y);
      // float coordinates (1e-4 px at 1920) and float points (6e-5 mm at 900 mm) bound the error
      worst = std::max(worst, (p - t.point).norm());
      EXPECT_NEAR(depth.at<float>(t.y, t.x), t.point.z(), 0.01);
    }
    EXPECT_LT(worst, 0.01) << FringeDirectionName(dir);
  }
}

TEST(ProjectorTriangulate, RayRayRecoversTruthAndRejectsDisagreement) {
  const ProjectorCalibration c = Rig();
  const std::vector<TruthPoint> truth = TruthPoints(c, 200);
  DecodedCamera u = EmptyMaps(c.camera), v = EmptyMaps(c.camera);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const TruthPoint& t = truth[i];
    u.coordinate.at<float>(t.y, t.x) = static_cast<float>(t.projector.x());
    // The last 20 rows disagree by 50 sigma: not a point of this ray.
    v.coordinate.at<float>(t.y, t.x) = static_cast<float>(t.projector.y() + (i >= 180 ? 5.0 : 0.0));
    u.sigma_coordinate.at<float>(t.y, t.x) = 0.1f;
    v.sigma_coordinate.at<float>(t.y, t.x) = 0.1f;
  }
  ProjectorTriangulationSummary sum;
  const PointCloud cloud = TriangulateProjectorPixels(c, u, v, {}, &sum);
  EXPECT_EQ(sum.points, 180);
  EXPECT_EQ(sum.rejected_residual, 20);
  for (std::size_t i = 0; i < 180; ++i) EXPECT_LT((PointAt(cloud, truth[i].x, truth[i].y) - truth[i].point).norm(), 0.01);
}

// sigma = |dX/du| sigma_u, dX/du from the truth's projection by central differences along the ray
// (independent of the solver's analytic derivative); ray–ray combines both directions'
// information, 1/sigma^2 = 1/sigma_u-only^2 + 1/sigma_v-only^2.
TEST(ProjectorTriangulate, SigmaIsTheFiniteDifferenceSensitivity) {
  const ProjectorCalibration c = Rig();
  const std::vector<TruthPoint> truth = TruthPoints(c, 50);
  DecodedCamera u = EmptyMaps(c.camera), v = EmptyMaps(c.camera);
  const double su = 0.2, sv = 0.3;
  for (const TruthPoint& t : truth) {
    u.coordinate.at<float>(t.y, t.x) = static_cast<float>(t.projector.x());
    v.coordinate.at<float>(t.y, t.x) = static_cast<float>(t.projector.y());
    u.sigma_coordinate.at<float>(t.y, t.x) = static_cast<float>(su);
    v.sigma_coordinate.at<float>(t.y, t.x) = static_cast<float>(sv);
  }
  const PointCloud cu = TriangulateProjectorPlanes(c, FringeDirection::kVertical, u, {});
  const PointCloud cv_ = TriangulateProjectorPlanes(c, FringeDirection::kHorizontal, v, {});
  const PointCloud cuv = TriangulateProjectorPixels(c, u, v, {});
  for (const TruthPoint& t : truth) {
    const Vec3 ray = t.point.normalized();
    const double h = 1e-3;  // mm along the ray
    const Vec2 pa = ProjectPoint(c.projector, c.projector_from_camera * (t.point - h * ray));
    const Vec2 pb = ProjectPoint(c.projector, c.projector_from_camera * (t.point + h * ray));
    const Vec2 dp = (pb - pa) / (2 * h);  // projector px per mm along the ray
    const double expect_u = su / std::abs(dp.x()), expect_v = sv / std::abs(dp.y());
    double s_u = 0, s_v = 0, s_uv = 0;
    PointAt(cu, t.x, t.y, &s_u);
    PointAt(cv_, t.x, t.y, &s_v);
    PointAt(cuv, t.x, t.y, &s_uv);
    EXPECT_NEAR(s_u / expect_u, 1.0, 1e-4);
    EXPECT_NEAR(s_v / expect_v, 1.0, 1e-4);
    EXPECT_NEAR(s_uv, 1.0 / std::sqrt(1.0 / (expect_u * expect_u) + 1.0 / (expect_v * expect_v)), 1e-4 * s_uv);
  }
}

TEST(ProjectorTriangulate, DepthRangeAndProjectorImageBoundTheCloud) {
  const ProjectorCalibration c = Rig();
  const std::vector<TruthPoint> truth = TruthPoints(c, 100);
  DecodedCamera d = EmptyMaps(c.camera);
  long near = 0;
  for (const TruthPoint& t : truth) {
    d.coordinate.at<float>(t.y, t.x) = static_cast<float>(t.projector.x());
    d.sigma_coordinate.at<float>(t.y, t.x) = 0.1f;
    near += t.point.z() < 700 ? 1 : 0;
  }
  ProjectorTriangulationOptions o;
  o.max_depth_mm = 700;
  ProjectorTriangulationSummary sum;
  TriangulateProjectorPlanes(c, FringeDirection::kVertical, d, o, &sum);
  EXPECT_EQ(sum.points, near);
  EXPECT_EQ(sum.rejected_geometry, 100 - near);
  // A projector too short for the rows the points fall on: every point is outside its image.
  ProjectorCalibration short_projector = c;
  short_projector.projector.height = 1;
  short_projector.projector.cy = -2000;
  TriangulateProjectorPlanes(short_projector, FringeDirection::kVertical, d, {}, &sum);
  EXPECT_EQ(sum.points, 0);
  o.max_depth_mm = 0;
  EXPECT_THROW(TriangulateProjectorPlanes(c, FringeDirection::kVertical, d, o), InputError);
}

constexpr const char* kSlmasterLayout = R"(%YAML:1.0
---
M1: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 1.7541123627841946e+03, 0., 6.4538474154275900e+02, 0.,
       1.7529027557721547e+03, 5.2949022809895587e+02, 0., 0., 1. ]
D1: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -7.1168430051385817e-02, -1.8504732992084422e-01,
       2.3178169769376712e-04, 5.5407654763752953e-04,
       1.8431788041215542e+00 ]
S: !!opencv-matrix
   rows: 2
   cols: 1
   dt: d
   data: [ 1280., 1024. ]
M4: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 2.4966331464214777e+03, 0., 9.9032167330402626e+02, 0.,
       2.4958149904072193e+03, 5.4700959472428224e+02, 0., 0., 1. ]
D4: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -4.2496386209949652e-02, -6.5992696789578686e-01,
       -6.8873531127175988e-04, 1.0583521629718045e-03,
       3.4566274542907882e+00 ]
Rlp: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 9.9592406128807542e-01, -9.6302285710377269e-03,
       8.9680113989308669e-02, 1.0052906594322801e-02,
       9.9994038256107221e-01, -4.2626743509623565e-03,
       -8.9633716962266213e-02, 5.1468457608616841e-03,
       9.9596149863448147e-01 ]
Tlp: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ -1.0818012009065924e+02, -5.1567303113233223e+00,
       -1.5731733622707548e+01 ]
)";

TEST(ProjectorCalibrationFile, ReadsSlmasterMonocularLayout) {
  const ProjectorCalibration c = ParseProjectorCalibration(kSlmasterLayout, "caliInfo.yml", 1920, 1024);
  EXPECT_EQ(c.camera.width, 1280);
  EXPECT_EQ(c.camera.height, 1024);
  EXPECT_DOUBLE_EQ(c.camera.fx, 1.7541123627841946e+03);
  EXPECT_DOUBLE_EQ(c.camera.distortion.k3, 1.8431788041215542e+00);
  EXPECT_DOUBLE_EQ(c.projector.fx, 2.4966331464214777e+03);
  EXPECT_DOUBLE_EQ(c.projector.cy, 5.4700959472428224e+02);
  EXPECT_DOUBLE_EQ(c.projector.distortion.k2, -6.5992696789578686e-01);
  EXPECT_EQ(c.projector.width, 1920);
  EXPECT_EQ(c.projector.height, 1024);
  EXPECT_DOUBLE_EQ(c.projector_from_camera.linear()(0, 2), 8.9680113989308669e-02);
  EXPECT_DOUBLE_EQ(c.projector_from_camera.linear()(2, 0), -8.9633716962266213e-02);
  EXPECT_DOUBLE_EQ(c.projector_from_camera.translation().x(), -1.0818012009065924e+02);
  // SLMaster's file has no projector resolution: without the manifest's it is an error.
  EXPECT_THROW(ParseProjectorCalibration(kSlmasterLayout, "caliInfo.yml"), InputError);
}

TEST(ProjectorCalibrationFile, RamtkLayoutRoundTrips) {
  const ProjectorCalibration c = Rig();
  const std::string path = ::testing::TempDir() + "/projector_calibration.yml";
  WriteProjectorCalibration(path, c);
  const ProjectorCalibration r = ReadProjectorCalibration(path);
  EXPECT_EQ(r.projector.width, 1920);
  EXPECT_EQ(r.projector.height, 1080);
  EXPECT_NEAR(r.projector.distortion.k3, 0.5, 1e-15);
  EXPECT_NEAR(r.camera.cx, 322.0, 1e-12);
  EXPECT_TRUE(r.projector_from_camera.isApprox(c.projector_from_camera, 1e-14));
}

}  // namespace
}  // namespace ramtk::vision
