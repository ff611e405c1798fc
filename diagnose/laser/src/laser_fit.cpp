#include "ramtk/diagnose/laser/detail/laser_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "ramtk/core/ceres_solve.h"
#include "ramtk/diagnose/engine/model_selection.h"

namespace ramtk::diagnose::laser_detail {
namespace {

Eigen::VectorXd Rows(const Eigen::VectorXd& r, const std::vector<bool>& use) {
  Eigen::VectorXd out(std::count(use.begin(), use.end(), true));
  for (int i = 0, k = 0; i < r.size(); ++i)
    if (use[i]) out(k++) = r(i);
  return out;
}

}  // namespace

double Rms(const Eigen::VectorXd& v) { return v.size() ? std::sqrt(v.squaredNorm() / v.size()) : 0.0; }

namespace {

// The model's residuals on the used rows as a Ceres cost of the free parameters, with the
// Jacobian by central differences at the model's own step per parameter (the residual models
// are closed-form geometry evaluated by code that is not templated for automatic
// differentiation).
class ResidualModelCost : public ceres::CostFunction {
 public:
  ResidualModelCost(const ResidualModel& model, const std::vector<int>& free, const std::vector<bool>& use,
                    const Eigen::VectorXd& fixed)
      : model_(model), free_(free), use_(use), fixed_(fixed) {
    set_num_residuals(static_cast<int>(std::count(use.begin(), use.end(), true)));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free.size()));
  }

  Eigen::VectorXd Full(const double* p) const {
    Eigen::VectorXd full = fixed_;
    for (std::size_t j = 0; j < free_.size(); ++j) full(free_[j]) = p[j];
    return full;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::VectorXd p = Full(parameters[0]);
    const Eigen::VectorXd r = Rows(model_.residuals(p), use_);
    if (!r.allFinite()) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
    if (jacobians && jacobians[0]) {
      const int n = static_cast<int>(r.size()), k = static_cast<int>(free_.size());
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(jacobians[0], n, k);
      for (int j = 0; j < k; ++j) {
        const int i = free_[j];
        Eigen::VectorXd hi = p, lo = p;
        hi(i) += model_.step(i);
        lo(i) -= model_.step(i);
        jac.col(j) = (Rows(model_.residuals(hi), use_) - Rows(model_.residuals(lo), use_)) / (2.0 * model_.step(i));
      }
      if (!jac.allFinite()) return false;
    }
    return true;
  }

 private:
  const ResidualModel& model_;
  const std::vector<int>& free_;
  const std::vector<bool>& use_;
  Eigen::VectorXd fixed_;
};

}  // namespace

