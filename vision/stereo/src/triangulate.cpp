// Midpoint triangulation and the per-point sigma (triangulate.h).
#include "ramtk/vision/stereo/triangulate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/vision/kernels/rank_select.h"

namespace ramtk::vision {

namespace {

// Midpoint of the shortest segment between the left ray (origin 0, direction dl) and the right
// ray (origin c, direction dr, both in the left frame).
Vec3 MidpointOfRays(const Vec3& dl, const Vec3& dr, const Vec3& c, double* gap_mm) {
  // Minimise |t dl - (c + s dr)|^2.
  const double a = dl.dot(dl), b = dl.dot(dr), e = dr.dot(dr);
  const double d1 = dl.dot(c), d2 = dr.dot(c);
  const double den = a * e - b * b;
  if (!(std::abs(den) > 1e-15)) {
    if (gap_mm) *gap_mm = std::numeric_limits<double>::quiet_NaN();
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  const double t = (e * d1 - b * d2) / den;
  const double s = (b * d1 - a * d2) / den;
  const Vec3 pl = t * dl, pr = c + s * dr;
  if (gap_mm) *gap_mm = (pl - pr).norm();
  return 0.5 * (pl + pr);
}

Vec2 Normalized(const CameraIntrinsics& c, const Vec2& pixel) {
  return {(pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy};
}

}  // namespace

Vec3 TriangulateMidpoint(const StereoCalibration& calibration, const Vec2& left_pixel, const Vec2& right_pixel,
                         double* gap_mm) {
  // Left ray: origin 0, direction dl. Right ray in the left frame: origin c = -R^T T, direction R^T dr.
  const Mat3 R = calibration.right_from_left.linear();
  const Vec3 T = calibration.right_from_left.translation();
  const Vec3 dl = PixelRay(calibration.left, left_pixel);
  const Vec3 dr = R.transpose() * PixelRay(calibration.right, right_pixel);
  return MidpointOfRays(dl, dr, -R.transpose() * T, gap_mm);
}

std::string TriangulationOptions::Validate() const {
  if (!(max_ray_gap_mm > 0)) return "max_ray_gap_mm: must be > 0";
  return "";
}

std::string TriangulationSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << "triangulate: " << points << " points (" << rejected_gap << " dropped for ray gap), z " << depth_min_mm << ".."
    << depth_max_mm << " mm, median sigma " << median_sigma_mm * 1000 << " um";
  return s.str();
}

namespace {

// Throws when the match's maps or the left modulation do not fit together.
void CheckMatchMaps(const DecodedCamera& left, const StereoMatch& match, bool from_match, bool has_xy, int W, int H) {
  if (from_match && (match.depth_mm.type() != CV_32F || match.point_sigma_mm.type() != CV_32F ||
                     match.point_sigma_mm.size() != match.depth_mm.size() ||
                     (!match.right_u.empty() && match.right_u.size() != match.depth_mm.size())))
    throw InputError({"", 0, "depth_mm"}, "the match's depth and point sigma must be CV_32F maps of the match's size");
  if (has_xy && (match.x_mm.type() != CV_32F || match.y_mm.type() != CV_32F ||
                 match.x_mm.size() != match.depth_mm.size() || match.y_mm.size() != match.depth_mm.size()))
    throw InputError({"", 0, "x_mm"}, "the match's x and y must be CV_32F maps of its depth map's size");
  if (!from_match && (match.right_v.size() != match.right_u.size() || match.sigma_px.size() != match.right_u.size()))
    throw InputError({"", 0, "right_u"}, "the match's right pixels and sigma are not maps of one size");
  if (W * H > 0 && left.modulation.size() != cv::Size(W, H))
    throw InputError({"", 0, "modulation"}, "the left modulation map is not of the match's size");
}

// Each row's first cloud slot (a prefix sum of the rows' finite pixels; H + 1 entries).
std::vector<std::size_t> RowSlots(const cv::Mat& matched) {
  const int W = matched.cols, H = matched.rows;
  std::vector<std::size_t> first(static_cast<std::size_t>(H) + 1, 0);
  cv::parallel_for_(cv::Range(0, H), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* u = matched.ptr<float>(y);
      std::size_t n = 0;
      for (int x = 0; x < W; ++x) n += std::isfinite(u[x]) ? 1 : 0;
      first[y + 1] = n;
    }
  });
  for (int y = 0; y < H; ++y) first[y + 1] += first[y];
  return first;
}

// One row of TriangulateMatches: its inputs, the cloud whose slots it fills and the depth map.
struct RowTriangulator {
  const StereoCalibration& calibration;
  const DecodedCamera& left;
  const StereoMatch& match;
  const TriangulationOptions& options;
  double sigma_i;  // the left camera's intensity noise (DN), the quality's denominator
  Mat3 R, Rt;      // right_from_left's rotation and its transpose
  Vec3 c;          // the right camera's centre in the left frame
  PointCloud& cloud;
  std::vector<uchar>& kept;
  cv::Mat& z;

