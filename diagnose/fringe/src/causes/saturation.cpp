// Saturation: the camera clips at full scale; clipped pixels refitted on their unclipped phase
// samples and every prediction clipped.
#include <Eigen/Dense>
#include <cmath>

#include "../fringe_fit_kit.h"

namespace ramtk::diagnose::fringe {

CandidateFit FitSaturation(const CandidateContext& ctx) {
  const FringeFit& fit = *ctx.fit;
  const auto& by_tile = ctx.by_tile;
  const int nt = static_cast<int>(by_tile.size());
  const int nf = fit.frames, n = fit.steps;
  const double clip = fit.full_scale;
  std::vector<double> ssr(nt, 0.0);
  long refit = 0;
  cv::parallel_for_(cv::Range(0, nt), [&](const cv::Range& range) {
    for (int t = range.start; t < range.end; ++t)
      for (int i : by_tile[t]) {
        const PixelFit& p0 = fit.pixels[i];
        PixelFit p = p0;
        if (p0.clipped) {
          Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
          Eigen::Vector3d b = Eigen::Vector3d::Zero();
          int used = 0;
          for (int k = 0; k < n; ++k) {
            const double v = fit.images[fit.phase_frame[k]].at<float>(p.y, p.x);
            if (v >= clip - 0.5) continue;
            const double d = StepShift(k, n);
            const Eigen::Vector3d row(1.0, std::cos(d), -std::sin(d));
            a += row * row.transpose(), b += row * v, ++used;
          }
          if (used >= 4) {
            const Eigen::Vector3d x = a.ldlt().solve(b);
            p.a = x(0), p.b = std::hypot(x(1), x(2)), p.phi = std::atan2(x(2), x(1));
          }
        }
        for (int f = 0; f < nf; ++f) {
          const size_t idx = static_cast<size_t>(i) * nf + f;
          if (!std::isfinite(fit.residual[idx])) continue;
          const double v = fit.images[f].at<float>(p.y, p.x);
          ssr[t] += std::pow((v - std::min(IdealIntensity(fit, p, f), clip)) * W(fit, idx), 2);
        }
      }
  });
  for (const PixelFit& p : fit.pixels) refit += p.clipped ? 1 : 0;
  CandidateFit c;
  c.effect = "saturation";
  c.num_parameters = 1;
  CrossValidate(
      ctx.fold_of_tile, ctx.folds, ctx.count, [&](int, int t) { return ssr[t]; }, &c);
  c.parameters["clip_level_DN"] = clip;
  c.parameters["clipped_pixels"] = static_cast<double>(refit);
  return c;
}

}  // namespace ramtk::diagnose::fringe
