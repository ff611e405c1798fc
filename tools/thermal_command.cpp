// ramtk simulate thermal, ramtk thermal identify|screen|compensate|predict: thermal drift of the
// kinematic parameters (thesis ch. 3 and §5.1). Options are parsed here; the work is in ramtk::thermal.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/compensation.h"
#include "ramtk/thermal/predictor.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/thermal/thermal_report.h"
#include "ramtk/thermal/simulator.h"

namespace ramtk::tools {
namespace {

using namespace thermal;

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

// ---------------------------------------------------------------- simulate thermal
struct SimulateThermalOptions {
  std::string robot_path;
  std::string preset = "thesis";
  std::uint64_t seed = 1;
  int cycles = 0;                  // 0: the preset's
  double sensor_noise_mm = -1.0;   // < 0: the preset's (both sensors)
  double repeatability_mm = -1.0;  // < 0: the preset's
  std::string out_dir;
  bool force = false;  // replace an existing output folder
};

int RunSimulateThermal(const SimulateThermalOptions& opt) {
  if (opt.preset != "thesis") throw InputError({"", 0, "--preset"}, "unknown preset '" + opt.preset + "' (thesis)");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  ThermalSimOptions o = ThesisPreset(opt.seed);
  if (opt.cycles > 0) o.cycles = opt.cycles;
  if (opt.sensor_noise_mm >= 0.0) o.sensor_noise_mm = o.tool_sensor_noise_mm = opt.sensor_noise_mm;
  if (opt.repeatability_mm >= 0.0) o.repeatability_mm = opt.repeatability_mm;
  CheckOutputAgainstInputs(opt.out_dir, {opt.robot_path}, "--out");
  const ThermalSimResult r = SimulateThermal(model, o);
  WriteThermalSimulation(r, o, opt.preset, opt.out_dir, opt.force);
  const double max_drift = LargestBallDriftMm(r);
  std::cout << "simulated " << o.cycles << " cycles (" << o.ball_poses << " ball poses, " << o.monitoring_points
            << " monitoring points) into " << opt.out_dir << "\n"
            << "drifting parameters (truth): " << ParamListToString(r.drifting_params) << "\n"
            << "largest ball-centre drift from the cold cycle: " << Fmt("%.3f", max_drift) << " mm\n";
  return kExitOk;
}

// ---------------------------------------------------------------- shared inputs
struct ExperimentInputs {
  std::string robot_path;
  std::string setup_path;
  std::string ball_path;
  std::string monitoring_path;
  int reference_cycle = 0;
  double joint_tolerance_deg = 0.01;
  std::string params;   // names, "traditional", "all"
  std::string poses;    // pose positions, comma list
  int pose_budget = 0;  // choose this many poses D-optimally for `params`
  bool unweighted = false;  // ignore the ball file's centre covariance (cov_xx..cov_yz)
  double robot_noise_mm = 0.0;  // robot repeatability σ per axis added to every centre's covariance
};

void AddInputs(CLI::App* sub, ExperimentInputs* in, bool monitoring_required) {
  sub->add_option("--robot", in->robot_path, "Robot model file (YAML)")->required();
  sub->add_option("--setup", in->setup_path, "Thermal setup (JSON: sensor_from_base, ball_in_flange_mm, ...)")
      ->required();
  sub->add_option("--ball", in->ball_path, "Ball measurements CSV (cycle,time_s,pose,q1..q6,x,y,z)")->required();
  auto* m = sub->add_option("--monitoring", in->monitoring_path,
                            "Monitoring-point CSV (cycle,time_s,point,q1..q6,x,y,z in the tool-sensor frame)");
  if (monitoring_required) m->required();
  sub->add_option("--reference-cycle", in->reference_cycle, "Cold reference cycle number (default 0)");
  sub->add_option("--joint-tolerance-deg", in->joint_tolerance_deg,
                  "Largest joint difference of a pose between cycles (deg, default 0.01)");
  sub->add_flag("--unweighted", in->unweighted,
                "Ignore the ball file's centre covariance columns (default: weight each centre by its covariance)");
  sub->add_option("--robot-noise", in->robot_noise_mm,
                  "Robot repeatability sigma per axis (mm) added to every centre's covariance when weighting (default 0)");
}

// The named outputs may not be an input of the experiment or each other (core/outputs.h).
void CheckOutputs(const ExperimentInputs& in, const std::vector<std::pair<std::string, std::string>>& outputs,
                  const std::vector<std::string>& more_inputs = {}) {
  std::vector<std::string> inputs = {in.robot_path, in.setup_path, in.ball_path, in.monitoring_path};
  inputs.insert(inputs.end(), more_inputs.begin(), more_inputs.end());
  for (const auto& [field, path] : outputs) CheckOutputAgainstInputs(path, inputs, field);
  CheckOutputsDistinct(outputs);
}

struct LoadedExperiment {
  kinematics::RobotModel model;
  ThermalSetup setup;
  CycleSeries ball;
  CycleSeries monitoring;
  bool has_monitoring = false;
};

LoadedExperiment Load(const ExperimentInputs& in) {
  LoadedExperiment e;
  e.model = kinematics::ReadRobotModel(in.robot_path);
  e.setup = ReadThermalSetup(in.setup_path);
  CycleOptions co;
  co.reference_cycle = in.reference_cycle;
  co.joint_tolerance_deg = in.joint_tolerance_deg;
  const kinematics::RobotMeasurementSet ball = kinematics::ReadRobotMeasurements(in.ball_path);
  if (ball.kind != kinematics::MeasurementKind::kBall)
    throw InputError({in.ball_path, 1, "pose"}, "not a ball file: expected a 'pose' column (this one has 'point': "
                                                "a monitoring file?)");
  e.ball = GroupCycles(ball, in.ball_path, co);
  if (!in.monitoring_path.empty()) {
    const kinematics::RobotMeasurementSet mon = kinematics::ReadRobotMeasurements(in.monitoring_path);
    if (mon.kind != kinematics::MeasurementKind::kMonitoring)
      throw InputError({in.monitoring_path, 1, "point"}, "not a monitoring file: expected a 'point' column (this one "
                                                          "has 'pose': a ball file?)");
    e.monitoring = GroupCycles(mon, in.monitoring_path, co);
    e.has_monitoring = true;
  }
  return e;
}

// Weights from the ball file's centre covariance (when it has the columns and --unweighted is off).
std::vector<std::vector<Mat3>> Weights(const ExperimentInputs& in, const LoadedExperiment& e) {
  if (!(in.robot_noise_mm >= 0.0)) throw InputError({"", 0, "--robot-noise"}, "must be >= 0 mm");
  return in.unweighted ? std::vector<std::vector<Mat3>>{} : e.ball.DifferenceCovariances(in.robot_noise_mm);
}

IdentificationOptions MakeIdOptions(const ExperimentInputs& in, const LoadedExperiment& e, const DriftModel& dm,
                                    const std::vector<int>& params) {
  IdentificationOptions id;
  id.params = params;
  id.difference_covariance_mm2 = Weights(in, e);
  if (!in.poses.empty()) {
    for (double p : ParseDoubleList(in.poses, {"", 0, "--poses"})) {
      const int k = static_cast<int>(p);
      if (k != p || k < 0 || k >= e.ball.NumPoses()) {
        throw InputError({"", 0, "--poses"},
                         "pose positions are integers in 0.." + std::to_string(e.ball.NumPoses() - 1));
      }
      id.poses.push_back(k);
    }
  } else if (in.pose_budget > 0) {
    id.poses = SelectPoses(dm, params, in.pose_budget);
  }
  return id;
}

std::vector<int> PoseIds(const LoadedExperiment& e, const IdentificationOptions& id) {
  std::vector<int> out;
  for (int p : id.poses) out.push_back(e.ball.ids[p]);
  return out;
}

std::string IntList(const std::vector<int>& v) {
  std::string s;
  for (int x : v) s += (s.empty() ? "" : ",") + std::to_string(x);
  return s;
}

// ---------------------------------------------------------------- thermal identify
struct IdentifyOptions {
  ExperimentInputs in;
  std::string out_path;
};

int RunIdentify(const IdentifyOptions& opt) {
  CheckOutputs(opt.in, {{"--out", opt.out_path}});
  const LoadedExperiment e = Load(opt.in);
  const std::vector<int> params = ParseParamList(opt.in.params, e.model, "--params");
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  const IdentificationOptions id = MakeIdOptions(opt.in, e, dm, params);
  IdentificationSummary s;
  const Eigen::MatrixXd x = dm.Solve(e.ball.DifferencesFromReference(id.poses), id, &s);
  std::string csv = "cycle,time_s";
  for (int p : params) csv += "," + kinematics::ParamName(p);
  csv += "\n";
  for (int c = 0; c < e.ball.NumCycles(); ++c) {
    csv += std::to_string(e.ball.cycles[c].cycle) + Fmt(",%.3f", e.ball.cycles[c].time_s);
    for (int p : params) csv += Fmt(",%.9g", ToFileUnits(p, x(p, c)));
    csv += "\n";
  }
  if (!opt.out_path.empty()) WriteFileAtomically(opt.out_path, csv);
  std::cout << s.BriefReport() << "\n";
  std::cout << "poses: " << (id.poses.empty() ? std::string("all") : IntList(PoseIds(e, id))) << "\n";
  std::cout << "singular values (equilibrated columns):";
  for (int i = 0; i < s.singular_values.size(); ++i) std::cout << Fmt(" %.4g", s.singular_values[i]);
  std::cout << "\n";
  if (!s.dependent_params.empty()) {
    std::cout << "not identifiable given the others (QR pivoting): " << ParamListToString(s.dependent_params) << "\n";
  }
  for (const NullCombination& n : s.null_space) {
    std::cout << "unseen combination:";
    for (std::size_t i = 0; i < n.params.size(); ++i) {
      std::cout << Fmt(" %+.3f·", n.coefficients[i]) << kinematics::ParamName(n.params[i]);
    }
    std::cout << "\n";
  }
  const int last = e.ball.NumCycles() - 1;
  std::cout << "last cycle " << e.ball.cycles[last].cycle << " (mm, deg):";
  for (int p : params) std::cout << " " << kinematics::ParamName(p) << Fmt("=%.5f", ToFileUnits(p, x(p, last)));
  std::cout << "\n";
  if (!opt.out_path.empty()) std::cout << "wrote " << opt.out_path << "\n";
  if (s.rank < static_cast<int>(params.size())) {
    // Not a unique solution: the values written are the minimum-norm one of many. Say so and
    // exit with "no solution" (3), as every command does for a non-success result.
    std::cerr << "ramtk: error: rank deficient (" << s.rank << " of " << params.size()
              << " parameters identifiable with these poses): the drift is not unique; drop the parameters named above "
                 "or add poses\n";
    return kExitNoSolution;
  }
  return kExitOk;
}

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
    throw InputError({"", 0, "--keep"}, "expected auto or a count 1.." + std::to_string(kinematics::kNumParams) +
                                            ", got '" + text + "'");
  }
  return static_cast<int>(v);
}

