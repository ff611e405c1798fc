// Ray–sphere and ray–plane intersections against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ramtk/vision/sim/scene.h"

namespace ramtk::vision {
namespace {

TEST(SimScene, SphereOnAxisAndOffsetRays) {
  const Sphere ball{"ball", Vec3(0.0, 0.0, 700.0), 19.05, 0.8};
  // On axis: the front pole at 700 − r, the back pole from inside.
  EXPECT_NEAR(*IntersectSphere(ball, Vec3::Zero(), Vec3::UnitZ(), 0.0), 700.0 - 19.05, 1e-12);
  EXPECT_NEAR(*IntersectSphere(ball, Vec3(0, 0, 700), Vec3::UnitZ(), 0.0), 19.05, 1e-12);
  // A ray parallel to the axis at offset p meets the sphere at z = 700 − sqrt(r² − p²).
  for (double p : {0.0, 5.0, 19.0, 19.05 - 1e-9}) {
    const auto t = IntersectSphere(ball, Vec3(p, 0.0, 0.0), Vec3::UnitZ(), 0.0);
    ASSERT_TRUE(t.has_value()) << p;
    // The perpendicular-distance form stays accurate up to grazing (here the ray is exact in
    // floating point, so only rounding of r² − p² remains: ~1e-13 mm).
    EXPECT_NEAR(*t, 700.0 - std::sqrt(19.05 * 19.05 - p * p), 1e-9) << p;
  }
  EXPECT_FALSE(IntersectSphere(ball, Vec3(19.06, 0.0, 0.0), Vec3::UnitZ(), 0.0).has_value());
  EXPECT_FALSE(IntersectSphere(ball, Vec3::Zero(), -Vec3::UnitZ(), 0.0).has_value());  // behind
}

TEST(SimScene, RandomRaysHitTheSphereSurfaceAndNothingNearer) {
  const Sphere ball{"ball", Vec3(12.0, -7.0, 650.0), 19.05, 0.8};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> off(-25.0, 25.0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 target = ball.centre_in_left + Vec3(off(rng), off(rng), off(rng));
    const Vec3 dir = target.normalized();
    const auto t = IntersectSphere(ball, Vec3::Zero(), dir, 0.0);
    // Closed form: the ray misses iff its distance to the centre exceeds r.
    const double miss_distance = (ball.centre_in_left - ball.centre_in_left.dot(dir) * dir).norm();
    ASSERT_EQ(t.has_value(), miss_distance <= ball.radius) << i;
    if (!t) continue;
    ++hits;
    EXPECT_NEAR((*t * dir - ball.centre_in_left).norm(), ball.radius, 1e-9);
    // The entry point: the surface normal there faces the camera.
    EXPECT_LE((*t * dir - ball.centre_in_left).dot(dir), 1e-9);
  }
  EXPECT_GT(hits, 500);
}

TEST(SimScene, PlaneAndSceneOrder) {
  const Plane backdrop{"backdrop", Vec3(0, 0, 850), Vec3(0, 0.2, -1), 0.5};
  const Vec3 dir = Vec3(0.1, -0.05, 1.0).normalized();
  // Closed form: t = n·(p0 − o) / n·d.
  const Vec3 n = backdrop.normal_in_left.normalized();
  EXPECT_NEAR(*IntersectPlane(backdrop, Vec3::Zero(), dir, 0.0), n.dot(Vec3(0, 0, 850)) / n.dot(dir), 1e-12);
  EXPECT_FALSE(IntersectPlane({"wall", Vec3(0, 0, 850), Vec3(0, 0, -1), 0.5}, Vec3::Zero(), Vec3::UnitX(), 0.0));
  EXPECT_FALSE(IntersectPlane(backdrop, Vec3::Zero(), -dir, 0.0));  // behind the origin

  Scene scene;
  scene.spheres.push_back({"ball", Vec3(0, 0, 700), 19.05, 0.8});
  scene.planes.push_back(backdrop);
  const auto front = IntersectScene(scene, Vec3::Zero(), Vec3::UnitZ());
  ASSERT_TRUE(front);
  EXPECT_EQ(front->object, 0);
  EXPECT_NEAR(front->t, 700.0 - 19.05, 1e-12);
  EXPECT_NEAR((front->normal - Vec3(0, 0, -1)).norm(), 0.0, 1e-12);
  const auto side = IntersectScene(scene, Vec3::Zero(), Vec3(0.1, 0, 1).normalized());
  ASSERT_TRUE(side);
  EXPECT_EQ(side->object, 1);
  // The plane's normal is turned towards the ray's origin side.
  EXPECT_LT(side->normal.dot(Vec3(0.1, 0, 1)), 0.0);
  // A shadow ray from the backdrop behind the ball to the origin is blocked; beside it, not.
  EXPECT_TRUE(IsOccluded(scene, Vec3(0, 0, 850), -Vec3::UnitZ(), 1e-6, 850.0));
  EXPECT_FALSE(IsOccluded(scene, Vec3(0, 30, 850), Vec3(0, -30, -850).normalized(), 1e-6, 850.0));
}

}  // namespace
}  // namespace ramtk::vision
