#pragma once
// Synthetic clouds for the sphere-fit tests and benchmarks: the visible cap of a ball seen by two
// cameras (left at the origin, right at (baseline, 0, 0), both looking along +z), sampled by the
// left camera's pixel rays, kept where both cameras see the surface at less than a grazing limit.
// Noise is anisotropic like a triangulated point: sigma along the line of sight from the
// baseline midpoint, perpendicular_ratio * sigma across it; sigma grows from sigma_min_mm facing
// the sensor to sigma_max_mm at the grazing limit (lower fringe modulation). A backdrop plane
// behind the ball and gross outliers can be added. Header-only; truth is known exactly.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

namespace ramtk::vision::test {

struct CapScene {
  Eigen::Vector3d centre{100.0, 10.0, 700.0};  // mm, left-camera frame
  double radius = 19.05;                       // 38.1 mm ball
  double baseline_mm = 200.0;
  double pitch_mm = 0.5;            // ray spacing at the ball's depth
  double grazing_limit_deg = 75.0;  // max angle between normal and either sight line
  double sigma_min_mm = 0.005, sigma_max_mm = 0.030;
  double perpendicular_ratio = 0.25;
  bool backdrop = true;  // plane z = centre.z + backdrop_offset, 4R x 4R around the ball
  double backdrop_offset_mm = 60.0;
  double backdrop_pitch_mm = 1.0;
  double outlier_fraction = 0.02;  // gross outliers in the ball's bounding box +- 5 mm
  double spike_fraction = 0.01;    // sphere points pushed 0.2..1 mm along the sight line
};

struct SynthCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<float> sigma;     // along the sight line, as the fitter's kAlongLineOfSight reads it
  std::vector<char> on_sphere;  // 1 = a (non-spike) sphere point
  std::vector<char> sphere_id;  // -1 none, else index of the sphere in the scene
  int sphere_points = 0;
  Eigen::Vector3d viewpoint{100.0, 0.0, 0.0};
};

inline Eigen::Vector3d SightDirection(const Eigen::Vector3d& p, const Eigen::Vector3d& viewpoint) {
  return (p - viewpoint).normalized();
}

// Adds one ball's cap (and optionally the outliers around it) to `cloud`.
inline void AddCap(const CapScene& s, int id, std::mt19937_64& rng, SynthCloud* cloud) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d left(0, 0, 0), right(s.baseline_mm, 0, 0);
  const Eigen::Vector3d view(s.baseline_mm / 2, 0, 0);
  cloud->viewpoint = view;
  const double cos_limit = std::cos(s.grazing_limit_deg * M_PI / 180.0);
  int on_this_sphere = 0;
  const int half = static_cast<int>(std::ceil(s.radius / s.pitch_mm)) + 1;
  for (int iy = -half; iy <= half; ++iy)
    for (int ix = -half; ix <= half; ++ix) {
      const Eigen::Vector3d target = s.centre + Eigen::Vector3d(ix * s.pitch_mm, iy * s.pitch_mm, -s.radius);
      const Eigen::Vector3d d = target.normalized();  // left-camera ray
      const double b = d.dot(s.centre);
      const double disc = b * b - (s.centre.squaredNorm() - s.radius * s.radius);
      if (disc <= 0) continue;
      const Eigen::Vector3d p = d * (b - std::sqrt(disc));
      const Eigen::Vector3d n = (p - s.centre) / s.radius;
      if (n.dot((left - p).normalized()) < cos_limit || n.dot((right - p).normalized()) < cos_limit) continue;
      const Eigen::Vector3d sight = SightDirection(p, view);
      const double facing = -n.dot(sight);  // 1 facing the sensor
      const double sigma = s.sigma_min_mm + (s.sigma_max_mm - s.sigma_min_mm) * (1.0 - facing) / (1.0 - cos_limit);
      const Eigen::Vector3d e1 = sight.unitOrthogonal(), e2 = sight.cross(e1);
      Eigen::Vector3d q =
          p + sigma * (gauss(rng) * sight + s.perpendicular_ratio * (gauss(rng) * e1 + gauss(rng) * e2));
      const bool spike = unit(rng) < s.spike_fraction;
      if (spike) q += (unit(rng) < 0.5 ? -1 : 1) * (0.2 + 0.8 * unit(rng)) * sight;
      cloud->points.push_back(q.cast<float>());
      cloud->sigma.push_back(static_cast<float>(sigma));
      cloud->on_sphere.push_back(spike ? 0 : 1);
      cloud->sphere_id.push_back(static_cast<char>(spike ? -1 : id));
      if (!spike) ++on_this_sphere;
    }
  cloud->sphere_points += on_this_sphere;
  const int outliers = static_cast<int>(s.outlier_fraction * on_this_sphere);
  for (int k = 0; k < outliers; ++k) {
    const Eigen::Vector3d q =
        s.centre + (s.radius + 5) * Eigen::Vector3d(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1);
    cloud->points.push_back(q.cast<float>());
    cloud->sigma.push_back(0.02f);
    cloud->on_sphere.push_back(0);
    cloud->sphere_id.push_back(-1);
  }
}

