// Camera–projector triangulation with per-point sigma (projector_triangulate.h).
#include "ramtk/vision/projector/projector_triangulate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The projector's view of one camera ray and what was decoded there.
struct Observation {
  bool has_u = false, has_v = false;
  double u = 0, sigma_u = 1, v = 0, sigma_v = 1;  // projector px
};

enum class Outcome { kPoint, kGeometry, kResidual };

struct Solver {
  Mat3 R;
  Vec3 T;
  CameraIntrinsics projector;
  ProjectorTriangulationOptions options;

  // Depth z along the camera ray z·m (m = (x', y', 1)) whose projector projection best matches
  // the observation, and its sigma.
  Outcome Solve(const Vec3& m, const Observation& o, double* z_out, double* sigma_z_out) const {
    const Vec3 a = R * m;
    const Vec3& b = T;
    const CameraIntrinsics& p = projector;
    // Start: the ideal (undistorted) projector planes, each linear in z.
    double cc = 0, cd = 0;
    if (o.has_u) {
      const double un = (o.u - p.cx) / p.fx;
      const double c = un * a.z() - a.x(), d = b.x() - un * b.z();
      cc += c * c, cd += c * d;
    }
    if (o.has_v) {
      const double vn = (o.v - p.cy) / p.fy;
      const double c = vn * a.z() - a.y(), d = b.y() - vn * b.z();
      cc += c * c, cd += c * d;
    }
    if (!(cc > 1e-18)) return Outcome::kGeometry;
    double z = cd / cc;
    double info = 0, chi2 = 0, pu = 0, pv = 0;
    for (int it = 0; it <= options.max_iterations; ++it) {
      if (!(z > 0) || !std::isfinite(z)) return Outcome::kGeometry;
      const double den = a.z() * z + b.z();
      if (!(den > 0)) return Outcome::kGeometry;  // behind the projector
      const Vec2 n((a.x() * z + b.x()) / den, (a.y() * z + b.y()) / den);
      const Vec2 dn((a.x() * b.z() - a.z() * b.x()) / (den * den), (a.y() * b.z() - a.z() * b.y()) / (den * den));
      const Vec2 nd = DistortNormalized(p.distortion, n);
      const Vec2 g = DistortNormalizedJacobian(p.distortion, n) * dn;
      pu = p.fx * nd.x() + p.cx, pv = p.fy * nd.y() + p.cy;
      const double ju = p.fx * g.x(), jv = p.fy * g.y();
      double rj = 0;
      info = 0, chi2 = 0;
      if (o.has_u) {
        const double w = 1.0 / (o.sigma_u * o.sigma_u), r = pu - o.u;
        info += w * ju * ju, rj += w * r * ju, chi2 += w * r * r;
      }
      if (o.has_v) {
        const double w = 1.0 / (o.sigma_v * o.sigma_v), r = pv - o.v;
        info += w * jv * jv, rj += w * r * jv, chi2 += w * r * r;
      }
      if (!(info > 0)) return Outcome::kGeometry;
      const double dz = -rj / info;
      z += dz;
      if (std::abs(dz) <= 1e-12 * std::abs(z)) break;
    }
    if (!(z > options.min_depth_mm && z < options.max_depth_mm)) return Outcome::kGeometry;
    if (!(pu >= -0.5 && pu <= p.width - 0.5 && pv >= -0.5 && pv <= p.height - 0.5)) return Outcome::kGeometry;
    if (o.has_u && o.has_v && !(chi2 <= options.max_residual_sigma * options.max_residual_sigma))
      return Outcome::kResidual;
    *z_out = z;
    *sigma_z_out = 1.0 / std::sqrt(info);
    return Outcome::kPoint;
  }
};

void CheckSize(const cv::Mat& map, const CameraIntrinsics& camera, const std::string& field) {
  if (map.empty() || map.type() != CV_32F || map.cols != camera.width || map.rows != camera.height)
    throw InputError({"", 0, field}, "expected a CV_32F map of the camera's image size " +
                                         std::to_string(camera.width) + "x" + std::to_string(camera.height));
}

// One row's points before they are joined.
struct RowPoints {
  std::vector<Eigen::Vector3f> points;
  std::vector<float> sigma, quality;
  std::vector<Eigen::Vector2f> pixels;
  long coded = 0, geometry = 0, residual = 0;
};

