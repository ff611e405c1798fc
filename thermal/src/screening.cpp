#include "ramtk/thermal/screening.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ramtk/core/autocorrelation.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::thermal {

std::string AcfOptions::Validate() const {
  if (max_lag < 0) return "max_lag must be >= 0";
  if (!(z > 0.0)) return "z must be > 0";
  if (!(max_fraction_outside >= 0.0 && max_fraction_outside <= 1.0)) return "max_fraction_outside must be in [0, 1]";
  return "";
}

std::string ScreeningOptions::Validate() const {
  if (keep < 0) return "keep must be >= 0 (0: chosen by held-out error)";
  if (min_keep < 1) return "min_keep must be >= 1";
  if (!(heldout_z >= 0.0 && std::isfinite(heldout_z))) return "heldout_z must be finite and >= 0";
  std::string p = acf.Validate();
  if (!p.empty()) return "acf: " + p;
  p = lambda.Validate();
  if (!p.empty()) return "lambda: " + p;
  p = identifiability.Validate();
  if (!p.empty()) return "identifiability: " + p;
  return identification.Validate();
}

AcfResult AutocorrelationTest(const Eigen::VectorXd& series, const AcfOptions& options) {
  AcfResult out;
  const int n = static_cast<int>(series.size());
  const int max_lag = options.max_lag > 0 ? std::min(options.max_lag, n - 1) : std::min(20, n / 4);
  out.band = options.z / std::sqrt(static_cast<double>(std::max(n, 1)));
  if (n < 3 || max_lag < 1) {
    out.steady = true;
    return out;
  }
  const std::vector<double> acf = Autocorrelation(std::vector<double>(series.data(), series.data() + n), max_lag);
  for (int k = 1; k <= max_lag; ++k) {
    out.acf.push_back(acf[k]);
    if (std::abs(acf[k]) > out.band) ++out.outside;
  }
  out.steady = out.outside <= options.max_fraction_outside * max_lag;
  return out;
}

std::string ScreeningSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf), "screening %s: %d steps, %d lambda evaluations, lambda %.2f%% -> %.2f%%, kept %s",
                message.c_str(), iterations, lambda_evaluations, initial_lambda, final_lambda,
                ParamListToString(selected).c_str());
  return buf;
}

namespace {

struct Scorer {
  const ThermalExperiment& experiment;
  const DriftModel drift_model;
  const MonitoringModel monitoring;
  Eigen::MatrixXd y;  // ball differences for the chosen poses
  int evaluations = 0;

  Scorer(const ThermalExperiment& e, const std::vector<int>& poses)
      : experiment(e),
        drift_model(e.model, e.setup, e.ball.taught),
        monitoring(e.model, e.setup, e.monitoring),
        y(e.ball.DifferencesFromReference(poses)) {}

  // ΔX per ball cycle (30 × ball cycles) and λ; *rms gets the RMS residual of the warm cycles.
  double Score(const IdentificationOptions& id, const LambdaOptions& lambda, Eigen::MatrixXd* x_ball,
               Eigen::MatrixXd* residuals = nullptr, double* rms = nullptr) {
    ++evaluations;
    const Eigen::MatrixXd x = drift_model.Solve(y, id);
    Eigen::MatrixXd x_mon(x.rows(), static_cast<Eigen::Index>(experiment.ball_column.size()));
    for (std::size_t c = 0; c < experiment.ball_column.size(); ++c) x_mon.col(c) = x.col(experiment.ball_column[c]);
    const Eigen::MatrixXd r = monitoring.Residuals(x_mon);
    if (x_ball != nullptr) *x_ball = x;
    if (residuals != nullptr) *residuals = r;
    if (rms != nullptr) {
      const Eigen::Index warm = r.cols() - 1;
      *rms = warm > 0 ? std::sqrt(r.rightCols(warm).squaredNorm() / static_cast<double>(r.rows() * warm)) : 0.0;
    }
    return Lambda(r, lambda);
  }
};

// Leave-one-pose-out errors of one parameter set, against an existing DriftModel.
Eigen::VectorXd PoseErrors(const DriftModel& drift_model, const Eigen::MatrixXd& y_all, int num_params,
                           const IdentificationOptions& options) {
  std::vector<int> poses = options.poses;
  if (poses.empty()) {
    for (int i = 0; i < drift_model.NumPoses(); ++i) poses.push_back(i);
  }
  const Eigen::Index warm = y_all.cols() - 1;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(poses.size()));
  if (warm < 1) return out;
  const bool enough = 3 * (static_cast<int>(poses.size()) - 1) >= num_params;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!enough) {
      out[static_cast<Eigen::Index>(k)] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    IdentificationOptions o = options;
    o.poses.clear();
    for (std::size_t j = 0; j < poses.size(); ++j) {
      if (j != k) o.poses.push_back(poses[j]);
    }
    Eigen::MatrixXd y(3 * o.poses.size(), y_all.cols());
    for (std::size_t j = 0; j < o.poses.size(); ++j) y.middleRows(3 * j, 3) = y_all.middleRows(3 * o.poses[j], 3);
    const Eigen::MatrixXd x = drift_model.Solve(y, o);
    const Eigen::MatrixXd err =
        y_all.middleRows(3 * poses[k], 3) - drift_model.FullSensitivity().middleRows(3 * poses[k], 3) * x;
    out[static_cast<Eigen::Index>(k)] = err.rightCols(warm).squaredNorm() / static_cast<double>(3 * warm);
  }
  return out;
}