int RunScreen(const ScreenOptions& opt) {
  CheckOutputs(opt.in, {{"--json", opt.out_json}, {"--series", opt.out_series}, {"--report", opt.out_report}});
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
  const ScreeningSummary s = ScreenParameters(ex, so);
  if (!so.identification.difference_covariance_mm2.empty()) {
    std::cout << "identification weighted by each centre's covariance (cov_xx..cov_yz of " << opt.in.ball_path
              << ")\n";
  }
  std::cout << "Elimination (form of thesis Table 5-1):\n" << FormatEliminationTable(s) << s.BriefReport() << "\n\n";
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
    WriteFileAtomically(opt.out_series, csv);
    std::cout << "wrote " << opt.out_series << "\n";
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
  j["initial_lambda_percent"] = s.initial_lambda;
  j["final_lambda_percent"] = s.final_lambda;
  for (const ScreeningStep& st : s.steps) {
    j["steps"].push_back({{"card", st.card},
                          {"removed", st.removed < 0 ? "-" : kinematics::ParamName(st.removed)},
                          {"lambda_percent", st.lambda},
                          {"steady", ParamListToString(st.steady)},
                          {"heldout_rms_mm", st.heldout_rms_mm},
                          {"heldout_z", st.heldout_z}});
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
  if (!opt.out_json.empty()) {
    WriteFileAtomically(opt.out_json, j.dump(2) + "\n");
    std::cout << "wrote " << opt.out_json << "\n";
  }
  if (!opt.out_report.empty()) {
    ScreeningReport(ex, s, rows, last_budget_rows, opt.threshold_mm).Write(opt.out_report);
    std::cout << "wrote " << opt.out_report << "\n";
  }
  return kExitOk;
}

// ---------------------------------------------------------------- thermal compensate
struct CompensateOptions {
  ExperimentInputs in;
  int cycle = -1;  // -1: the last cycle
  double threshold_mm = 0.1;
  std::string out_path;
  std::string out_report;  // report.html
};

int RunCompensate(const CompensateOptions& opt) {
  CheckOutputs(opt.in, {{"--out", opt.out_path}, {"--report", opt.out_report}});
  const LoadedExperiment e = Load(opt.in);
  const ThermalExperiment ex = MakeExperiment(e.model, e.setup, e.ball, e.monitoring);
  const std::vector<int> params = ParseParamList(opt.in.params, e.model, "--params");
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  const IdentificationOptions id = MakeIdOptions(opt.in, e, dm, params);
  IdentificationSummary is;
  const Eigen::MatrixXd x_mon = IdentifyForMonitoring(ex, dm, id, &is);
  const MonitoringModel mon(e.model, e.setup, e.monitoring);
  LambdaOptions lo;
  lo.threshold_mm = opt.threshold_mm;
  const Eigen::MatrixXd before = mon.Uncompensated();
  const Eigen::MatrixXd after = mon.Residuals(x_mon);
  const int col = opt.cycle < 0 ? e.monitoring.NumCycles() - 1 : e.monitoring.Find(opt.cycle);
  if (col < 0)
    throw InputError({opt.in.monitoring_path, 0, "--cycle"}, "cycle " + std::to_string(opt.cycle) + " not found");
  CompensationSummary cs;
  const ParamVector dx = x_mon.col(col);
  const auto corrected = CompensateTaughtPoses(e.model, dx, e.monitoring.taught, {}, &cs);
  std::string csv = "point,q1,q2,q3,q4,q5,q6,dq1,dq2,dq3,dq4,dq5,dq6\n";
  for (int k = 0; k < e.monitoring.NumPoses(); ++k) {
    csv += std::to_string(e.monitoring.ids[k]);
    for (int j = 0; j < kinematics::kNumJoints; ++j) csv += Fmt(",%.9f", RadToDeg(corrected[k][j]));
    for (int j = 0; j < kinematics::kNumJoints; ++j)
      csv += Fmt(",%.9f", RadToDeg(corrected[k][j] - e.monitoring.taught[k][j]));
    csv += "\n";
  }
  if (!opt.out_path.empty()) WriteFileAtomically(opt.out_path, csv);
  std::cout << is.BriefReport() << "\n"
            << "params " << ParamListToString(params) << ", poses "
            << (id.poses.empty() ? std::string("all") : IntList(PoseIds(e, id))) << "\n"
            << "monitoring points recomputed with the identified drift (" << e.monitoring.NumPoses() << " points x "
            << e.monitoring.NumCycles() << " cycles):\n"
            << "  lambda (RMS over cycles < " << opt.threshold_mm << " mm): before " << Fmt("%.2f", Lambda(before, lo))
            << " %, after " << Fmt("%.2f", Lambda(after, lo)) << " %\n"
            << "  RMS residual: before " << Fmt("%.4f", std::sqrt(before.squaredNorm() / before.size()))
            << " mm, after " << Fmt("%.4f", std::sqrt(after.squaredNorm() / after.size())) << " mm\n"
            << "corrected joints for the taught monitoring poses at cycle " << e.monitoring.cycles[col].cycle << ": "
            << cs.BriefReport() << "\n";
  // What the identification's noise leaves in the compensated points (issue 14).
  const Eigen::VectorXd mon_sigma = CompensatedMonitoringSigma(mon, dm, id, ResidualSigmaY(is));
  if (mon_sigma.size() > 0) {
    std::vector<double> v(mon_sigma.data(), mon_sigma.data() + mon_sigma.size());
    std::sort(v.begin(), v.end());
    std::cout << "predicted sigma of the compensated monitoring directions from the identification noise: median "
              << Fmt("%.4f", v[v.size() / 2]) << " mm, largest " << Fmt("%.4f", v.back()) << " mm\n";
  }
  if (!opt.out_path.empty()) std::cout << "wrote " << opt.out_path << "\n";
  if (!opt.out_report.empty()) {
    CompensationReportInput in;
    in.monitoring_sigma_mm = mon_sigma;
    in.experiment = &ex;
    in.params = params;
    in.before = before, in.after = after, in.delta_x = x_mon;
    in.threshold_mm = opt.threshold_mm;
    in.cycle_column = col;
    for (int k = 0; k < e.monitoring.NumPoses(); ++k) {
      std::vector<double> q(6), t(6);
      for (int j = 0; j < 6; ++j) q[j] = RadToDeg(corrected[k][j]), t[j] = RadToDeg(e.monitoring.taught[k][j]);
      in.corrected_deg.push_back(q), in.taught_deg.push_back(t);
    }
    in.drift_model = &dm;
    in.identification_options = id;
    in.identification = is;
    CompensationReport(in).Write(opt.out_report);
    std::cout << "wrote " << opt.out_report << "\n";
  }
  return cs.converged == cs.poses ? kExitOk : kExitNoSolution;
}

// ---------------------------------------------------------------- thermal predict
struct PredictOptions {
  ExperimentInputs in;
  int window_every = 10;
  int min_windows = 4;
  std::string train_ball;      // optional characterisation run (identified every cycle, all poses)
  std::string train_setup;     // its setup (default: --setup)
  double kalman_ratio = -1.0;  // >= 0: Kalman filter with this process/measurement ratio per hour
};

void Temperatures(const CycleSeries& series, const std::vector<int>& columns, Eigen::MatrixXd* temps,
                  std::vector<double>* times) {
  temps->resize(kinematics::kNumJoints, static_cast<Eigen::Index>(columns.size()));
  times->clear();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const Cycle& cycle = series.cycles[columns[c]];
    times->push_back(cycle.time_s);
    for (int j = 0; j < kinematics::kNumJoints; ++j) {
      const std::string name = "temp_j" + std::to_string(j + 1);
      const auto it = cycle.extra.find(name);
      if (it == cycle.extra.end()) throw InputError({series.path, 1, name}, "the predictor needs temperature columns");
      (*temps)(j, static_cast<Eigen::Index>(c)) = it->second;
    }
  }
}

