#pragma once
// A scene of spheres and planes for the fringe renderer, in the left-camera frame (mm), and ray
// intersection against it.

#include <optional>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"

namespace ramtk::vision {

// A matte (Lambertian) sphere, e.g. the 38.1 mm precision ball on the robot flange.
struct Sphere {
  std::string name;                    // label written to the ground truth, e.g. "ball"
  Vec3 centre_in_left = Vec3::Zero();  // centre in the left-camera frame, mm
  double radius = 19.05;               // mm
  double albedo = 0.8;                 // diffuse reflectance in [0, 1]
};

// A matte infinite plane, e.g. a backdrop behind the ball. Both sides reflect.
struct Plane {
  std::string name;                     // label written to the ground truth
  Vec3 point_in_left = Vec3::Zero();    // any point on the plane, mm
  Vec3 normal_in_left = Vec3::UnitZ();  // normal (need not be unit length; normalised on use)
  double albedo = 0.5;                  // diffuse reflectance in [0, 1]
};

struct Scene {
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  // Objects are numbered spheres first, then planes: id = sphere index, or spheres.size() + plane
  // index.
  int ObjectCount() const { return static_cast<int>(spheres.size() + planes.size()); }
};

// The first surface a ray meets.
struct RayHit {
  double t = 0.0;              // distance along the (unit) ray direction, mm
  Vec3 point = Vec3::Zero();   // hit point, left-camera frame
  Vec3 normal = Vec3::Zero();  // unit surface normal turned towards the ray's origin side
  int object = -1;             // object id (see Scene)
  double albedo = 0.0;         // the object's albedo
};

// Nearest intersection t > t_min of the ray origin + t·direction (|direction| = 1) with a sphere /
// plane, or nullopt. The sphere uses the perpendicular-distance form of the quadratic, accurate
// near grazing incidence.
std::optional<double> IntersectSphere(const Sphere& sphere, const Vec3& origin, const Vec3& direction, double t_min);
std::optional<double> IntersectPlane(const Plane& plane, const Vec3& origin, const Vec3& direction, double t_min);

// First hit with t in (t_min, t_max) over all objects, or nullopt.
std::optional<RayHit> IntersectScene(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min = 1e-9,
                                     double t_max = 1e300);

// True if any object is hit with t in (t_min, t_max) (shadow rays).
bool IsOccluded(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min, double t_max);

}  // namespace ramtk::vision