int CountParams(const ThermalExperiment& e, const IdentificationOptions& o) {
  return static_cast<int>(o.params.empty() ? e.model.FreeParams().size() : o.params.size());
}

}  // namespace

Eigen::VectorXd HeldoutPoseErrors(const ThermalExperiment& experiment, const IdentificationOptions& options) {
  const DriftModel drift_model(experiment.model, experiment.setup, experiment.ball.taught);
  return PoseErrors(drift_model, experiment.ball.DifferencesFromReference({}), CountParams(experiment, options),
                    options);
}

// The element of S whose removal from `current` scores best (λ, then the lower RMS), or with
// first_improvement the first that does not lower λ.
struct Removal {
  int param = -1;
  double lambda = -1.0;
  Eigen::MatrixXd x_ball;
};

Removal BestRemoval(Scorer* scorer, const ScreeningOptions& options, const std::vector<int>& current,
                    const std::vector<int>& trial_set, double lambda) {
  IdentificationOptions id = options.identification;
  double best_lambda = -1.0, best_rms = 0.0;
  int best = -1;
  Eigen::MatrixXd best_x;
  for (int s : trial_set) {
    std::vector<int> reduced;
    for (int p : current) {
      if (p != s) reduced.push_back(p);
    }
    id.params = reduced;
    Eigen::MatrixXd x_trial;
    double rms_i = 0.0;
    const double lambda_i = scorer->Score(id, options.lambda, &x_trial, nullptr, &rms_i);
    if (lambda_i > best_lambda || (lambda_i == best_lambda && rms_i < best_rms)) {
      best_lambda = lambda_i;
      best_rms = rms_i;
      best = s;
      best_x = x_trial;
    }
    if (options.first_improvement && lambda_i >= lambda) {
      best_lambda = lambda_i;
      best = s;
      best_x = x_trial;
      break;
    }
  }
  return {best, best_lambda, best_x};
}

// Held-out error of every set on the path; the smallest set not worse than the best (index into
// *best) beyond heldout_z standard errors of the paired per-pose differences. Fills each step's
// held-out RMS and z.
int ChooseFromHeldout(const Scorer& scorer, const ThermalExperiment& experiment, const ScreeningOptions& options,
                      const std::vector<std::vector<int>>& path, ScreeningSummary* out, int* best_index) {
  ScreeningSummary& summary = *out;
  int& best = *best_index;
  // Held-out error of every set on the path; keep the smallest one not worse than the best
  // beyond heldout_z standard errors of the paired per-pose differences.
  const Eigen::MatrixXd y_all = experiment.ball.DifferencesFromReference({});
  std::vector<Eigen::VectorXd> errors;
  for (std::size_t i = 0; i < path.size(); ++i) {
    IdentificationOptions o = options.identification;
    o.params = path[i];
    errors.push_back(PoseErrors(scorer.drift_model, y_all, static_cast<int>(path[i].size()), o));
    const bool finite = errors.back().allFinite() && errors.back().size() > 0 && summary.steps[i].identifiable;
    summary.steps[i].heldout_rms_mm = finite ? std::sqrt(errors.back().mean()) : 0.0;
    if (finite && (best < 0 || errors.back().mean() < errors[best].mean())) best = static_cast<int>(i);
  }
  if (best < 0) {
    bool any_identifiable = false;
    for (const ScreeningStep& st : summary.steps) any_identifiable = any_identifiable || st.identifiable;
    if (!any_identifiable) {
      throw InputError({"", 0, "poses"}, "no set on the elimination path is identifiable with these poses "
                                         "(condition number above the guard's limit for every set)");
    }
    throw InputError({"", 0, "poses"}, "screening by held-out error needs enough ball poses to leave one out (" +
                                           std::to_string(errors.empty() ? 0 : errors[0].size()) + " given)");
  }
  int chosen = best;
  const Eigen::VectorXd& e_best = errors[best];
  const double n = static_cast<double>(e_best.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (!errors[i].allFinite() || !summary.steps[i].identifiable || static_cast<int>(i) == best) continue;
    const Eigen::VectorXd d = errors[i] - e_best;
    const double mean = d.mean();
    const double sd = n > 1 ? std::sqrt((d.array() - mean).square().sum() / (n - 1.0)) : 0.0;
    const double se = sd / std::sqrt(n);
    summary.steps[i].heldout_z = se > 0.0 ? mean / se : (mean > 0.0 ? INFINITY : 0.0);
    if (summary.steps[i].heldout_z <= options.heldout_z && path[i].size() < path[chosen].size()) {
      chosen = static_cast<int>(i);
    }
  }
  return chosen;
}