int RunPredict(const PredictOptions& opt) {
  const LoadedExperiment e = Load(opt.in);
  const ThermalExperiment ex = MakeExperiment(e.model, e.setup, e.ball, e.monitoring);
  const std::vector<int> params = ParseParamList(opt.in.params, e.model, "--params");
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  const IdentificationOptions id = MakeIdOptions(opt.in, e, dm, params);
  const Eigen::MatrixXd x = IdentifyForMonitoring(ex, dm, id);
  Eigen::MatrixXd temps;
  std::vector<double> times;
  Temperatures(e.ball, ex.ball_column, &temps, &times);
  DriftPredictorOptions po;
  po.window_every = opt.window_every;
  po.min_windows = opt.min_windows;
  std::unique_ptr<TemperatureDriftModel> offline;
  if (!opt.train_ball.empty()) {
    CycleOptions co;
    co.reference_cycle = opt.in.reference_cycle;
    co.joint_tolerance_deg = opt.in.joint_tolerance_deg;
    const CycleSeries train = GroupCycles(kinematics::ReadRobotMeasurements(opt.train_ball), opt.train_ball, co);
    const ThermalSetup train_setup = opt.train_setup.empty() ? e.setup : ReadThermalSetup(opt.train_setup);
    IdentificationOptions tid;
    tid.params = params;
    const Eigen::MatrixXd tx = IdentifyCycles(e.model, train_setup, train, tid);
    std::vector<int> all;
    for (int c = 0; c < train.NumCycles(); ++c) all.push_back(c);
    Eigen::MatrixXd ttemps;
    std::vector<double> ttimes;
    Temperatures(train, all, &ttemps, &ttimes);
    offline = std::make_unique<TemperatureDriftModel>(FitTemperatureModel(tx, ttemps, ttimes, params, po.model));
  }
  DriftPredictionSummary ps;
  DriftPrediction pred = PredictDrift(x, temps, times, params, po, offline.get(), &ps);
  if (opt.kalman_ratio >= 0.0) {
    // Window covariance from the identification residual (σ per coordinate, dof-corrected).
    IdentificationSummary is;
    dm.Solve(e.ball.DifferencesFromReference(id.poses), id, &is);
    const double sigma_y = ResidualSigmaY(is);
    KalmanDriftOptions ko;
    ko.window_every = opt.window_every;
    ko.process_ratio_per_hour = opt.kalman_ratio;
    pred = KalmanPredictDrift(x, dm.Covariance(id, sigma_y), temps, times, params, ko, offline.get());
    std::cout << "Kalman filter: window σ_Y " << Fmt("%.4f", sigma_y) << " mm, process ratio " << opt.kalman_ratio
              << " per hour" << (offline ? ", temperature model as input" : ", random walk") << "\n";
  }
  // Scored on the monitoring points against the every-cycle identification of the held-out cycles.
  const MonitoringModel mon(e.model, e.setup, e.monitoring);
  double sq_pred = 0, sq_hold = 0;
  int n = 0;
  for (int c = 0; c < e.monitoring.NumCycles(); ++c) {
    if (pred.is_window[c]) continue;
    for (int k = 0; k < mon.NumPoints(); ++k) {
      sq_pred += (mon.Jacobian(k) * (pred.predicted.col(c) - x.col(c))).squaredNorm();
      sq_hold += (mon.Jacobian(k) * (pred.hold_last.col(c) - x.col(c))).squaredNorm();
      ++n;
    }
  }
  std::cout << ps.BriefReport() << "\n"
            << "between-window error on the monitoring points vs the held-out per-cycle identification (RMS 3-D):\n"
            << "  hold-last " << Fmt("%.4f", n ? std::sqrt(sq_hold / n) : 0.0) << " mm, "
            << (opt.kalman_ratio >= 0.0 ? "Kalman filter " : "temperature model ")
            << Fmt("%.4f", n ? std::sqrt(sq_pred / n) : 0.0) << " mm\n"
            << "(the reference itself carries the per-cycle identification noise; score against truth in tests)\n";
  return kExitOk;
}

}  // namespace

