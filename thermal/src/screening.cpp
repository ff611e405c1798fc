#include "ramtk/thermal/screening.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

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
  if (keep < 1) return "keep must be >= 1";
  std::string p = acf.Validate();
  if (!p.empty()) return "acf: " + p;
  p = lambda.Validate();
  if (!p.empty()) return "lambda: " + p;
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
  const Eigen::VectorXd x = series.array() - series.mean();
  const double c0 = x.squaredNorm();
  for (int k = 1; k <= max_lag; ++k) {
    const double ck = c0 > 0.0 ? x.head(n - k).dot(x.tail(n - k)) / c0 : 0.0;
    out.acf.push_back(ck);
    if (std::abs(ck) > out.band) ++out.outside;
  }
  out.steady = out.outside <= options.max_fraction_outside * max_lag;
  return out;
}

std::string ScreeningSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf), "screening %s: %d steps, %d lambda evaluations, lambda %.2f%% -> %.2f%%, kept %s",
                termination.c_str(), iterations, lambda_evaluations, initial_lambda, final_lambda,
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

}  // namespace

ScreeningSummary ScreenParameters(const ThermalExperiment& experiment, const ScreeningOptions& options) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw InputError({"", 0, "ScreeningOptions"}, problem);
  Scorer scorer(experiment, options.identification.poses);
  ScreeningSummary summary;
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
    // (3) steady parameters of the current set, from their identified series over the ball cycles.
    for (int p : current) {
      if (AutocorrelationTest(x_ball.row(p).transpose(), options.acf).steady) step.steady.push_back(p);
    }
    const bool done = static_cast<int>(current.size()) <= options.keep;
    std::vector<int> trial_set = step.steady;
    if (trial_set.empty() && !done) {
      trial_set = current;
      step.steady_fallback = true;
    }
    summary.steps.push_back(step);
    if (done) break;
    if (options.progress && !options.progress({"screening", summary.steps.size(), current.size() - options.keep})) {
      summary.termination = "cancelled";
      break;
    }
    // (4) try removing each element of S.
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
      const double lambda_i = scorer.Score(id, options.lambda, &x_trial, nullptr, &rms_i);
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
    current.erase(std::find(current.begin(), current.end(), best));
    lambda = best_lambda;
    x_ball = best_x;
    removed = best;
    ++summary.iterations;
  }
  if (summary.termination != "cancelled") summary.termination = "kept " + std::to_string(current.size());
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
  std::string out = "card(dX0)  removed   lambda(%)  steady set S\n";
  char buf[64];
  for (const ScreeningStep& s : summary.steps) {
    std::snprintf(buf, sizeof(buf), "%9d  %-8s  %9.2f  ", s.card,
                  s.removed < 0 ? "-" : kinematics::ParamName(s.removed).c_str(), s.lambda);
    out += buf;
    out += s.steady.empty() ? "-" : ParamListToString(s.steady);
    if (s.steady_fallback) out += "  (S empty: every parameter tried)";
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