  // Fills slot k with a point seen at left pixel (x, y).
  void Put(std::size_t k, const Eigen::Vector3f& p, float sigma, float quality, int x, int y) const {
    kept[k] = 1;
    cloud.points_in_left[k] = p;
    cloud.sigma_mm[k] = sigma;
    cloud.quality[k] = quality;
    if (options.keep_pixels) cloud.left_pixels[k] = Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y));
  }

  // The match's own points (StereoMatch::x_mm, y_mm): the same numbers as IntersectRow's, copied.
  void CopyRow(int y, std::size_t slot) const {
    const float* zm = match.depth_mm.ptr<float>(y);
    const float* xm = match.x_mm.ptr<float>(y);
    const float* ym = match.y_mm.ptr<float>(y);
    const float* ps = match.point_sigma_mm.ptr<float>(y);
    const float* b = left.modulation.ptr<float>(y);
    for (int x = 0; x < z.cols; ++x) {
      if (!std::isfinite(zm[x])) continue;
      Put(slot++, Eigen::Vector3f(xm[x], ym[x], zm[x]), ps[x], static_cast<float>(b[x] / sigma_i), x, y);
    }
  }

  // The match's own depths: the left ray as the match found it, undistorted from the previous
  // pixels' rays, extrapolated along the row when the two before were points (one Gauss-Newton
  // round), at the stored depth.
  void DepthRow(int y, std::size_t slot) const {
    const CameraIntrinsics& lc = calibration.left;
    const float* zm = match.depth_mm.ptr<float>(y);
    const float* ps = match.point_sigma_mm.ptr<float>(y);
    const float* b = left.modulation.ptr<float>(y);
    float* zr = z.ptr<float>(y);
    Vec2 left_ideal_prev(std::numeric_limits<double>::quiet_NaN(), 0);
    Vec2 left_ideal_prev2 = left_ideal_prev;
    int x_prev = -10, x_prev2 = -10;
    for (int x = 0; x < z.cols; ++x) {
      if (!std::isfinite(zm[x])) continue;
      const std::size_t k = slot++;
      const Vec2 ln = Normalized(lc, Vec2(x, y));
      const Vec2 seed = x_prev == x - 1 && x_prev2 == x - 2  ? Vec2(2.0 * left_ideal_prev - left_ideal_prev2)
                        : std::isfinite(left_ideal_prev.x()) ? left_ideal_prev
                                                             : ln;
      const Vec2 left_ideal = UndistortNormalized(lc.distortion, ln, seed);
      left_ideal_prev2 = left_ideal_prev;
      left_ideal_prev = left_ideal;
      x_prev2 = x_prev;
      x_prev = x;
      const double zx = zm[x];
      Put(k, Eigen::Vector3f(static_cast<float>(left_ideal.x() * zx), static_cast<float>(left_ideal.y() * zx), zm[x]),
          ps[x], static_cast<float>(b[x] / sigma_i), x, y);
      zr[x] = zm[x];
    }
  }

  // Triangulation Jacobian |dX/ds| along the epipolar tangent (central difference, 1e-3 px). The
  // tangent: the left ray's points s * (ideal, 1) move in the right camera's ideal plane along
  // g_xy - ideal_r * g_z (g = R * the ray), mapped to pixels through the lens. The right rays at
  // +-h along it come from the ideal point moved by J^-1 (h t / f), J the lens Jacobian there (the
  // undistortion's own derivative; its second-order term changes the derivative by ~h / f
  // relative, < 1e-6).
  double EpipolarJacobian(const Vec2& left_ideal, const Vec3& dl, const Vec2& right_ideal) const {
    const CameraIntrinsics& rc = calibration.right;
    const Vec3 g = R * Vec3(left_ideal.x(), left_ideal.y(), 1.0);
    const Vec2 dideal(g.x() - right_ideal.x() * g.z(), g.y() - right_ideal.y() * g.z());
    const Eigen::Matrix2d jac = DistortNormalizedJacobian(rc.distortion, right_ideal);
    const Vec2 dd = jac * dideal;
    const Vec2 t = Vec2(rc.fx * dd.x(), rc.fy * dd.y()).normalized();
    const double h = 1e-3;
    const Vec2 step = jac.inverse() * Vec2(h * t.x() / rc.fx, h * t.y() / rc.fy);
    const Vec3 dra = Rt * Vec3(right_ideal.x() - step.x(), right_ideal.y() - step.y(), 1.0).normalized();
    const Vec3 drb = Rt * Vec3(right_ideal.x() + step.x(), right_ideal.y() + step.y(), 1.0).normalized();
    const Vec3 Xa = MidpointOfRays(dl, dra, c, nullptr);
    const Vec3 Xb = MidpointOfRays(dl, drb, c, nullptr);
    return ((Xb - Xa) / (2 * h)).norm();
  }

  // The matched right pixels: both rays intersected. Undistortion is warm-started from the row's
  // previous point: the left ray from the neighbour's, the right ray from its distorted point
  // shifted by the previous right point's distortion offset (ideal - distorted changes slowly
  // across the image). The same rays to 1e-15 in one or two Gauss-Newton steps instead of four
  // to six. Points whose rays miss by more than max_ray_gap_mm leave their slot unkept.
  void IntersectRow(int y, std::size_t slot) const {
    const CameraIntrinsics& lc = calibration.left;
    const CameraIntrinsics& rc = calibration.right;
    Vec2 left_ideal_prev(std::numeric_limits<double>::quiet_NaN(), 0);
    Vec2 right_offset_prev(std::numeric_limits<double>::quiet_NaN(), 0);
    const float* ru = match.right_u.ptr<float>(y);
    const float* rv = match.right_v.ptr<float>(y);
    for (int x = 0; x < z.cols; ++x) {
      const float u = ru[x], v = rv[x];
      if (!std::isfinite(u)) continue;
      const std::size_t k = slot++;
      const Vec2 lp(x, y), rp(u, v);
      const Vec2 ln = Normalized(lc, lp);
      const Vec2 left_ideal =
          UndistortNormalized(lc.distortion, ln, std::isfinite(left_ideal_prev.x()) ? left_ideal_prev : ln);
      left_ideal_prev = left_ideal;
      const Vec3 dl = Vec3(left_ideal.x(), left_ideal.y(), 1.0).normalized();
      const Vec2 rn = Normalized(rc, rp);
      const Vec2 right_ideal = UndistortNormalized(
          rc.distortion, rn, std::isfinite(right_offset_prev.x()) ? Vec2(rn + right_offset_prev) : rn);
      right_offset_prev = right_ideal - rn;
      const Vec3 dr = Rt * Vec3(right_ideal.x(), right_ideal.y(), 1.0).normalized();
      double gap = 0;
      const Vec3 X = MidpointOfRays(dl, dr, c, &gap);
      if (!(gap <= options.max_ray_gap_mm) || !X.allFinite()) continue;
      const double dXds = EpipolarJacobian(left_ideal, dl, right_ideal);
      Put(k, X.cast<float>(), static_cast<float>(dXds * match.sigma_px.at<float>(y, x)),
          static_cast<float>(left.modulation.at<float>(y, x) / sigma_i), x, y);
      z.at<float>(y, x) = static_cast<float>(X.z());
    }
  }
};