ScreeningSummary ScreenParameters(const ThermalExperiment& experiment, const ScreeningOptions& options) {
  ThrowIfInvalid(options.Validate(), "ScreeningOptions");
  Scorer scorer(experiment, options.identification.poses);
  ScreeningSummary summary;
  const bool from_heldout = options.keep == 0;
  const int target = from_heldout ? options.min_keep : options.keep;
  std::vector<std::vector<int>> path;  // the set of every row of the table
  std::vector<int> current = options.candidates.empty() ? experiment.model.FreeParams() : options.candidates;
  std::sort(current.begin(), current.end());
  IdentificationOptions id = options.identification;
  id.params = current;
  Eigen::MatrixXd x_ball;
  double lambda = scorer.Score(id, options.lambda, &x_ball);
  summary.initial_lambda = lambda;
  summary.initial_delta_x = x_ball;
  int removed = -1;
  while (true) {
    ScreeningStep step;
    step.card = static_cast<int>(current.size());
    step.removed = removed;
    step.lambda = lambda;
    {
      IdentifiabilityOptions check = options.identifiability;
      check.reduce = false;
      const IdentifiabilitySummary g =
          CheckIdentifiability(scorer.drift_model, current, options.identification.poses, check);
      step.condition_number = g.condition_number;
      step.identifiable = g.Identifiable();
    }
    // (3) steady parameters of the current set, from their identified series over the ball cycles.
    for (int p : current) {
      if (AutocorrelationTest(x_ball.row(p).transpose(), options.acf).steady) step.steady.push_back(p);
    }
    const bool done = static_cast<int>(current.size()) <= target;
    std::vector<int> trial_set = step.steady;
    if (trial_set.empty() && !done) {
      trial_set = current;
      step.steady_fallback = true;
    }
    summary.steps.push_back(step);
    path.push_back(current);
    if (done) break;
    if (options.progress &&
        !options.progress({"screening", summary.steps.size(),
                           summary.steps.size() + current.size() - static_cast<std::size_t>(target)})) {
      summary.termination = Termination::kCancelled;
      summary.message = "cancelled";
      break;
    }
    // (4) try removing each element of S.
    const Removal r = BestRemoval(&scorer, options, current, trial_set, lambda);
    const int best = r.param;
    const double best_lambda = r.lambda;
    const Eigen::MatrixXd best_x = r.x_ball;
    current.erase(std::find(current.begin(), current.end(), best));
    lambda = best_lambda;
    x_ball = best_x;
    removed = best;
    ++summary.iterations;
  }
  if (from_heldout && summary.termination != Termination::kCancelled) {
    int best = -1;
    const int chosen = ChooseFromHeldout(scorer, experiment, options, path, &summary, &best);
    summary.best_heldout_card = static_cast<int>(path[best].size());
    summary.count_from_heldout = true;
    current = path[chosen];
    lambda = summary.steps[chosen].lambda;
    IdentificationOptions o = options.identification;
    o.params = current;
    scorer.Score(o, options.lambda, &x_ball);
  }
  if (summary.termination != Termination::kCancelled) {
    // The guard on the selected set: refused, or reduced and identified again.
    summary.identifiability =
        CheckIdentifiability(scorer.drift_model, current, options.identification.poses, options.identifiability);
    if (!summary.identifiability.Identifiable()) {
      summary.termination = Termination::kNoResult;
      summary.message = "selected set " + summary.identifiability.message;
    } else if (!summary.identifiability.dropped.empty()) {
      current = summary.identifiability.params;
      IdentificationOptions o = options.identification;
      o.params = current;
      lambda = scorer.Score(o, options.lambda, &x_ball);
      summary.termination = Termination::kPartial;
      summary.message = "kept " + std::to_string(current.size()) + (from_heldout ? " (held-out)" : "") +
                        ", the guard dropped " + ParamListToString(summary.identifiability.dropped);
    } else {
      summary.termination = Termination::kSuccess;
      summary.message = "kept " + std::to_string(current.size()) + (from_heldout ? " (held-out)" : "");
    }
  }
  summary.selected = current;
  summary.final_lambda = lambda;
  summary.lambda_evaluations = scorer.evaluations;
  summary.selected_delta_x.resize(x_ball.rows(), static_cast<Eigen::Index>(experiment.ball_column.size()));
  for (std::size_t c = 0; c < experiment.ball_column.size(); ++c) {
    summary.selected_delta_x.col(c) = x_ball.col(experiment.ball_column[c]);
  }
  return summary;
}

