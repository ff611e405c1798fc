// Candidate extensions of the ideal fringe model, each fitted on the training tiles and scored on
// the held-out tiles. Linear extensions (harmonics, phase-step errors, per-frame gain/offset) are
// first-order corrections of the residual, projected like the per-pixel fit projects the data (the
// per-pixel A, B, φ absorb whatever lies in the span of 1, cos δ_k, sin δ_k over the phase frames).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>

#include "fringe_internal.h"
#include "ramtk/diagnose/engine/model_selection.h"

namespace ramtk::diagnose::fringe {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Weight of residual sample k (σ̄/σ(I), 1 without a noise-level function).
inline double W(const FringeFit& fit, size_t k) { return fit.weight.empty() ? 1.0 : fit.weight[k]; }

std::vector<std::vector<int>> PixelsByTile(const FringeFit& fit) {
  std::vector<std::vector<int>> out(fit.tiles_x * fit.tiles_y);
  for (size_t i = 0; i < fit.pixels.size(); ++i) out[fit.pixels[i].tile].push_back(static_cast<int>(i));
  return out;
}

// Per-tile sums of squared residuals.
struct TileSums {
  std::vector<double> ssr;
  std::vector<long> count;
};

// Held-out and training RMS from per-fold choices: `ssr_for(fold, tile)` is the SSR of `tile` under
// the model fitted without `fold`.
void CrossValidate(const std::vector<int>& fold_of_tile, int folds, const std::vector<long>& count,
                   const std::function<double(int, int)>& ssr_for, CandidateFit* c) {
  double held = 0, train = 0;
  long nheld = 0, ntrain = 0;
  c->heldout_group_ssr.assign(count.size(), 0.0);
  for (int k = 0; k < folds; ++k)
    for (size_t t = 0; t < count.size(); ++t) {
      if (count[t] == 0) continue;
      const double s = ssr_for(k, static_cast<int>(t));
      if (fold_of_tile[t] == k)
        held += s, nheld += count[t], c->heldout_group_ssr[t] = s;
      else
        train += s, ntrain += count[t];
    }
  c->heldout_rms = nheld > 0 ? std::sqrt(std::max(held, 0.0) / nheld) : 0.0;
  c->train_rms = ntrain > 0 ? std::sqrt(std::max(train, 0.0) / ntrain) : 0.0;
  c->heldout_count = static_cast<int>(nheld);
}

// A linear extension: r ≈ M·c with M (frames × m) built per pixel.
using BasisFn = std::function<void(const FringeFit&, const PixelFit&, Eigen::Ref<Eigen::MatrixXd>)>;

CandidateFit FitLinear(const FringeFit& fit, const std::string& name, int m, const BasisFn& basis,
                       const std::vector<std::vector<int>>& by_tile, const std::vector<int>& fold_of_tile, int folds,
                       double sigma, const std::function<std::string(int)>& key,
                       const std::function<double(int, double)>& scale) {
  const int nt = static_cast<int>(by_tile.size());
  const int nf = fit.frames, n = fit.steps;
  std::vector<Eigen::MatrixXd> g(nt, Eigen::MatrixXd::Zero(m, m));
  std::vector<Eigen::VectorXd> h(nt, Eigen::VectorXd::Zero(m));
  std::vector<double> s(nt, 0.0);
  std::vector<long> count(nt, 0);
  std::vector<double> cos_d(n), sin_d(n);
  for (int k = 0; k < n; ++k) cos_d[k] = std::cos(StepShift(k, n)), sin_d[k] = std::sin(StepShift(k, n));
  cv::parallel_for_(cv::Range(0, nt), [&](const cv::Range& range) {
    Eigen::MatrixXd mat(nf, m);
    Eigen::VectorXd r(nf);
    std::vector<int> nz;
    nz.reserve(m);
    for (int t = range.start; t < range.end; ++t)
      for (int i : by_tile[t]) {
        const PixelFit& p = fit.pixels[i];
        mat.setZero();
        basis(fit, p, mat);
        // Project the phase rows off span{1, cos δ_k, sin δ_k}.
        for (int col = 0; col < m; ++col) {
          double mean = 0, cs = 0, sn = 0;
          bool any = false;
          for (int k = 0; k < n; ++k) {
            const double v = mat(fit.phase_frame[k], col);
            any = any || v != 0.0;
            mean += v, cs += v * cos_d[k], sn += v * sin_d[k];
          }
          if (!any) continue;
          mean /= n, cs *= 2.0 / n, sn *= 2.0 / n;
          for (int k = 0; k < n; ++k) mat(fit.phase_frame[k], col) -= mean + cs * cos_d[k] + sn * sin_d[k];
        }
        long used = 0;
        for (int f = 0; f < nf; ++f) {
          const size_t idx = static_cast<size_t>(i) * nf + f;
          r(f) = fit.residual[idx];
          if (std::isfinite(r(f))) {
            ++used;
            const double w = W(fit, idx);
            r(f) *= w, mat.row(f) *= w;
          } else {
            r(f) = 0, mat.row(f).setZero();
          }
        }
        // Rows are sparse (a Gray frame touches one or two columns): accumulate over non-zeros.
        for (int f = 0; f < nf; ++f) {
          nz.clear();
          for (int col = 0; col < m; ++col)
            if (mat(f, col) != 0.0) nz.push_back(col);
          for (int a : nz) {
            const double va = mat(f, a);
            h[t](a) += va * r(f);
            for (int b : nz) g[t](a, b) += va * mat(f, b);
          }
        }
        s[t] += r.squaredNorm();
        count[t] += used;
      }
  });
  Eigen::MatrixXd gall = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd hall = Eigen::VectorXd::Zero(m);
  for (int t = 0; t < nt; ++t) gall += g[t], hall += h[t];
  auto solve = [&](const Eigen::MatrixXd& gm, const Eigen::VectorXd& hv) {
    const double ridge = 1e-9 * std::max(gm.trace() / m, 1e-30);
    Eigen::MatrixXd reg = gm;
    reg.diagonal().array() += ridge;
    return Eigen::VectorXd(reg.ldlt().solve(hv));
  };
  std::vector<Eigen::VectorXd> coef(folds);
  for (int k = 0; k < folds; ++k) {
    Eigen::MatrixXd gk = gall;
    Eigen::VectorXd hk = hall;
    for (int t = 0; t < nt; ++t)
      if (fold_of_tile[t] == k) gk -= g[t], hk -= h[t];
    coef[k] = solve(gk, hk);
  }
  CandidateFit c;
  c.effect = name;
  CrossValidate(
      fold_of_tile, folds, count,
      [&](int k, int t) { return s[t] - 2.0 * coef[k].dot(h[t]) + coef[k].dot(g[t] * coef[k]); }, &c);
  // Effective number of parameters: the rank of the (scaled) normal matrix.
  Eigen::VectorXd d = gall.diagonal().cwiseMax(1e-30).cwiseSqrt().cwiseInverse();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d.asDiagonal() * gall * d.asDiagonal());
  const double top = eig.eigenvalues().maxCoeff();
  int rank = 0;
  for (int i = 0; i < m; ++i) rank += eig.eigenvalues()(i) > 1e-7 * top ? 1 : 0;
  c.num_parameters = rank;
  const Eigen::VectorXd all = solve(gall, hall);
  Eigen::MatrixXd reg = gall;
  reg.diagonal().array() += 1e-9 * std::max(gall.trace() / m, 1e-30);
  const Eigen::MatrixXd cov = reg.inverse() * sigma * sigma;
  for (int i = 0; i < m; ++i) {
    const std::string k = key(i);
    if (k.empty()) continue;
    c.parameters[k] = scale(i, all(i));
    c.sigmas[k] = std::abs(scale(i, std::sqrt(std::max(cov(i, i), 0.0))));
  }
  return c;
}

