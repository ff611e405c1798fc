// ramtk thermal screen: which kinematic parameters drift (thesis §3.2, Tables 5-1, 5-2).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/parse.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/thermal/thermal_report.h"
#include "thermal_inputs.h"

namespace ramtk::tools {
namespace {

using namespace thermal;

// ---------------------------------------------------------------- thermal screen
struct ScreenOptions {
  ExperimentInputs in;
  std::string keep = "auto";
  double heldout_z = 1.0;
  double threshold_mm = 0.1;
  std::string statistic = "rms";
  bool best_improvement = false;
  int budget = 6;
  std::string out_json;
  std::string out_series;
  std::string out_report;  // report.html
};

LambdaOptions MakeLambda(double threshold_mm, const std::string& statistic) {
  LambdaOptions lo;
  lo.threshold_mm = threshold_mm;
  if (statistic == "rms") {
    lo.statistic = LambdaStatistic::kRms;
  } else if (statistic == "max") {
    lo.statistic = LambdaStatistic::kMax;
  } else {
    throw InputError({"", 0, "--statistic"}, "expected rms or max, got '" + statistic + "'");
  }
  const std::string problem = lo.Validate();
  if (!problem.empty()) throw InputError({"", 0, "--threshold-mm"}, problem);
  return lo;
}

// --keep: "auto" (held-out error) or a positive count.
int ParseKeep(const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0' || v < 1 || v > kinematics::kNumParams) {
    throw InputError({"", 0, "--keep"},
                     "expected auto or a count 1.." + std::to_string(kinematics::kNumParams) + ", got '" + text + "'");
  }
  return static_cast<int>(v);
}

int RunScreen(const ScreenOptions& opt, Provenance provenance) {
  CheckOutputs(opt.in, {{"--json", opt.out_json}, {"--series", opt.out_series}, {"--report", opt.out_report}});
  for (const std::string& f : {opt.in.robot_path, opt.in.setup_path, opt.in.ball_path, opt.in.monitoring_path})
    AddProvenanceFile(&provenance, f);
  const LoadedExperiment e = Load(opt.in);
  const ThermalExperiment ex = MakeExperiment(e.model, e.setup, e.ball, e.monitoring);
  ScreeningOptions so;
  if (opt.keep != "auto") {
    so.keep = ParseKeep(opt.keep);
  }
  so.heldout_z = opt.heldout_z;
  so.lambda = MakeLambda(opt.threshold_mm, opt.statistic);
  so.first_improvement = !opt.best_improvement;
  if (!opt.in.params.empty()) so.candidates = ParseParamList(opt.in.params, e.model, "--params");
  so.identification.difference_covariance_mm2 = Weights(opt.in, e);
  so.identifiability.max_condition = opt.in.max_condition;
  so.identifiability.reduce = opt.in.reduce;
  const ScreeningSummary s = ScreenParameters(ex, so);
  if (s.termination == Termination::kNoResult) {
    std::cout << "Elimination (form of thesis Table 5-1):\n" << FormatEliminationTable(s);
    std::cerr << "ramtk: error: " << s.message << " (condition number "
              << Fmt("%.3g", s.identifiability.condition_number) << " > " << Fmt("%.3g", opt.in.max_condition)
              << "; --reduce drops them); nothing written\n";
    return kExitNoSolution;
  }
  if (!so.identification.difference_covariance_mm2.empty()) {
    std::cout << "identification weighted by each centre's covariance (cov_xx..cov_yz of " << opt.in.ball_path << ")\n";
  }
  std::cout << "Elimination (form of thesis Table 5-1):\n" << FormatEliminationTable(s) << s.BriefReport() << "\n"
            << "selected set " << s.identifiability.BriefReport() << "\n";
  // The selected set identified once more for its per-parameter sigma (last cycle).
  const DriftModel dm_all(e.model, e.setup, e.ball.taught);
  IdentificationOptions sel = so.identification;
  sel.params = s.selected;
  IdentificationSummary sel_summary;
  const Eigen::MatrixXd sel_x = dm_all.Solve(e.ball.DifferencesFromReference(sel.poses), sel, &sel_summary);
  const int last = e.ball.NumCycles() - 1;
  std::cout << sel_summary.covariance_scaling << "\nselected set at cycle " << e.ball.cycles[last].cycle
            << " (mm, deg; value ± sigma):";
  nlohmann::json sel_json = nlohmann::json::object();
  for (std::size_t k = 0; k < s.selected.size(); ++k) {
    const int p = s.selected[k];
    const double sd = sel_summary.Sigma(static_cast<int>(k), last);
    std::cout << " " << kinematics::ParamName(p) << "=" << ValueWithSigma(p, sel_x(p, last), sd);
    sel_json[kinematics::ParamName(p)] = {{"value", ToFileUnits(p, sel_x(p, last))}, {"sigma", SigmaToFileUnits(p, sd)}};
  }
  std::cout << "\n\n";
  std::vector<std::pair<std::string, std::string>> files;  // written together at the end
  if (!opt.out_series.empty()) {
    // Per-parameter series with every candidate (Figs. 3-3/3-4), and which the first test called steady.
    std::vector<int> first = so.candidates.empty() ? e.model.FreeParams() : so.candidates;
    std::sort(first.begin(), first.end());
    std::string csv = "# steady in the first autocorrelation test: " +
                      (s.steps.empty() ? std::string("-") : ParamListToString(s.steps[0].steady)) + "\ncycle,time_s";
    for (int p : first) csv += "," + kinematics::ParamName(p);
    csv += "\n";
    for (int c = 0; c < e.ball.NumCycles(); ++c) {
      csv += std::to_string(e.ball.cycles[c].cycle) + Fmt(",%.3f", e.ball.cycles[c].time_s);
      for (int p : first) csv += Fmt(",%.9g", ToFileUnits(p, s.initial_delta_x(p, c)));
      csv += "\n";
    }
    files.emplace_back(opt.out_series, csv);
  }
  const std::vector<std::pair<std::string, std::vector<int>>> sets = {
      {"traditional", TraditionalParams(e.model)}, {"screened", s.selected}, {"all", e.model.FreeParams()}};
  const auto rows = CompareParameterSets(ex, sets, so.identification, so.lambda);
  std::cout << "Share of monitored directions under " << opt.threshold_mm << " mm (form of thesis Table 5-2), all "
            << e.ball.NumPoses() << " poses:\n"
            << FormatComparisonTable(rows);
  nlohmann::json j;
  j["selected"] = ParamListToString(s.selected);
  j["weighted_by_centre_covariance"] = !so.identification.difference_covariance_mm2.empty();
  j["kept_count_rule"] = s.count_from_heldout ? "held-out error" : "fixed";
  if (s.count_from_heldout) {
    j["heldout_z"] = so.heldout_z;
    j["best_heldout_card"] = s.best_heldout_card;
  }
  j["identifiability"] = {{"condition_number", s.identifiability.condition_number},
                           {"max_condition", s.identifiability.max_condition},
                           {"dropped", ParamListToString(s.identifiability.dropped)},
                           {"message", s.identifiability.message}};
  j["selected_last_cycle"] = {{"cycle", e.ball.cycles[last].cycle},
                              {"covariance_scaling", sel_summary.covariance_scaling},
                              {"delta_x", sel_json}};
  j["initial_lambda_percent"] = s.initial_lambda;
  j["final_lambda_percent"] = s.final_lambda;
  for (const ScreeningStep& st : s.steps) {
    j["steps"].push_back({{"card", st.card},
                          {"removed", st.removed < 0 ? "-" : kinematics::ParamName(st.removed)},
                          {"lambda_percent", st.lambda},
                          {"steady", ParamListToString(st.steady)},
                          {"heldout_rms_mm", st.heldout_rms_mm},
                          {"heldout_z", st.heldout_z},
                          {"condition_number", st.condition_number},
                          {"identifiable", st.identifiable}});
  }
  auto rows_json = [](const std::vector<ComparisonRow>& rs) {
    nlohmann::json a = nlohmann::json::array();
    for (const ComparisonRow& r : rs) {
      a.push_back({{"set", r.label},
                   {"params", ParamListToString(r.params)},
                   {"poses", r.num_poses},
                   {"lambda_percent", r.lambda},
                   {"rms_mm", r.rms_residual_mm},
                   {"worst_mm", r.worst_residual_mm}});
    }
    return a;
  };
  j["comparison_all_poses"] = rows_json(rows);
  std::vector<ComparisonRow> last_budget_rows;
  if (opt.budget > 0 && opt.budget < e.ball.NumPoses()) {
    // Production budget: each set on its own D-optimal poses.
    const DriftModel dm(e.model, e.setup, e.ball.taught);
    std::vector<ComparisonRow> budget_rows;
    for (const auto& set : sets) {
      if (3 * opt.budget < static_cast<int>(set.second.size())) continue;
      IdentificationOptions id = so.identification;
      id.poses = SelectPoses(dm, set.second, opt.budget);
      const auto r = CompareParameterSets(ex, {set}, id, so.lambda);
      if (budget_rows.empty()) budget_rows.push_back(r[0]);
      budget_rows.push_back(r[1]);
    }
    std::cout << "\nProduction budget: " << opt.budget << " D-optimal poses per set:\n"
              << FormatComparisonTable(budget_rows);
    j["comparison_budget"] = rows_json(budget_rows);
    last_budget_rows = budget_rows;
  }
  if (!opt.out_json.empty()) files.emplace_back(opt.out_json, j.dump(2) + "\n");
  if (!opt.out_report.empty()) {
    report::HtmlReport page = ScreeningReport(ex, s, rows, last_budget_rows, opt.threshold_mm);
    page.AddProvenance(provenance);
    files.emplace_back(opt.out_report, page.Page());
  }
  StampOutputs(&files, provenance);
  WriteFilesAtomically(files);
  for (const auto& f : files) std::cout << "wrote " << f.first << "\n";
  return kExitOk;
}

}  // namespace

