// Blur of the Gray-code frames: camera_defocus and (projector) defocus.
#include <cmath>

#include "../fringe_fit_kit.h"

namespace ramtk::diagnose::fringe {
namespace {

// Blur: the phase frames only lose modulation, which B absorbs; the Gray-code frames keep
// their full contrast (more than B) and their edges spread. Two candidates differ in where the
// blur happens, hence in how its width in projector px varies across the image:
// `camera_defocus` blurs the image by σ camera px, so the code edges spread by σ·|∇u|
// projector px (more where the surface is seen foreshortened); `defocus` (projector) blurs the
// pattern by σ projector px everywhere. σ on a grid, chosen per fold on the training tiles.
CandidateFit FitBlur(const CandidateContext& ctx, const std::string& name, const std::string& key, bool camera_space) {
  const FringeFit& fit = *ctx.fit;
  const auto& by_tile = ctx.by_tile;
  const auto& fold_of_tile = ctx.fold_of_tile;
  const auto& count = ctx.count;
  const int folds = ctx.folds;
  const int nt = static_cast<int>(by_tile.size());
  const int nf = fit.frames, n = fit.steps;
  // Per-tile SSR for each blur in `sigmas` (the candidate's unit).
  const auto evaluate = [&](const std::vector<double>& sigmas) {
    const int ng = static_cast<int>(sigmas.size());
    std::vector<std::vector<double>> ssr(ng, std::vector<double>(nt, 0.0));
    cv::parallel_for_(cv::Range(0, nt), [&](const cv::Range& range) {
      for (int t = range.start; t < range.end; ++t)
        for (int i : by_tile[t]) {
          const PixelFit& p = fit.pixels[i];
          double phase_ssr = 0;
          for (int k = 0; k < n; ++k) {
            const size_t idx = static_cast<size_t>(i) * nf + fit.phase_frame[k];
            phase_ssr += std::pow(fit.residual[idx] * W(fit, idx), 2);
          }
          const double g = camera_space ? std::hypot(p.grad_x, p.grad_y) : 1.0;
          for (int s = 0; s < ng; ++s) {
            double sum = phase_ssr;
            for (int j = 0; j < fit.gray_bits; ++j) {
              const int f = fit.gray_frame[j];
              const size_t idx = static_cast<size_t>(i) * nf + f;
              if (!std::isfinite(fit.residual[idx])) continue;
              const double pred = SensorExpectation(fit, p, GrayIntensity(fit, p, j, sigmas[s] * g));
              sum += std::pow((fit.images[f].at<float>(p.y, p.x) - pred) * W(fit, idx), 2);
            }
            ssr[s][t] += sum;
          }
        }
    });
    return ssr;
  };
  const auto best_without = [&](const std::vector<std::vector<double>>& ssr, int fold) {
    int best = 0;
    double best_v = 1e300;
    for (size_t s = 0; s < ssr.size(); ++s) {
      double v = 0;
      for (int t = 0; t < nt; ++t)
        if (fold_of_tile[t] != fold) v += ssr[s][t];
      if (v < best_v) best_v = v, best = static_cast<int>(s);
    }
    return best;
  };
  // A coarse grid, then a fine one (13 steps) between the coarse neighbours of the best: the
  // two candidates differ only in how the width varies across the image, so a grid step of
  // 20-30 % would otherwise decide between them.
  std::vector<double> grid = {0, 0.2, 0.4, 0.8, 1.2, 1.6, 2, 2.5, 3, 4, 6};
  std::vector<std::vector<double>> ssr = evaluate(grid);
  const int coarse = best_without(ssr, -1);
  const double lo = grid[std::max(coarse - 1, 0)], hi = grid[std::min<int>(coarse + 1, static_cast<int>(grid.size()) - 1)];
  std::vector<double> fine;
  for (int k = 1; k < 13; ++k) fine.push_back(lo + (hi - lo) * k / 13.0);
  const std::vector<std::vector<double>> fine_ssr = evaluate(fine);
  grid.insert(grid.end(), fine.begin(), fine.end());
  ssr.insert(ssr.end(), fine_ssr.begin(), fine_ssr.end());
  std::vector<int> chosen(folds);
  for (int k = 0; k < folds; ++k) chosen[k] = best_without(ssr, k);
  CandidateFit c;
  c.effect = name;
  c.num_parameters = 1;
  CrossValidate(
      fold_of_tile, folds, count, [&](int k, int t) { return ssr[chosen[k]][t]; }, &c);
  c.parameters[key] = grid[best_without(ssr, -1)];
  return c;
}

}  // namespace

CandidateFit FitCameraDefocus(const CandidateContext& ctx) { return FitBlur(ctx, "camera_defocus", "blur_sigma_px", true); }

CandidateFit FitProjectorDefocus(const CandidateContext& ctx) {
  return FitBlur(ctx, "defocus", "blur_sigma_projector_px", false);
}

}  // namespace ramtk::diagnose::fringe
