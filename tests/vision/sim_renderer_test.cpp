// Rendered images against truth the renderer did not produce: a flat Lambertian plane against the
// closed-form irradiance (and the projector's frustum), the decoded projector coordinate on the ball
// against the analytic ray–sphere hit projected into the projector, and the silhouette area
// against the analytic projection of the sphere's tangent cone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ramtk/vision/sim/fringe_renderer.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

CameraIntrinsics IdealCamera(int width, int height, double f) {
  return {f, f, (width - 1) / 2.0, (height - 1) / 2.0, {}, width, height};
}

// A phase-shift frame whose value is 1 − O(1e-10) everywhere: a "white" projector image.
std::vector<PatternFrame> WhiteFrame() {
  std::vector<PatternFrame> frames = ExpandSequence({PhaseShiftBlock(3, 1e-6, 0.0)});
  frames.resize(1);
  return frames;
}

// Pinhole projection without distortion, written out here (independent of ProjectPoint).
Vec2 PinholePixel(const CameraIntrinsics& k, const Isometry3& view_from_left, const Vec3& x_in_left) {
  const Vec3 p = view_from_left.linear() * x_in_left + view_from_left.translation();
  return {k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy};
}

TEST(SimRenderer, FlatLambertianPlaneMatchesClosedForm) {
  const FringeSimulationConfig preset = MakeFringePreset("small");
  Scene scene;
  scene.planes.push_back({"plane", Vec3(0, 0, 700), Vec3(0, 0, -1), 0.6});
  PinholeView camera{IdealCamera(200, 160, 400.0), Isometry3::Identity()};
  // A narrow projector (f = 3000 px) so that the camera also sees the plane outside its image.
  PinholeView projector{{3000.0, 3000.0, 455.5, 569.5, {}, 912, 1140}, preset.projector.view_from_left};
  RenderOptions options;
  options.ambient = 0.1;
  const RenderedView view = RenderView(scene, camera, projector, WhiteFrame(), options);
  const Vec3 projector_centre = projector.view_from_left.inverse().translation();
  // One camera pixel covers 1.75 mm on the plane ≈ 7.5 projector pixels; pixels within 8 projector
  // pixels of the projector image border are partly lit and skipped.
  const double margin = 8.0;
  int lit = 0, unlit = 0;
  for (int v = 0; v < 160; ++v) {
    for (int u = 0; u < 200; ++u) {
      const Vec3 x(700.0 * (u - camera.intrinsics.cx) / 400.0, 700.0 * (v - camera.intrinsics.cy) / 400.0, 700.0);
      const Vec2 p = PinholePixel(projector.intrinsics, projector.view_from_left, x);
      const double inside = std::min({p.x() + 0.5, 911.5 - p.x(), p.y() + 0.5, 1139.5 - p.y()});
      const double radiance = view.radiance[0].at<float>(v, u);
      if (inside > margin) {
        const double cosine = Vec3(0, 0, -1).dot((projector_centre - x).normalized());
        // Pixel mean vs centre value: the second-order variation of cos θ over 1.75 mm at
        // ~700 mm is ~1e-7; float32 storage ~6e-8.
        EXPECT_NEAR(radiance, 0.6 * (0.1 + cosine), 1e-6) << u << "," << v;
        EXPECT_NEAR(view.projector_x.at<float>(v, u), p.x(), 2e-4);  // float32 of ~500 px
        ++lit;
      } else if (inside < -margin) {
        EXPECT_NEAR(radiance, 0.6 * 0.1, 1e-7) << u << "," << v;
        EXPECT_TRUE(std::isnan(view.projector_x.at<float>(v, u)));
        ++unlit;
      }
      EXPECT_NEAR(view.depth.at<float>(v, u), 700.0, 1e-4);
    }
  }
  EXPECT_GT(lit, 5000);
  EXPECT_GT(unlit, 5000);
}

