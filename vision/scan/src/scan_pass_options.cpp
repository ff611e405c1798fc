// Every rewrite of the scan's options, in one place (scan_pass.h).
#include <algorithm>
#include <limits>

#include "scan_pass.h"

namespace ramtk::vision::detail {

ScanStageOptions StageOptionsOf(const ScanOptions& options) {
  ScanStageOptions s;
  s.decode = options.decode;
  s.decode.progress = {};
  s.match = options.match;
  s.match.progress = {};
  s.match.right_pixels = false;  // the cloud needs the depths only
  s.match.sigma_map = false;     // the points carry their own sigma (StereoMatch::point_sigma_mm)
  s.triangulation = options.triangulation;
  s.sphere = options.sphere;
  s.sphere.progress = {};
  return s;
}

ScanOptions CoarsePassOptions(const ScanOptions& options) {
  ScanOptions o = options;
  o.progress = {};
  o.roi = ScanRoiOptions();
  o.fit_spheres = true;
  o.on_cloud = {};
  // A window only needs the centre to a fraction of a millimetre: no nonlinearity correction,
  // and the variance gate is left to the windowed pass (the coarse cloud's noise model is not
  // the point here); the radius gate stays, so a backdrop is not taken for the ball.
  o.decode.correct_nonlinearity = false;
  o.max_sphere_variance_factor = std::numeric_limits<double>::max();
  // No left-right check (it is a second, right-to-left match pass): a wrong crossing left in the
  // coarse cloud is an outlier to the sphere search, which the windowed pass then checks.
  o.match.lr_tolerance_px = 0;
  // The coarse ball has ~1/stride^2 of the points; a few dozen fix its centre to ~0.1 mm.
  o.sphere.min_points = std::min(o.sphere.min_points, 50);
  return o;
}

ScanOptions WindowedPassOptions(const ScanOptions& options, const StereoCalibration& calibration,
                                const std::vector<Sphere>& spheres) {
  ScanOptions o = options;
  if (spheres.empty() || options.roi.depth_margin_mm < 0) return o;
  double l0 = 1e300, l1 = -1e300, r0 = 1e300, r1 = -1e300;
  for (const Sphere& s : spheres) {
    const double reach = s.radius + options.roi.margin_mm + options.roi.depth_margin_mm;
    const double zl = s.centre_in_left.z(), zr = (calibration.right_from_left * s.centre_in_left).z();
    l0 = std::min(l0, zl - reach), l1 = std::max(l1, zl + reach);
    r0 = std::min(r0, zr - reach), r1 = std::max(r1, zr + reach);
  }
  l0 = std::max(l0, options.match.min_depth_mm), l1 = std::min(l1, options.match.max_depth_mm);
  if (!(l0 > 0 && l1 > l0 && r0 > 0 && r1 > r0)) return o;
  o.match.min_depth_mm = l0, o.match.max_depth_mm = l1;
  if (options.match.right_max_depth_mm > 0) {
    r0 = std::max(r0, options.match.right_min_depth_mm), r1 = std::min(r1, options.match.right_max_depth_mm);
    if (!(r1 > r0)) return options;
  }
  o.match.right_min_depth_mm = r0, o.match.right_max_depth_mm = r1;
  return o;
}

}  // namespace ramtk::vision::detail