FitResult Fit(const ResidualModel& model, const std::vector<int>& free, const std::vector<bool>& use,
              const Eigen::VectorXd& start) {
  FitResult out;
  out.params = start;
  out.sigma = Eigen::VectorXd::Zero(start.size());
  const int n = static_cast<int>(std::count(use.begin(), use.end(), true)), k = static_cast<int>(free.size());
  if (k == 0 || n == 0) {
    const Eigen::VectorXd r = Rows(model.residuals(start), use);
    out.rms = Rms(r);
    out.ok = r.allFinite();
    return out;
  }
  std::vector<double> x(static_cast<std::size_t>(k));
  for (int j = 0; j < k; ++j) x[j] = start(free[j]);
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ResidualModelCost cost(model, free, use, start);
  problem.AddResidualBlock(&cost, nullptr, x.data());
  // Relative cost change 1e-12: the residuals are mm / deg, fitted to ~1e-4. One thread: candidates
  // and folds are evaluated in parallel by the callers.
  const ceres::Solver::Options so = DenseSolverOptions({100, 1e-12, 1e-12, 1e-14});
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  out.params = cost.Full(x.data());
  const double sum_sq = 2.0 * summary.final_cost;
  out.rms = std::sqrt(sum_sq / n);
  out.ok = std::isfinite(sum_sq) && summary.termination_type != ceres::FAILURE;
  if (n > k) {
    // Parameter covariance (J^T J)^-1 scaled by the residual variance sum r^2 / (n - k); a
    // direction the rows do not constrain gives no sigma (NaN), not a pseudo-inverse's zero.
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.num_threads = 1;
    ceres::Covariance covariance(co);
    const std::vector<std::pair<const double*, const double*>> blocks = {{x.data(), x.data()}};
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> cov(k, k);
    if (covariance.Compute(blocks, &problem) && covariance.GetCovarianceBlock(x.data(), x.data(), cov.data())) {
      const double s2 = sum_sq / (n - k);
      for (int j = 0; j < k; ++j) out.sigma(free[j]) = std::sqrt(std::max(0.0, cov(j, j) * s2));
    } else {
      for (int j = 0; j < k; ++j) out.sigma(free[j]) = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return out;
}

CandidateOutcome EvaluateCandidate(const ResidualModel& model, const std::vector<int>& base, const CandidateSpec& spec,
                                   int num_folds) {
  CandidateOutcome out;
  std::vector<int> free = base;
  free.insert(free.end(), spec.params.begin(), spec.params.end());
  const int n = static_cast<int>(model.group.size());
  out.full = Fit(model, free, std::vector<bool>(n, true), model.initial);
  const bool leave_one_out = num_folds >= model.num_groups;
  const int folds = leave_one_out ? model.num_groups : num_folds;
  const std::vector<int> fold_of_group = leave_one_out ? std::vector<int>() : FoldOfGroup(model.num_groups, folds);
  auto fold_of = [&](int row) { return leave_one_out ? model.group[row] : fold_of_group[model.group[row]]; };
  out.heldout_resid = Eigen::VectorXd::Zero(n);
  for (int f = 0; f < folds; ++f) {
    std::vector<bool> use(n);
    bool any = false;
    for (int i = 0; i < n; ++i) any |= !(use[i] = fold_of(i) != f);
    if (!any) continue;
    // Start from the full fit: the held-out rows only change it slightly, and it keeps the
    // damped iteration away from other minima.
    const FitResult fit = Fit(model, free, use, out.full.params);
    const Eigen::VectorXd r = model.residuals(fit.params);
    for (int i = 0; i < n; ++i)
      if (!use[i]) out.heldout_resid(i) = r(i);
  }
  CandidateFit& c = out.fit;
  c.effect = spec.effect;
  c.num_parameters = static_cast<int>(spec.params.size());
  for (int i : spec.params) {
    c.parameters[model.names[i]] = out.full.params(i);
    c.sigmas[model.names[i]] = out.full.sigma(i);
    if (model.lower.size() == model.initial.size() &&
        (out.full.params(i) < model.lower(i) || out.full.params(i) > model.upper(i))) {
      std::ostringstream why;
      why.precision(4);
      why << model.names[i] << " = " << out.full.params(i) << " outside the plausible [" << model.lower(i) << ", "
          << model.upper(i) << "]";
      c.implausible += (c.implausible.empty() ? "" : "; ") + why.str();
    }
  }
  c.train_rms = out.full.rms;
  c.heldout_rms = Rms(out.heldout_resid);
  c.heldout_count = n;
  return out;
}

int Conclude(const std::vector<CandidateOutcome>& outcomes, double min_improvement, Diagnosis* d) {
  std::vector<CandidateFit> fits;
  for (const CandidateOutcome& o : outcomes) fits.push_back(o.fit);
  SelectionOptions selection;
  selection.min_improvement = min_improvement;
  SelectCandidate(&fits, selection);
  d->candidates = fits;
  int none = 0, chosen = 0;
  for (int i = 0; i < static_cast<int>(outcomes.size()); ++i) {
    if (outcomes[i].fit.effect == kNoEffect) none = i;
    if (outcomes[i].fit.effect == fits.front().effect) chosen = i;
  }
  if (!d->structure_found) chosen = none;
  const CandidateFit& c = outcomes[chosen].fit;
  d->rms_before = outcomes[none].fit.heldout_rms;
  d->rms_after = c.heldout_rms;
  d->excess_removed = ExcessRemoved(d->rms_before, d->rms_after, d->noise_floor_rms);
  d->parameters = c.parameters;
  d->sigmas = c.sigmas;
  for (const CandidateFit& f : fits)
    if (f.effect == c.effect) d->confidence = f.weight;
  d->cause = c.effect;
  if (d->structure_found && chosen == none) d->cause = kUnexplained;
  return chosen;
}

CandidateOutcome AddFurtherEffects(const ResidualModel& model, const std::vector<int>& base,
                                   const std::vector<CandidateSpec>& specs,
                                   const std::vector<CandidateOutcome>& outcomes, int chosen, int num_folds,
                                   double min_improvement, const std::string& label, Diagnosis* d) {
  CandidateOutcome current = outcomes[chosen];
  std::ostringstream line;
  line << label << ": ";
  for (const CandidateOutcome& o : outcomes)
    if (o.fit.effect == kNoEffect) line << "current model " << o.fit.heldout_rms << " " << d->unit;
  if (outcomes[chosen].fit.effect == kNoEffect || d->cause == kUnexplained) {
    d->findings.push_back(line.str());
    return current;
  }
  line << ", " << d->cause << " " << current.fit.heldout_rms << " " << d->unit;
  CandidateSpec acc = specs[chosen];
  std::vector<bool> used(specs.size(), false);
  used[chosen] = true;
  for (size_t i = 0; i < specs.size(); ++i) used[i] = used[i] || specs[i].effect == kNoEffect;
  while (true) {
    std::vector<CandidateOutcome> stage = {current};
    stage.front().fit.effect = kNoEffect;
    stage.front().fit.num_parameters = 0;
    std::vector<int> index = {-1};
    for (size_t i = 0; i < specs.size(); ++i) {
      if (used[i]) continue;
      CandidateSpec more{specs[i].effect, acc.params};
      more.params.insert(more.params.end(), specs[i].params.begin(), specs[i].params.end());
      CandidateOutcome o = EvaluateCandidate(model, base, more, num_folds);
      o.fit.num_parameters = static_cast<int>(specs[i].params.size());
      stage.push_back(o);
      index.push_back(static_cast<int>(i));
    }
    if (stage.size() == 1) break;
    std::vector<CandidateFit> fits;
    for (const CandidateOutcome& o : stage) fits.push_back(o.fit);
    SelectionOptions selection;
    selection.min_improvement = min_improvement;
    SelectCandidate(&fits, selection);
    if (fits.front().effect == kNoEffect) break;
    int k = 1;
    while (stage[k].fit.effect != fits.front().effect) ++k;
    const int spec = index[k];
    used[spec] = true;
    acc.effect += "+" + specs[spec].effect;
    acc.params.insert(acc.params.end(), specs[spec].params.begin(), specs[spec].params.end());
    current = stage[k];
    d->findings.push_back("further effect on top of " + d->cause + ": " + specs[spec].effect);
    d->parameters = current.fit.parameters;
    d->sigmas = current.fit.sigmas;
    d->rms_after = current.fit.heldout_rms;
    d->excess_removed = ExcessRemoved(d->rms_before, d->rms_after, d->noise_floor_rms);
    line << ", + " << specs[spec].effect << " " << d->rms_after << " " << d->unit;
    CandidateFit combined = current.fit;
    combined.effect = acc.effect;
    combined.num_parameters = static_cast<int>(acc.params.size());
    combined.score = combined.heldout_count * std::log(std::max(1e-300, combined.heldout_rms * combined.heldout_rms)) +
                     2.0 * combined.num_parameters;
    combined.weight = 0.0;  // a later stage, outside the first stage's evidence weights
    d->candidates.push_back(combined);
  }
  if (acc.effect != specs[chosen].effect) {
    std::ostringstream est;
    est.precision(4);
    est << "estimates (" << acc.effect << "):";
    for (const auto& [k, v] : d->parameters)
      est << " " << k << " = " << std::fixed << v << " ± " << d->sigmas.at(k) << ";";
    d->findings.push_back(est.str());
  }
  d->findings.push_back(line.str());
  return current;
}

}  // namespace ramtk::diagnose::laser_detail