TEST(SimRenderer, DecodedProjectorCoordinateOnTheBallMatchesAnalyticHit) {
  FringeSimulationConfig config = MakeFringePreset("small");
  config.cameras.left.distortion = {};  // ideal pinhole: the analytic ray below needs no undistortion
  const std::vector<PatternFrame> frames = ExpandSequence({PhaseShiftBlock(4, 64.0)});
  const PinholeView camera{config.cameras.left, Isometry3::Identity()};
  for (const FringeDirection orientation : {FringeDirection::kVertical, FringeDirection::kHorizontal}) {
    const bool vertical = orientation == FringeDirection::kVertical;
    SCOPED_TRACE(vertical ? "vertical fringes" : "horizontal fringes");
    RenderOptions options;
    options.supersampling = 4;
    options.direction = orientation;
    const RenderedView view = RenderView(config.scene, camera, config.projector, frames, options);
    SensorOptions sensor;
    sensor.bits = 16;
    sensor.noise = false;
    std::vector<cv::Mat> images;
    for (const cv::Mat& r : view.radiance) images.push_back(ApplySensor(r, 1.0, sensor, 1, 0));

    const Sphere& ball = config.scene.spheres[0];
    const CameraIntrinsics& k = camera.intrinsics;
    const double u0 = std::round(k.fx * ball.centre_in_left.x() / ball.centre_in_left.z() + k.cx);
    const double v0 = std::round(k.fy * ball.centre_in_left.y() / ball.centre_in_left.z() + k.cy);
    int checked = 0;
    double worst = 0.0;
    for (int dv = -75; dv <= 75; dv += 25) {  // within 0.83 r of the ball centre (r ≈ 128 px)
      for (int du = -75; du <= 75; du += 25) {
        const int u = static_cast<int>(u0) + du, v = static_cast<int>(v0) + dv;
        // Analytic first hit of the pixel-centre ray: t = b − sqrt(r² − |c|² + b²).
        const Vec3 d = Vec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).normalized();
        const double b = d.dot(ball.centre_in_left);
        const double disc = ball.radius * ball.radius - ball.centre_in_left.squaredNorm() + b * b;
        ASSERT_GT(disc, 0.0);
        const Vec3 x = (b - std::sqrt(disc)) * d;
        const Vec2 p = PinholePixel(config.projector.intrinsics, config.projector.view_from_left, x);
        ASSERT_EQ(view.lit_fraction.at<float>(v, u), 1.0f);
        EXPECT_NEAR(view.projector_x.at<float>(v, u), p.x(), 1e-4);
        EXPECT_NEAR(view.projector_y.at<float>(v, u), p.y(), 1e-4);
        EXPECT_NEAR(view.depth.at<float>(v, u), x.z(), 1e-4);
        // Least-squares phase of I_k = A + B cos(φ + 2πk/N), unwrapped with the true period.
        double s = 0.0, c = 0.0;
        for (int i = 0; i < 4; ++i) {
          const double value = images[i].at<std::uint16_t>(v, u);
          s += value * std::sin(2 * kPi * i / 4);
          c += value * std::cos(2 * kPi * i / 4);
        }
        const double period = (vertical ? 912.0 : 1140.0) / 64.0;
        const double phase = std::atan2(-s, c);
        const double true_phase = 2 * kPi * (vertical ? p.x() : p.y()) / period - kPi;  // φ0 = −π
        const double wrapped_error = std::remainder(phase - true_phase, 2 * kPi);
        const double error_px = wrapped_error * period / (2 * kPi);
        // Budget: 16-bit quantisation gives σφ ≈ 1e-5 rad (2e-5 projector px); the n×n pixel mean
        // of cos φ is unbiased for a locally linear φ; the curvature of φ across a pixel on the ball
        // biases it by ~5e-5 px near the centre, a few 1e-4 px at 0.8 r towards the limb.
        EXPECT_NEAR(error_px, 0.0, 1e-3) << u << "," << v;
        worst = std::max(worst, std::abs(error_px));
        ++checked;
      }
    }
    EXPECT_EQ(checked, 49);
    RecordProperty(vertical ? "worst_projector_px_error" : "worst_projector_px_error_horizontal",
                   std::to_string(worst));
  }
}

// Semi-axes in the normalised image plane of the tangent cone of a sphere whose centre is at angle
// θ from the optical axis and subtends half-angle α: a = sinα cosα / (cos²θ − sin²α),
// b = sinα / sqrt(cos²θ − sin²α).
double ConeEllipseAreaPx(const Vec3& centre, double radius, double f) {
  const double alpha = std::asin(radius / centre.norm());
  const double theta = std::acos(centre.z() / centre.norm());
  const double denom = std::pow(std::cos(theta), 2) - std::pow(std::sin(alpha), 2);
  const double a = std::sin(alpha) * std::cos(alpha) / denom;
  const double b = std::sin(alpha) / std::sqrt(denom);
  return kPi * a * b * f * f;
}

