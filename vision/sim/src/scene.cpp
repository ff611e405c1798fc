#include "ramtk/vision/sim/scene.h"

#include <cmath>

namespace ramtk::vision {

std::optional<double> IntersectSphere(const Sphere& s, const Vec3& origin, const Vec3& direction, double t_min) {
  const Vec3 oc = s.centre_in_left - origin;
  const double b = oc.dot(direction);    // distance to the closest approach
  const Vec3 perp = oc - b * direction;  // centre's offset from the ray
  const double h2 = s.radius * s.radius - perp.squaredNorm();
  if (h2 < 0.0) return std::nullopt;
  const double h = std::sqrt(h2);
  if (b - h > t_min) return b - h;
  if (b + h > t_min) return b + h;
  return std::nullopt;
}

std::optional<double> IntersectPlane(const Plane& p, const Vec3& origin, const Vec3& direction, double t_min) {
  const Vec3 n = p.normal_in_left.normalized();
  const double denom = n.dot(direction);
  if (denom == 0.0) return std::nullopt;
  const double t = n.dot(p.point_in_left - origin) / denom;
  if (!(t > t_min)) return std::nullopt;
  return t;
}

std::optional<RayHit> IntersectScene(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min,
                                     double t_max) {
  RayHit best;
  best.t = t_max;
  const int n_spheres = static_cast<int>(scene.spheres.size());
  for (int i = 0; i < n_spheres; ++i) {
    const auto t = IntersectSphere(scene.spheres[i], origin, direction, t_min);
    if (t && *t < best.t) {
      best.t = *t;
      best.object = i;
    }
  }
  for (int i = 0; i < static_cast<int>(scene.planes.size()); ++i) {
    const auto t = IntersectPlane(scene.planes[i], origin, direction, t_min);
    if (t && *t < best.t) {
      best.t = *t;
      best.object = n_spheres + i;
    }
  }
  if (best.object < 0) return std::nullopt;
  best.point = origin + best.t * direction;
  if (best.object < n_spheres) {
    const Sphere& s = scene.spheres[best.object];
    best.normal = (best.point - s.centre_in_left) / s.radius;
    best.albedo = s.albedo;
  } else {
    const Plane& p = scene.planes[best.object - n_spheres];
    best.normal = p.normal_in_left.normalized();
    best.albedo = p.albedo;
  }
  if (best.normal.dot(direction) > 0.0) best.normal = -best.normal;
  return best;
}

bool IsOccluded(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min, double t_max) {
  for (const Sphere& s : scene.spheres) {
    const auto t = IntersectSphere(s, origin, direction, t_min);
    if (t && *t < t_max) return true;
  }
  for (const Plane& p : scene.planes) {
    const auto t = IntersectPlane(p, origin, direction, t_min);
    if (t && *t < t_max) return true;
  }
  return false;
}

}  // namespace ramtk::vision