void RegisterThermalScreen(CLI::App* thermal, int* exit_code) {
  auto opt = std::make_shared<ScreenOptions>();
  CLI::App* sub = thermal->add_subcommand("screen", "Screen the drifting parameters (§3.2, Tables 5-1, 5-2)");
  AddInputs(sub, &opt->in, true);
  sub->add_option("--params", opt->in.params, "Candidate parameters (default all free)");
  sub->add_option("--keep", opt->keep,
                  "Parameters to keep: auto (the smallest set on the elimination path whose leave-one-pose-out "
                  "error is within --heldout-z standard errors of the best) or a count (thesis: 8)")
      ->capture_default_str();
  sub->add_option("--heldout-z", opt->heldout_z,
                  "With --keep auto: standard errors of the paired per-pose held-out difference a smaller set may lose")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threshold-mm", opt->threshold_mm, "λ threshold (mm, thesis 0.1)");
  sub->add_option("--statistic", opt->statistic, "Residual summary per direction: rms or max");
  sub->add_flag("--best-improvement", opt->best_improvement, "Take the best removal, not the first non-worse");
  sub->add_option("--pose-budget", opt->budget, "Also compare the sets on this many D-optimal poses (0: skip)");
  sub->add_option("--json", opt->out_json, "Write the tables as JSON");
  sub->add_option("--series", opt->out_series, "Write every candidate's identified series per cycle (CSV, mm/deg)");
  sub->add_option("--report", opt->out_report,
                  "Write one self-contained HTML page: the tables, the elimination and the selected drift");
  AddGuardOptions(sub, &opt->in);
  sub->callback([opt, exit_code, sub]() { *exit_code = RunScreen(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
