// Board corners in projector pixels from decoded fringes by local homographies (projector_corners.h).
#include "ramtk/vision/projector/projector_corners.h"

#include <Eigen/Dense>
#include <cmath>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

// Weighted least-squares homography (affine start on centred, scaled coordinates, then
// Gauss-Newton on the projector-pixel residuals, weights 1 / sigma^2) from camera pixels `a` to
// projector pixels `b` (sigma `s` per coordinate), evaluated at `c` with its sigma from the fit's
// covariance (the projective terms are correlated with the offset, so it exceeds sigma / sqrt(n)).
// Returns false for a degenerate window.
bool FitAndEvaluate(const std::vector<Vec2>& a, const std::vector<Vec2>& b, const std::vector<Vec2>& s,
                    const Vec2& c, Vec2* at_c, Vec2* sigma_c, double* residual_rms) {
  const std::size_t n = a.size();
  // Camera coordinates relative to the corner (the homography's centre), in window units.
  double scale = 0;
  for (const Vec2& p : a) scale = std::max(scale, (p - c).cwiseAbs().maxCoeff());
  if (!(scale > 0)) return false;
  Vec2 b_mean = Vec2::Zero();
  for (const Vec2& q : b) b_mean += q / static_cast<double>(n);
  // Parameters h (8): u = (h0 x + h1 y + h2) / (h6 x + h7 y + 1), v = (h3 x + h4 y + h5) / (...),
  // x, y = (camera - c) / scale, u, v = projector - b_mean. Start: the affine least squares.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd bu(n), bv(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 x = (a[i] - c) / scale;
    A.row(static_cast<long>(i)) << x.x(), x.y(), 1.0;
    bu[static_cast<long>(i)] = b[i].x() - b_mean.x();
    bv[static_cast<long>(i)] = b[i].y() - b_mean.y();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) return false;
  const Eigen::Vector3d pu = qr.solve(bu), pv = qr.solve(bv);
  Eigen::Matrix<double, 8, 1> h;
  h << pu[0], pu[1], pu[2], pv[0], pv[1], pv[2], 0, 0;
  double sq = 0;
  Eigen::Matrix<double, 8, 8> JtJ;
  for (int it = 0; it < 6; ++it) {
    JtJ.setZero();
    Eigen::Matrix<double, 8, 1> Jtr = Eigen::Matrix<double, 8, 1>::Zero();
    sq = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 x = (a[i] - c) / scale;
      const double w = h[6] * x.x() + h[7] * x.y() + 1;
      const double nu = h[0] * x.x() + h[1] * x.y() + h[2], nv = h[3] * x.x() + h[4] * x.y() + h[5];
      const double ru = nu / w - bu[static_cast<long>(i)], rv = nv / w - bv[static_cast<long>(i)];
      Eigen::Matrix<double, 8, 1> ju, jv;
      ju << x.x() / w, x.y() / w, 1 / w, 0, 0, 0, -nu * x.x() / (w * w), -nu * x.y() / (w * w);
      jv << 0, 0, 0, x.x() / w, x.y() / w, 1 / w, -nv * x.x() / (w * w), -nv * x.y() / (w * w);
      const double wu = 1.0 / (s[i].x() * s[i].x()), wv = 1.0 / (s[i].y() * s[i].y());
      JtJ += wu * ju * ju.transpose() + wv * jv * jv.transpose();
      Jtr += wu * ju * ru + wv * jv * rv;
      sq += ru * ru + rv * rv;
    }
    const Eigen::Matrix<double, 8, 1> step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return false;
    h += step;
    if (step.norm() < 1e-12) break;
  }
  // At the corner x = 0: (h2, h5) / 1.
  *at_c = Vec2(h[2], h[5]) + b_mean;
  *residual_rms = std::sqrt(sq / (2.0 * static_cast<double>(n)));
  const Eigen::Matrix<double, 8, 8> cov = JtJ.inverse();
  *sigma_c = Vec2(std::sqrt(cov(2, 2)), std::sqrt(cov(5, 5)));
  return at_c->allFinite() && sigma_c->allFinite();
}

}  // namespace

std::string ProjectorCornerOptions::Validate() const {
  if (half_window_px < 2 || half_window_px > 200) return "half_window_px: must be 2..200";
  if (!(min_valid_fraction > 0 && min_valid_fraction <= 1)) return "min_valid_fraction: must be in (0, 1]";
  return "";
}

std::vector<ProjectorCorner> ProjectorCornersFromPhase(const std::vector<cv::Point2f>& camera_corners,
                                                       const DecodedCamera& columns, const DecodedCamera& rows,
                                                       const ProjectorCornerOptions& options) {
  ThrowIfInvalid(options.Validate(), "ProjectorCornerOptions");
  for (const cv::Mat* m : {&columns.coordinate, &rows.coordinate, &columns.sigma_coordinate, &rows.sigma_coordinate})
    if (m->type() != CV_32F || m->size() != columns.coordinate.size())
      throw InputError({"", 0, "coordinate"}, "expected CV_32F coordinate and sigma maps of one size for both directions");
  const int W = columns.coordinate.cols, H = columns.coordinate.rows, r = options.half_window_px;
  const int window = (2 * r + 1) * (2 * r + 1);
  std::vector<ProjectorCorner> out(camera_corners.size());
  for (std::size_t k = 0; k < camera_corners.size(); ++k) {
    const Vec2 c(camera_corners[k].x, camera_corners[k].y);
    const int cx = static_cast<int>(std::lround(c.x())), cy = static_cast<int>(std::lround(c.y()));
    if (cx - r < 0 || cy - r < 0 || cx + r >= W || cy + r >= H) continue;
    std::vector<Vec2> a, b, s;
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x) {
        const float u = columns.coordinate.at<float>(y, x), v = rows.coordinate.at<float>(y, x);
        const float su = columns.sigma_coordinate.at<float>(y, x), sv = rows.sigma_coordinate.at<float>(y, x);
        if (!std::isfinite(u) || !std::isfinite(v) || !(su > 0) || !(sv > 0)) continue;
        a.emplace_back(x, y);
        b.emplace_back(u, v);
        s.emplace_back(su, sv);
      }
    ProjectorCorner& pc = out[k];
    pc.pixels = static_cast<int>(a.size());
    if (pc.pixels < options.min_valid_fraction * window || pc.pixels < 8) continue;
    if (!FitAndEvaluate(a, b, s, c, &pc.projector_px, &pc.sigma_px, &pc.residual_rms_px)) continue;
    pc.valid = true;
  }
  return out;
}

}  // namespace ramtk::vision
