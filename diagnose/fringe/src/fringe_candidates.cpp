// Candidate extensions of the ideal fringe model, each fitted on the training tiles and scored on
// the held-out tiles: the cross-validation and the linear-extension fit the candidates share, and
// FitCandidates, which fits every row of the fringe cause table (the fits are in causes/), then the
// registered causes.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>

#include "fringe_fit_kit.h"
#include "ramtk/diagnose/engine/model_selection.h"

namespace ramtk::diagnose::fringe {

std::vector<std::vector<int>> PixelsByTile(const FringeFit& fit) {
  std::vector<std::vector<int>> out(fit.tiles_x * fit.tiles_y);
  for (size_t i = 0; i < fit.pixels.size(); ++i) out[fit.pixels[i].tile].push_back(static_cast<int>(i));
  return out;
}

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

CandidateFit FitLinear(const CandidateContext& ctx, const std::string& name, int m, const BasisFn& basis,
                       const std::function<std::string(int)>& key, const std::function<double(int, double)>& scale) {
  const FringeFit& fit = *ctx.fit;
  const std::vector<std::vector<int>>& by_tile = ctx.by_tile;
  const std::vector<int>& fold_of_tile = ctx.fold_of_tile;
  const int folds = ctx.folds;
  const double sigma = ctx.sigma;
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

CandidateFit NotFitted(const CandidateContext&) { return CandidateFit{}; }

std::vector<CandidateFit> FitCandidates(const FringeFit& fit, int folds, double sigma) {
  CandidateContext ctx;
  ctx.fit = &fit;
  ctx.by_tile = PixelsByTile(fit);
  ctx.folds = folds;
  ctx.sigma = sigma;
  const int nt = static_cast<int>(ctx.by_tile.size());
  ctx.fold_of_tile = FoldOfGroup(nt, folds);
  const int nf = fit.frames;

  // The current model.
  std::vector<double> base_ssr(nt, 0.0);
  ctx.count.assign(nt, 0);
  for (int t = 0; t < nt; ++t)
    for (int i : ctx.by_tile[t]) {
      for (int f = 0; f < nf; ++f) {
        const size_t idx = static_cast<size_t>(i) * nf + f;
        const double r = fit.residual[idx] * W(fit, idx);
        if (std::isfinite(r)) base_ssr[t] += r * r, ++ctx.count[t];
      }
    }
  CandidateFit none;
  none.effect = kNoEffect;
  CrossValidate(
      ctx.fold_of_tile, folds, ctx.count, [&](int, int t) { return base_ssr[t]; }, &none);
  std::vector<CandidateFit> out = {none};
  // Every row of the fringe cause table that the ideal model can fit, in table order.
  using FitFn = CandidateFit (*)(const CandidateContext&);
  static const FitFn kFits[] = {
#define RAMTK_FRINGE_CAUSE(name, fit, lo, hi, either_sign, visible, parameters, plausible, help) fit,
#include "ramtk/diagnose/engine/fringe_causes.def"
  };
  for (FitFn f : kFits)
    if (f != &NotFitted) out.push_back(f(ctx));
  for (const FringeLinearCause& cause : RegisteredFringeCauses()) out.push_back(FitRegistered(ctx, cause));
  return out;
}

}  // namespace ramtk::diagnose::fringe