// Squeezes out the slots not kept (nothing moves before the first one) and returns the summary.
TriangulationSummary SqueezeAndSummarize(PointCloud& cloud, std::vector<uchar>& kept, bool keep_pixels) {
  TriangulationSummary sum;
  sum.depth_min_mm = std::numeric_limits<double>::infinity();
  sum.depth_max_mm = -sum.depth_min_mm;
  const std::size_t slots = kept.size();
  std::size_t n = 0;
  while (n < slots && kept[n]) ++n;
  for (std::size_t k = n; k < slots; ++k) {
    if (!kept[k]) {
      ++sum.rejected_gap;
      continue;
    }
    cloud.points_in_left[n] = cloud.points_in_left[k];
    cloud.sigma_mm[n] = cloud.sigma_mm[k];
    cloud.quality[n] = cloud.quality[k];
    if (keep_pixels) cloud.left_pixels[n] = cloud.left_pixels[k];
    ++n;
  }
  cloud.points_in_left.resize(n);
  cloud.sigma_mm.resize(n);
  cloud.quality.resize(n);
  if (keep_pixels) cloud.left_pixels.resize(n);
  std::vector<uchar>().swap(kept);
  sum.points = static_cast<long>(cloud.size());
  for (const Eigen::Vector3f& p : cloud.points_in_left) {
    sum.depth_min_mm = std::min<double>(sum.depth_min_mm, p.z());
    sum.depth_max_mm = std::max<double>(sum.depth_max_mm, p.z());
  }
  if (cloud.size() == 0) sum.depth_min_mm = sum.depth_max_mm = 0;
  if (!cloud.sigma_mm.empty()) sum.median_sigma_mm = detail::ValuesAtRanks(cloud.sigma_mm, {cloud.size() / 2})[0];
  return sum;
}

}  // namespace

