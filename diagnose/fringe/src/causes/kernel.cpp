// sampling_kernel: the camera's pixel response differs from the stated sampling kernel.
#include <algorithm>
#include <cmath>

#include "../fringe_fit_kit.h"

namespace ramtk::diagnose::fringe {
namespace {

// Per-tile SSR of every pixel's samples (phase frames as they are, Gray frames predicted with
// `kernel` in place of the stated one).
std::vector<double> TileSsr(const CandidateContext& ctx, const SamplingKernel& kernel) {
  const FringeFit& fit = *ctx.fit;
  const int nt = static_cast<int>(ctx.by_tile.size());
  const int nf = fit.frames;
  std::vector<double> ssr(nt, 0.0);
  cv::parallel_for_(cv::Range(0, nt), [&](const cv::Range& range) {
    for (int t = range.start; t < range.end; ++t)
      for (int i : ctx.by_tile[t]) {
        const PixelFit& p = fit.pixels[i];
        double sum = 0;
        for (int f : fit.phase_frame) {
          const size_t idx = static_cast<size_t>(i) * nf + f;
          sum += std::pow(fit.residual[idx] * W(fit, idx), 2);
        }
        for (int j = 0; j < fit.gray_bits; ++j) {
          const int f = fit.gray_frame[j];
          const size_t idx = static_cast<size_t>(i) * nf + f;
          if (!std::isfinite(fit.residual[idx])) continue;
          const double pred = SensorExpectation(fit, p, GrayIntensityWith(fit, kernel, p, j, 0.0));
          sum += std::pow((fit.images[f].at<float>(p.y, p.x) - pred) * W(fit, idx), 2);
        }
        ssr[t] += sum;
      }
  });
  return ssr;
}

}  // namespace

// The kernel that fits: a box of fill factor 0 … 1 and a Gaussian PSF of 0 … 1 camera px (a focused
// lens; a wider blur is camera_defocus), on a
// grid (then 9 PSF steps between the coarse neighbours of the best), the Gray-code frames
// predicted with it over the samples the stated kernel's edge band keeps. Chosen per fold on the
// training tiles; the parameters' sigmas are the delete-a-fold jackknife of the fold choices (at
// least the grid step over √12).
CandidateFit FitSamplingKernel(const CandidateContext& ctx) {
  const int nt = static_cast<int>(ctx.by_tile.size());
  std::vector<SamplingKernel> grid;
  std::vector<std::vector<double>> ssr;
  const auto add = [&](double fill, double psf) {
    grid.push_back({fill, psf});
    ssr.push_back(TileSsr(ctx, grid.back()));
  };
  const std::vector<double> fills = {0, 0.25, 0.5, 0.75, 1}, psfs = {0, 0.2, 0.4, 0.6, 0.8, 1.0};
  for (double f : fills)
    for (double s : psfs) add(f, s);
  const auto best_without = [&](int fold) {
    int best = 0;
    double best_v = 1e300;
    for (size_t g = 0; g < grid.size(); ++g) {
      double v = 0;
      for (int t = 0; t < nt; ++t)
        if (ctx.fold_of_tile[t] != fold) v += ssr[g][t];
      if (v < best_v) best_v = v, best = static_cast<int>(g);
    }
    return best;
  };
  const SamplingKernel coarse = grid[best_without(-1)];
  const double lo = std::max(0.0, coarse.psf_sigma_px - 0.2), hi = std::min(1.0, coarse.psf_sigma_px + 0.2);
  for (int k = 1; k < 10; ++k) add(coarse.fill_factor, lo + (hi - lo) * k / 10.0);
  std::vector<int> chosen(ctx.folds);
  for (int k = 0; k < ctx.folds; ++k) chosen[k] = best_without(k);
  CandidateFit c;
  c.effect = "sampling_kernel";
  c.num_parameters = 2;
  CrossValidate(
      ctx.fold_of_tile, ctx.folds, ctx.count, [&](int k, int t) { return ssr[chosen[k]][t]; }, &c);
  const SamplingKernel best = grid[best_without(-1)];
  c.parameters["fill_factor"] = best.fill_factor;
  c.parameters["psf_sigma_px"] = best.psf_sigma_px;
  const auto jackknife = [&](double SamplingKernel::*field, double step) {
    const int k = ctx.folds;
    double mean = 0, ss = 0;
    for (int f = 0; f < k; ++f) mean += grid[chosen[f]].*field / k;
    for (int f = 0; f < k; ++f) ss += std::pow(grid[chosen[f]].*field - mean, 2);
    return std::max(std::sqrt((k - 1.0) / k * ss), step / std::sqrt(12.0));
  };
  c.sigmas["fill_factor"] = jackknife(&SamplingKernel::fill_factor, 0.25);
  c.sigmas["psf_sigma_px"] = jackknife(&SamplingKernel::psf_sigma_px, (hi - lo) / 10.0);
  return c;
}

}  // namespace ramtk::diagnose::fringe