// A backdrop plane behind the given balls, with the balls' shadows (from the left camera) cut out.
inline void AddBackdrop(const std::vector<CapScene>& balls, std::mt19937_64& rng, SynthCloud* cloud) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  const CapScene& s = balls.front();
  Eigen::Vector3d lo = s.centre, hi = s.centre;
  for (const CapScene& b : balls) {
    lo = lo.cwiseMin(b.centre);
    hi = hi.cwiseMax(b.centre);
  }
  const double z = hi.z() + s.backdrop_offset_mm;
  const double margin = 2 * s.radius;
  for (double y = lo.y() - margin; y <= hi.y() + margin; y += s.backdrop_pitch_mm)
    for (double x = lo.x() - margin; x <= hi.x() + margin; x += s.backdrop_pitch_mm) {
      const Eigen::Vector3d p(x, y, z);
      bool shadow = false;
      for (const CapScene& b : balls) {
        const Eigen::Vector3d d = p.normalized();
        const double t = d.dot(b.centre);
        shadow = shadow || (b.centre - t * d).norm() < b.radius;
      }
      if (shadow) continue;
      const Eigen::Vector3d sight = SightDirection(p, cloud->viewpoint);
      const double sigma = 0.02;
      const Eigen::Vector3d q = p + sigma * gauss(rng) * sight;
      cloud->points.push_back(q.cast<float>());
      cloud->sigma.push_back(static_cast<float>(sigma));
      cloud->on_sphere.push_back(0);
      cloud->sphere_id.push_back(-1);
    }
}

inline SynthCloud MakeCapCloud(const CapScene& s, uint64_t seed) {
  std::mt19937_64 rng(seed);
  SynthCloud cloud;
  AddCap(s, 0, rng, &cloud);
  if (s.backdrop) AddBackdrop({s}, rng, &cloud);
  return cloud;
}

// A ball bar: two balls `length_mm` apart along `axis` (centred on s.centre).
inline SynthCloud MakeBallBarCloud(const CapScene& s, double length_mm, const Eigen::Vector3d& axis, uint64_t seed,
                                   Eigen::Vector3d* centre_a, Eigen::Vector3d* centre_b) {
  std::mt19937_64 rng(seed);
  CapScene a = s, b = s;
  a.centre = s.centre - 0.5 * length_mm * axis.normalized();
  b.centre = s.centre + 0.5 * length_mm * axis.normalized();
  SynthCloud cloud;
  AddCap(a, 0, rng, &cloud);
  AddCap(b, 1, rng, &cloud);
  if (s.backdrop) AddBackdrop({a, b}, rng, &cloud);
  *centre_a = a.centre;
  *centre_b = b.centre;
  return cloud;
}

}  // namespace ramtk::vision::test
