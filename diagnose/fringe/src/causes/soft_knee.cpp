// Soft knee response of the sensor.
#include <Eigen/Dense>
#include <cmath>

#include "../fringe_fit_kit.h"

namespace ramtk::diagnose::fringe {

// soft_knee_response: the sensor compresses the signal above a knee K = k·F smoothly towards
// full scale F. Unlike a projector response, whose harmonics are the same share of B at every
// pixel, the distortion depends on each pixel's absolute level: none below the knee. Two
// shapes of soft clip, S ↦ K + (F − K)·g((S − K)/(F − K)) with g = tanh or x/√(1 + x²), on a
// grid of knees; every pixel is refitted on its linearised phase samples g⁻¹ and predicted
// through g. Knee and shape chosen per fold on the training tiles.
CandidateFit FitSoftKneeResponse(const CandidateContext& ctx) {
  const FringeFit& fit = *ctx.fit;
  const auto& by_tile = ctx.by_tile;
  const auto& fold_of_tile = ctx.fold_of_tile;
  const auto& count = ctx.count;
  const int folds = ctx.folds;
  const int nt = static_cast<int>(by_tile.size());
  const int nf = fit.frames, n = fit.steps;
  const double full = fit.full_scale;
  std::vector<std::pair<double, int>> grid;  // (knee fraction, shape: 0 tanh, 1 algebraic)
  for (int shape = 0; shape < 2; ++shape)
    for (double k = 0.20; k < 0.951; k += 0.05) grid.push_back({k, shape});
  const int ng = static_cast<int>(grid.size());
  auto compress = [full](double v, double knee, int shape) {
    if (v <= knee) return v;
    const double x = (v - knee) / (full - knee);
    return knee + (full - knee) * (shape == 0 ? std::tanh(x) : x / std::sqrt(1.0 + x * x));
  };
  auto expand = [full](double v, double knee, int shape) {
    if (v <= knee) return v;
    const double y = std::min((v - knee) / (full - knee), 0.995);
    return knee + (full - knee) * (shape == 0 ? std::atanh(y) : y / std::sqrt(1.0 - y * y));
  };
  std::vector<std::vector<double>> ssr(ng, std::vector<double>(nt, 0.0));
  cv::parallel_for_(cv::Range(0, nt), [&](const cv::Range& range) {
    std::vector<double> obs(nf);
    for (int t = range.start; t < range.end; ++t)
      for (int i : by_tile[t]) {
        const PixelFit& p = fit.pixels[i];
        double base = 0, top = 0;
        for (int f = 0; f < nf; ++f) {
          const size_t idx = static_cast<size_t>(i) * nf + f;
          obs[f] = fit.images[f].at<float>(p.y, p.x);
          if (std::isfinite(fit.residual[idx])) base += std::pow(fit.residual[idx] * W(fit, idx), 2);
        }
        for (int k = 0; k < n; ++k) top = std::max(top, obs[fit.phase_frame[k]]);
        const double gray_top = p.a + p.b / 0.05;  // the brightest a Gray prediction can be
        for (int s = 0; s < ng; ++s) {
          const double knee = grid[s].first * full;
          const int shape = grid[s].second;
          if (top <= knee && gray_top <= knee) {
            ssr[s][t] += base;  // nothing of this pixel is above the knee
            continue;
          }
          Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
          Eigen::Vector3d b = Eigen::Vector3d::Zero();
          for (int k = 0; k < n; ++k) {
            const double d = StepShift(k, n);
            const Eigen::Vector3d row(1.0, std::cos(d), -std::sin(d));
            a += row * row.transpose(), b += row * expand(obs[fit.phase_frame[k]], knee, shape);
          }
          const Eigen::Vector3d x = a.ldlt().solve(b);
          PixelFit q = p;
          q.a = x(0), q.b = std::hypot(x(1), x(2)), q.phi = std::atan2(x(2), x(1));
          double sum = 0;
          for (int k = 0; k < n; ++k) {
            const size_t idx = static_cast<size_t>(i) * nf + fit.phase_frame[k];
            if (!std::isfinite(fit.residual[idx])) continue;
            const double pred = compress(q.a + q.b * std::cos(q.phi + StepShift(k, n)), knee, shape);
            sum += std::pow((obs[fit.phase_frame[k]] - pred) * W(fit, idx), 2);
          }
          for (int j = 0; j < fit.gray_bits; ++j) {
            const int f = fit.gray_frame[j];
            const size_t idx = static_cast<size_t>(i) * nf + f;
            if (!std::isfinite(fit.residual[idx])) continue;
            const double pred = compress(GrayIntensity(fit, q, j, 0.0), knee, shape);
            sum += std::pow((obs[f] - pred) * W(fit, idx), 2);
          }
          ssr[s][t] += sum;
        }
      }
  });
  auto best_without = [&](int fold) {
    int best = 0;
    double best_v = 1e300;
    for (int s = 0; s < ng; ++s) {
      double v = 0;
      for (int t = 0; t < nt; ++t)
        if (fold_of_tile[t] != fold) v += ssr[s][t];
      if (v < best_v) best_v = v, best = s;
    }
    return best;
  };
  std::vector<int> chosen(folds);
  for (int k = 0; k < folds; ++k) chosen[k] = best_without(k);
  CandidateFit c;
  c.effect = "soft_knee_response";
  c.num_parameters = 2;
  CrossValidate(
      fold_of_tile, folds, count, [&](int k, int t) { return ssr[chosen[k]][t]; }, &c);
  const int b = best_without(-1);
  c.parameters["knee_fraction"] = grid[b].first;
  c.parameters["knee_shape_algebraic"] = grid[b].second;
  return c;
}

}  // namespace ramtk::diagnose::fringe