TEST(SimRenderer, SilhouetteAreaMatchesConeProjection) {
  const double f = 1000.0;
  PinholeView camera{IdealCamera(640, 512, f), Isometry3::Identity()};
  // A projector facing away: the ball is only lit by the ambient term, so radiance = albedo ×
  // the fraction of the pixel the ball covers.
  PinholeView projector{{1000.0, 1000.0, 455.5, 569.5, {}, 912, 1140}, Isometry3::Identity()};
  projector.view_from_left.linear() = Vec3(-1.0, 1.0, -1.0).asDiagonal();
  RenderOptions options;
  options.ambient = 1.0;
  options.supersampling = 4;
  for (const Vec3& centre : {Vec3(0.0, 0.0, 400.0), Vec3(60.0, -45.0, 380.0)}) {
    Scene scene;
    scene.spheres.push_back({"ball", centre, 19.05, 0.8});
    const RenderedView view = RenderView(scene, camera, projector, WhiteFrame(), options);
    const double area = cv::sum(view.radiance[0])[0] / 0.8;
    const double expected = ConeEllipseAreaPx(centre, 19.05, f);
    const double radius_px = std::sqrt(expected / kPi);
    // Mean displacement of the edge = area difference / perimeter (≈ 2π × equivalent radius).
    // A 4×4 sample lattice estimates the area of a smooth convex shape of ~50 px radius to a few
    // px² (lattice-point counting), i.e. an edge error of ~0.01 px; the issue asks for ~0.1 px.
    const double edge_error_px = (area - expected) / (2 * kPi * radius_px);
    EXPECT_NEAR(edge_error_px, 0.0, 0.02) << "centre " << centre.transpose() << " radius " << radius_px;
    RecordProperty("edge_error_px_" + std::to_string(static_cast<int>(centre.x())), std::to_string(edge_error_px));
  }
}

TEST(SimRenderer, ProjectorShadowsAndCameraOcclusionMatchClosedForm) {
  // One ray per pixel (supersampling 1): every backdrop pixel is either in the ball's shadow
  // (ambient only) or lit (ambient + cos θ), decided here in closed form: does the segment from
  // the backdrop point to the projector centre pass within r of the ball centre?
  FringeSimulationConfig config = MakeFringePreset("small");
  const CameraIntrinsics k = IdealCamera(320, 256, 2350.0);  // the small preset at half resolution
  const Vec3 projector_centre = config.projector.view_from_left.inverse().translation();
  const Sphere& ball = config.scene.spheres[0];
  RenderOptions options;
  options.ambient = 0.05;
  options.supersampling = 1;
  const RenderedView view =
      RenderView(config.scene, {k, Isometry3::Identity()}, config.projector, WhiteFrame(), options);
  auto distance_to_centre = [&](const Vec3& from, const Vec3& to) {  // segment–point distance
    const Vec3 d = (to - from).normalized();
    const double t = std::clamp(d.dot(ball.centre_in_left - from), 0.0, (to - from).norm());
    return (from + t * d - ball.centre_in_left).norm();
  };
  int shadowed = 0, lit = 0, on_ball = 0;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Vec3 ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Vec3 x = ray * 850.0;  // backdrop z = 850
      const double camera_miss = distance_to_centre(Vec3::Zero(), x) - ball.radius;
      if (std::abs(camera_miss) < 1e-6) continue;  // tangent rays: either answer is right
      if (camera_miss < 0) {
        EXPECT_EQ(view.object_id.at<int>(v, u), 0);
        ++on_ball;
        continue;
      }
      ASSERT_EQ(view.object_id.at<int>(v, u), 1);
      const double projector_miss = distance_to_centre(x, projector_centre) - ball.radius;
      if (std::abs(projector_miss) < 1e-6) continue;
      const double radiance = view.radiance[0].at<float>(v, u);
      if (projector_miss < 0) {
        EXPECT_NEAR(radiance, 0.5 * 0.05, 1e-7) << u << "," << v;
        ++shadowed;
      } else {
        const double cosine = Vec3(0, 0, -1).dot((projector_centre - x).normalized());
        EXPECT_NEAR(radiance, 0.5 * (0.05 + cosine), 1e-6) << u << "," << v;
        ++lit;
      }
    }
  }
  EXPECT_GT(shadowed, 1000);
  EXPECT_GT(lit, 1000);
  EXPECT_GT(on_ball, 1000);
}

}  // namespace
}  // namespace ramtk::vision