std::string Numbered(const std::string& prefix, int i, const std::string& suffix) {
  std::ostringstream s;
  s << prefix << std::setw(2) << std::setfill('0') << i << suffix;
  return s.str();
}

}  // namespace

std::vector<CandidateFit> FitCandidates(const FringeFit& fit, int folds, double sigma) {
  const auto by_tile = PixelsByTile(fit);
  const int nt = static_cast<int>(by_tile.size());
  const std::vector<int> fold_of_tile = FoldOfGroup(nt, folds);
  const int nf = fit.frames, n = fit.steps;
  std::vector<CandidateFit> out;

  // The current model.
  std::vector<double> base_ssr(nt, 0.0);
  std::vector<long> count(nt, 0);
  for (int t = 0; t < nt; ++t)
    for (int i : by_tile[t]) {
      for (int f = 0; f < nf; ++f) {
        const size_t idx = static_cast<size_t>(i) * nf + f;
        const double r = fit.residual[idx] * W(fit, idx);
        if (std::isfinite(r)) base_ssr[t] += r * r, ++count[t];
      }
    }
  CandidateFit none;
  none.effect = kNoEffect;
  CrossValidate(
      fold_of_tile, folds, count, [&](int, int t) { return base_ssr[t]; }, &none);
  out.push_back(none);

  // projector_nonlinearity: harmonics h = 2..H of a memoryless response, B_h/B_1 = r_h. Phase frames
  // gain B·cos(hθ_k); Gray frames the response's white/black levels B·Σr_h and B·Σ(−1)^h r_h.
  const int hmax = std::max(2, (n + 1) / 2 - 1);  // the harmonics an N-step block resolves
  const int nh = hmax - 1;
  out.push_back(FitLinear(
      fit, "projector_nonlinearity", nh,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int c = 0; c < nh; ++c) {
          const int hh = c + 2;
          for (int k = 0; k < n; ++k) mat(ft.phase_frame[k], c) = p.b * std::cos(hh * (p.phi + StepShift(k, n)));
          double w, sp;
          Footprint(p, &w, &sp);
          for (int j = 0; j < ft.gray_bits; ++j) {
            const double q = GrayPattern(ft, j, p.u, w, sp);
            mat(ft.gray_frame[j], c) = p.b * (q + (1.0 - q) * (hh % 2 == 0 ? 1.0 : -1.0));
          }
        }
      },
      by_tile, fold_of_tile, folds, sigma, [](int c) { return "B" + std::to_string(c + 2) + "/B1"; },
      [](int, double v) { return v; }));

  // phase_shift_error: step k shifted by ε_k: −B·sin(θ_k)·ε_k.
  out.push_back(FitLinear(
      fit, "phase_shift_error", n,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int k = 0; k < n; ++k) mat(ft.phase_frame[k], k) = -p.b * std::sin(p.phi + StepShift(k, n));
      },
      by_tile, fold_of_tile, folds, sigma, [](int k) { return Numbered("step_", k, "_error_deg"); },
      [](int, double v) { return v * 180.0 / kPi; }));

  // intensity_drift: per-frame gain g_f and offset o_f: I_f ≈ (1 + g_f)·ideal + o_f.
  out.push_back(FitLinear(
      fit, "intensity_drift", 2 * nf,
      [&](const FringeFit& ft, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
        for (int f = 0; f < nf; ++f) {
          mat(f, f) = IdealIntensity(ft, p, f);
          mat(f, nf + f) = 1.0;
        }
      },
      by_tile, fold_of_tile, folds, sigma,
      [nf](int i) { return i < nf ? Numbered("gain_frame_", i, "") : Numbered("offset_frame_", i - nf, "_DN"); },
      [](int, double v) { return v; }));

  // saturation: the camera clips at full scale; clipped pixels refitted on their unclipped phase
  // samples and every prediction clipped.
  {
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
        fold_of_tile, folds, count, [&](int, int t) { return ssr[t]; }, &c);
    c.parameters["clip_level_DN"] = clip;
    c.parameters["clipped_pixels"] = static_cast<double>(refit);
    out.push_back(c);
  }

  // Blur: the phase frames only lose modulation, which B absorbs; the Gray-code frames keep
  // their full contrast (more than B) and their edges spread. Two candidates differ in where the
  // blur happens, hence in how its width in projector px varies across the image:
  // `camera_defocus` blurs the image by σ camera px, so the code edges spread by σ·|∇u|
  // projector px (more where the surface is seen foreshortened); `defocus` (projector) blurs the
  // pattern by σ projector px everywhere. σ on a grid, chosen per fold on the training tiles.
  const auto blur_candidate = [&](const std::string& name, const std::string& key, bool camera_space) {
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
  };
  out.push_back(blur_candidate("camera_defocus", "blur_sigma_px", true));
  out.push_back(blur_candidate("defocus", "blur_sigma_projector_px", false));

  // soft_knee_response: the sensor compresses the signal above a knee K = k·F smoothly towards
  // full scale F. Unlike a projector response, whose harmonics are the same share of B at every
  // pixel, the distortion depends on each pixel's absolute level: none below the knee. Two
  // shapes of soft clip, S ↦ K + (F − K)·g((S − K)/(F − K)) with g = tanh or x/√(1 + x²), on a
  // grid of knees; every pixel is refitted on its linearised phase samples g⁻¹ and predicted
  // through g. Knee and shape chosen per fold on the training tiles.
  {
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
    out.push_back(c);
  }
  return out;
}

}  // namespace ramtk::diagnose::fringe