PointCloud TriangulateMatches(const StereoCalibration& calibration, const DecodedCamera& left, const StereoMatch& match,
                              const TriangulationOptions& options, TriangulationSummary* summary, cv::Mat* depth) {
  ThrowIfInvalid(options.Validate(), "TriangulationOptions");
  // The match's own depths (StereoMatch::depth_mm): its right pixel is the projection of that
  // point of the left ray, so the rays meet there (gap 0) and nothing is intersected again; the
  // point is the left ray at that depth.
  const bool from_match = !match.depth_mm.empty();
  const cv::Mat& matched = from_match ? match.depth_mm : match.right_u;  // finite where a point is
  const int W = matched.cols, H = matched.rows;
  const bool has_xy = from_match && !match.x_mm.empty();
  CheckMatchMaps(left, match, from_match, has_xy, W, H);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // NaN-filled row by row below (in parallel: first touches fault); with the match's own points
  // their depth map is the answer (shared, not copied).
  cv::Mat z = has_xy ? match.depth_mm : cv::Mat(H, W, CV_32F);
  // The points are written straight into the cloud's arrays, row-major: each row's matched
  // pixels get slots from a prefix sum, and the slots of points dropped for their ray gap are
  // squeezed out afterwards (no per-pixel maps of x, y, z and sigma, no growing vectors).
  const std::vector<std::size_t> first = RowSlots(matched);
  const std::size_t slots = first[H];
  PointCloud cloud;
  cloud.points_in_left.resize(slots);
  cloud.sigma_mm.resize(slots);
  cloud.quality.resize(slots);
  if (options.keep_pixels) cloud.left_pixels.resize(slots);
  std::vector<uchar> kept(slots, 0);
  const Mat3 R = calibration.right_from_left.linear();
  const RowTriangulator rows{calibration,
                             left,
                             match,
                             options,
                             left.summary.sigma_intensity_dn > 0 ? left.summary.sigma_intensity_dn : 1.0,
                             R,
                             R.transpose(),
                             -R.transpose() * calibration.right_from_left.translation(),
                             cloud,
                             kept,
                             z};
  cv::parallel_for_(cv::Range(0, H), [&](const cv::Range& range) {
    for (int y = range.start; y < range.end; ++y) {
      if (has_xy) {
        rows.CopyRow(y, first[y]);
        continue;
      }
      std::fill_n(z.ptr<float>(y), W, nan);
      if (from_match)
        rows.DepthRow(y, first[y]);
      else
        rows.IntersectRow(y, first[y]);
    }
  });
  const TriangulationSummary sum = SqueezeAndSummarize(cloud, kept, options.keep_pixels);
  if (summary) *summary = sum;
  if (depth) *depth = z;
  return cloud;
}

}  // namespace ramtk::vision