namespace ramtk::vision {
namespace {

TEST(SimRenderer, SlmasterSequenceDecodesToTheTrueProjectorColumn) {
  // The preset's 12-step phase shift (64 periods, φ0 = −π) and 7-image complementary Gray code,
  // noiseless 16-bit, decoded here with the textbook complementary-Gray-code rule; every clean
  // pixel must land on the analytic projector column of its pixel-centre ray (the truth image is
  // checked against the closed form in the tests above). This pins the Gray code to the phase.
  FringeSimulationConfig config = MakeFringePreset("small");
  config.sensor.bits = 16;
  config.sensor.noise = false;
  const SimulatedCamera sim = SimulateCamera(config, 0);
  ASSERT_EQ(sim.images.size(), 19u);
  const double L = 912.0, cycles = 64.0;
  int clean = 0, order_errors = 0;
  double worst = 0.0, worst_near_limb = 0.0;
  const Sphere& ball = config.scene.spheres[0];
  const Vec2 ball_px = ProjectPoint(config.cameras.left, ball.centre_in_left);
  const double ball_radius_px = config.cameras.left.fx * std::tan(std::asin(ball.radius / ball.centre_in_left.norm()));
  for (int v = 0; v < 512; ++v) {
    for (int u = 0; u < 640; ++u) {
      if (sim.truth.lit_fraction.at<float>(v, u) != 1.0f) continue;
      double s = 0.0, c = 0.0, mean = 0.0;
      for (int k = 0; k < 12; ++k) {
        const double value = sim.images[k].at<std::uint16_t>(v, u);
        s += value * std::sin(2 * kPi * k / 12);
        c += value * std::cos(2 * kPi * k / 12);
        mean += value / 12.0;
      }
      const double psi = std::fmod(std::atan2(-s, c) + kPi + 4 * kPi, 2 * kPi);  // φ − φ0 in [0, 2π)
      int gray = 0;
      for (int i = 0; i < 7; ++i) gray = (gray << 1) | (sim.images[12 + i].at<std::uint16_t>(v, u) > mean ? 1 : 0);
      int k2 = 0;  // Gray → binary
      for (int g = gray; g; g >>= 1) k2 ^= g;
      const int k1 = k2 >> 1;
      int k;
      if (psi <= kPi / 2) {
        k = (k2 + 1) / 2;
      } else if (psi >= 3 * kPi / 2) {
        k = (k2 + 1) / 2 - 1;
      } else {
        k = k1;
      }
      const double column = (psi + 2 * kPi * k) * L / (2 * kPi * cycles);
      const double error = column - sim.truth.projector_x.at<float>(v, u);
      ++clean;
      if (std::abs(error) > 0.5 * L / cycles) {
        ++order_errors;
      } else {
        // Towards the ball's limb the projector column varies non-linearly across a pixel, and the
        // pixel mean of the fringe no longer decodes to its centre ray's column (up to ~0.1 px at
        // the limb): the bound applies away from it.
        const double from_centre = (Vec2(u, v) - ball_px).norm();
        if (from_centre < 0.85 * ball_radius_px || from_centre > ball_radius_px + 3.0) {
          worst = std::max(worst, std::abs(error));
        } else {
          worst_near_limb = std::max(worst_near_limb, std::abs(error));
        }
      }
    }
  }
  EXPECT_GT(clean, 100000);
  EXPECT_EQ(order_errors, 0);
  // Noiseless: only the pixel-mean curvature bias (≲ 1e-3 px, see the 4-step test) and 16-bit
  // rounding remain.
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(worst_near_limb, 0.25);
  RecordProperty("slmaster_sequence_worst_px", std::to_string(worst));
  RecordProperty("slmaster_sequence_worst_near_limb_px", std::to_string(worst_near_limb));
}

}  // namespace
}  // namespace ramtk::vision