PointCloud Triangulate(const ProjectorCalibration& calibration, const DecodedCamera* columns,
                       const DecodedCamera* rows, const ProjectorTriangulationOptions& options,
                       ProjectorTriangulationSummary* summary, cv::Mat* depth) {
  ThrowIfInvalid(options.Validate(), "ProjectorTriangulationOptions");
  const CameraIntrinsics& cam = calibration.camera;
  const DecodedCamera& first = columns ? *columns : *rows;
  for (const DecodedCamera* d : {columns, rows}) {
    if (!d) continue;
    CheckSize(d->coordinate, cam, "coordinate");
    CheckSize(d->sigma_coordinate, cam, "sigma_coordinate");
  }
  const bool has_modulation = !first.modulation.empty() && first.modulation.size() == first.coordinate.size();
  const double sigma_i = first.summary.sigma_intensity_dn > 0 ? first.summary.sigma_intensity_dn : 1.0;
  Solver solver{calibration.projector_from_camera.linear(), calibration.projector_from_camera.translation(),
                calibration.projector, options};
  const int W = cam.width, H = cam.height;
  cv::Mat z_map(H, W, CV_32F);
  std::vector<RowPoints> per_row(static_cast<std::size_t>(H));
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      RowPoints& out = per_row[static_cast<std::size_t>(y)];
      float* zr = z_map.ptr<float>(y);
      std::fill_n(zr, W, std::numeric_limits<float>::quiet_NaN());
      const float* cu = columns ? columns->coordinate.ptr<float>(y) : nullptr;
      const float* su = columns ? columns->sigma_coordinate.ptr<float>(y) : nullptr;
      const float* cv_ = rows ? rows->coordinate.ptr<float>(y) : nullptr;
      const float* sv = rows ? rows->sigma_coordinate.ptr<float>(y) : nullptr;
      const float* b = has_modulation ? first.modulation.ptr<float>(y) : nullptr;
      Vec2 ideal_prev(kNaN, 0);
      for (int x = 0; x < W; ++x) {
        Observation o;
        if (cu) {
          if (!std::isfinite(cu[x]) || !(su[x] > 0)) continue;
          o.has_u = true, o.u = cu[x], o.sigma_u = su[x];
        }
        if (cv_) {
          if (!std::isfinite(cv_[x]) || !(sv[x] > 0)) continue;
          o.has_v = true, o.v = cv_[x], o.sigma_v = sv[x];
        }
        ++out.coded;
        const Vec2 distorted((x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy);
        const Vec2 ideal = UndistortNormalized(cam.distortion, distorted,
                                               std::isfinite(ideal_prev.x()) ? ideal_prev : distorted);
        ideal_prev = ideal;
        const Vec3 m(ideal.x(), ideal.y(), 1.0);
        double z = 0, sigma_z = 0;
        const Outcome outcome = solver.Solve(m, o, &z, &sigma_z);
        if (outcome == Outcome::kGeometry) {
          ++out.geometry;
          continue;
        }
        if (outcome == Outcome::kResidual) {
          ++out.residual;
          continue;
        }
        out.points.emplace_back(static_cast<float>(z * m.x()), static_cast<float>(z * m.y()), static_cast<float>(z));
        out.sigma.push_back(static_cast<float>(m.norm() * sigma_z));
        out.quality.push_back(b ? static_cast<float>(b[x] / sigma_i) : 0.0f);
        if (options.keep_pixels) out.pixels.emplace_back(static_cast<float>(x), static_cast<float>(y));
        zr[x] = static_cast<float>(z);
      }
    }
  });
  ProjectorTriangulationSummary sum;
  std::size_t total = 0;
  for (const RowPoints& r : per_row) total += r.points.size();
  PointCloud cloud;
  cloud.points_in_left.reserve(total);
  cloud.sigma_mm.reserve(total);
  cloud.quality.reserve(total);
  if (options.keep_pixels) cloud.left_pixels.reserve(total);
  for (RowPoints& r : per_row) {
    sum.coded_pixels += r.coded, sum.rejected_geometry += r.geometry, sum.rejected_residual += r.residual;
    cloud.points_in_left.insert(cloud.points_in_left.end(), r.points.begin(), r.points.end());
    cloud.sigma_mm.insert(cloud.sigma_mm.end(), r.sigma.begin(), r.sigma.end());
    cloud.quality.insert(cloud.quality.end(), r.quality.begin(), r.quality.end());
    if (options.keep_pixels) cloud.left_pixels.insert(cloud.left_pixels.end(), r.pixels.begin(), r.pixels.end());
    r = RowPoints();
  }
  sum.points = static_cast<long>(cloud.size());
  if (!cloud.points_in_left.empty()) {
    sum.depth_min_mm = std::numeric_limits<double>::infinity();
    sum.depth_max_mm = -sum.depth_min_mm;
    for (const Eigen::Vector3f& p : cloud.points_in_left) {
      sum.depth_min_mm = std::min<double>(sum.depth_min_mm, p.z());
      sum.depth_max_mm = std::max<double>(sum.depth_max_mm, p.z());
    }
    std::vector<float> s = cloud.sigma_mm;
    std::nth_element(s.begin(), s.begin() + static_cast<long>(s.size() / 2), s.end());
    sum.median_sigma_mm = s[s.size() / 2];
  }
  if (summary) *summary = sum;
  if (depth) *depth = z_map;
  return cloud;
}

}  // namespace

std::string ProjectorTriangulationOptions::Validate() const {
  if (!(min_depth_mm >= 0)) return "min_depth_mm: must be >= 0";
  if (!(max_depth_mm > min_depth_mm)) return "max_depth_mm: must be > min_depth_mm";
  if (max_iterations < 1 || max_iterations > 100) return "max_iterations: must be 1..100";
  if (!(max_residual_sigma > 0)) return "max_residual_sigma: must be > 0";
  return "";
}

std::string ProjectorTriangulationSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << "projector triangulation: " << points << " points of " << coded_pixels << " coded pixels ("
    << rejected_geometry << " outside the projector or the depth range, " << rejected_residual
    << " disagreeing coordinates), z " << depth_min_mm << ".." << depth_max_mm << " mm, median sigma "
    << median_sigma_mm * 1000 << " um";
  return s.str();
}

PointCloud TriangulateProjectorPlanes(const ProjectorCalibration& calibration, FringeDirection direction,
                                      const DecodedCamera& coded, const ProjectorTriangulationOptions& options,
                                      ProjectorTriangulationSummary* summary, cv::Mat* depth) {
  const bool vertical = direction == FringeDirection::kVertical;
  return Triangulate(calibration, vertical ? &coded : nullptr, vertical ? nullptr : &coded, options, summary, depth);
}

PointCloud TriangulateProjectorPixels(const ProjectorCalibration& calibration, const DecodedCamera& columns,
                                      const DecodedCamera& rows, const ProjectorTriangulationOptions& options,
                                      ProjectorTriangulationSummary* summary, cv::Mat* depth) {
  return Triangulate(calibration, &columns, &rows, options, summary, depth);
}

}  // namespace ramtk::vision