std::vector<ComparisonRow> CompareParameterSets(const ThermalExperiment& experiment,
                                                const std::vector<std::pair<std::string, std::vector<int>>>& sets,
                                                const IdentificationOptions& id, const LambdaOptions& lambda) {
  Scorer scorer(experiment, id.poses);
  std::vector<ComparisonRow> rows;
  auto fill = [](ComparisonRow& row, const Eigen::MatrixXd& r) {
    const int warm = static_cast<int>(r.cols()) - 1;
    if (warm > 0) {
      row.rms_residual_mm = std::sqrt(r.rightCols(warm).squaredNorm() / (r.rows() * warm));
      row.worst_residual_mm = r.rightCols(warm).cwiseAbs().maxCoeff();
    }
  };
  ComparisonRow before{"before", {}, 0, Lambda(scorer.monitoring.Uncompensated(), lambda), 0.0, 0.0};
  fill(before, scorer.monitoring.Uncompensated());
  rows.push_back(before);
  for (const auto& [label, params] : sets) {
    IdentificationOptions o = id;
    o.params = params;
    Eigen::MatrixXd r;
    ComparisonRow row{label, params, scorer.drift_model.NumPoses(), 0.0, 0.0, 0.0};
    if (!id.poses.empty()) row.num_poses = static_cast<int>(id.poses.size());
    row.lambda = scorer.Score(o, lambda, nullptr, &r);
    fill(row, r);
    rows.push_back(row);
  }
  return rows;
}

std::string FormatEliminationTable(const ScreeningSummary& summary) {
  const bool heldout = summary.count_from_heldout;
  std::string out = heldout ? "card(dX0)  removed   lambda(%)  held-out(mm)  z vs best  steady set S\n"
                            : "card(dX0)  removed   lambda(%)  steady set S\n";
  char buf[96];
  for (const ScreeningStep& s : summary.steps) {
    std::snprintf(buf, sizeof(buf), "%9d  %-8s  %9.2f  ", s.card,
                  s.removed < 0 ? "-" : kinematics::ParamName(s.removed).c_str(), s.lambda);
    out += buf;
    if (heldout) {
      const char* mark = s.card == static_cast<int>(summary.selected.size()) ? "*" : " ";
      std::snprintf(buf, sizeof(buf), "%11.5f%s  %9.2f  ", s.heldout_rms_mm, mark, s.heldout_z);
      out += buf;
    }
    out += s.steady.empty() ? "-" : ParamListToString(s.steady);
    if (s.steady_fallback) out += "  (S empty: every parameter tried)";
    if (!s.identifiable) {
      std::snprintf(buf, sizeof(buf), "  (not identifiable: cond %.3g)", s.condition_number);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

std::string FormatComparisonTable(const std::vector<ComparisonRow>& rows) {
  std::string out = "set          poses  params  lambda(%)  RMS(mm)  worst(mm)  parameters\n";
  char buf[128];
  for (const ComparisonRow& r : rows) {
    std::snprintf(buf, sizeof(buf), "%-12s %5d  %6zu  %9.2f  %7.4f  %9.4f  ", r.label.c_str(), r.num_poses,
                  r.params.size(), r.lambda, r.rms_residual_mm, r.worst_residual_mm);
    out += buf;
    out += r.params.empty() ? "-" : ParamListToString(r.params);
    out += "\n";
  }
  return out;
}

}  // namespace ramtk::thermal