void RegisterThermalCommands(CLI::App& app, int* exit_code) {
  {
    CLI::App* simulate = SimulateCommand(app);
    auto opt = std::make_shared<SimulateThermalOptions>();
    CLI::App* sub =
        simulate->add_subcommand("thermal", "Thermal drift experiment (thesis §5.1): ball, monitoring, truth");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--preset", opt->preset, "Experiment preset (thesis)");
    sub->add_option("--seed", opt->seed, "Random seed");
    sub->add_option("--cycles", opt->cycles, "Override the preset's number of cycles")->check(CLI::PositiveNumber);
    sub->add_option("--sensor-noise-mm", opt->sensor_noise_mm, "σ per axis of both sensors (preset 0.02)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--repeatability-mm", opt->repeatability_mm,
                    "σ per axis of the robot's repeatability (preset 0.015)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--out", opt->out_dir, "Output folder")->required();
    sub->add_flag("--force", opt->force, "Replace an existing non-empty output folder (once the new one is complete)");
    sub->callback([opt, exit_code]() { *exit_code = RunSimulateThermal(*opt); });
  }
  CLI::App* thermal = GetOrAddSubcommand(app, "thermal", "Thermal drift: identify, screen parameters, compensate, predict");
  {
    auto opt = std::make_shared<IdentifyOptions>();
    CLI::App* sub = thermal->add_subcommand("identify", "Identify the parameter drift per cycle (eqs. 3-5..3-10)");
    AddInputs(sub, &opt->in, false);
    sub->add_option("--params", opt->in.params, "Parameters: names (d4,alpha3,...), 'traditional' or 'all'");
    sub->add_option("--poses", opt->in.poses, "Pose positions to use (0-based, comma list); default all");
    sub->add_option("--pose-budget", opt->in.pose_budget, "Choose this many poses D-optimally for --params");
    sub->add_option("--out", opt->out_path, "ΔX per cycle CSV (mm, deg)");
    sub->callback([opt, exit_code]() { *exit_code = RunIdentify(*opt); });
  }
  {
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
    sub->callback([opt, exit_code]() { *exit_code = RunScreen(*opt); });
  }
  {
    auto opt = std::make_shared<CompensateOptions>();
    CLI::App* sub =
        thermal->add_subcommand("compensate", "Corrected joints for the taught poses; monitoring residuals");
    AddInputs(sub, &opt->in, true);
    sub->add_option("--params", opt->in.params, "Parameters to identify")->required();
    sub->add_option("--poses", opt->in.poses, "Ball pose positions to use (default all)");
    sub->add_option("--pose-budget", opt->in.pose_budget, "Choose this many poses D-optimally");
    sub->add_option("--cycle", opt->cycle, "Cycle whose drift corrects the taught poses (default: last)");
    sub->add_option("--threshold-mm", opt->threshold_mm, "λ threshold (mm)");
    sub->add_option("--out", opt->out_path, "Corrected joints CSV (deg)");
    sub->add_option("--report", opt->out_report,
                    "Write one self-contained HTML page: monitoring error per cycle, identified drift, corrected joints");
    sub->callback([opt, exit_code]() { *exit_code = RunCompensate(*opt); });
  }
  {
    auto opt = std::make_shared<PredictOptions>();
    CLI::App* sub = thermal->add_subcommand("predict", "Drift between ball windows: temperature model vs hold-last");
    AddInputs(sub, &opt->in, true);
    sub->add_option("--params", opt->in.params, "Parameters to identify")->required();
    sub->add_option("--poses", opt->in.poses, "Ball pose positions to use (default all)");
    sub->add_option("--pose-budget", opt->in.pose_budget, "Choose this many poses D-optimally");
    sub->add_option("--window-every", opt->window_every, "A ball window every this many cycles");
    sub->add_option("--min-windows", opt->min_windows, "Windows before the online model replaces hold-last");
    sub->add_option("--train-ball", opt->train_ball,
                    "Characterisation run (ball CSV, every cycle) to fit the temperature model offline");
    sub->add_option("--train-setup", opt->train_setup, "Setup of the characterisation run (default --setup)");
    sub->add_option("--kalman", opt->kalman_ratio,
                    "Use a Kalman filter; value: process noise per hour as a multiple of the window covariance");
    sub->callback([opt, exit_code]() { *exit_code = RunPredict(*opt); });
  }
}

}  // namespace ramtk::tools
