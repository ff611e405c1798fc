// ramtk simulate thermal, ramtk thermal identify (and the registration of screen, compensate,
// predict: thermal_*_command.cpp): thermal drift of the kinematic parameters (thesis ch. 3 and
// §5.1). Options are parsed here; the work is in ramtk::thermal.
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
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/compensation.h"
#include "ramtk/thermal/simulator.h"
#include "ramtk/thermal/thermal_report.h"
#include "thermal_inputs.h"

namespace ramtk::tools {
namespace {

using namespace thermal;

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

int RunSimulateThermal(const SimulateThermalOptions& opt, Provenance provenance) {
  if (opt.preset != "thesis") throw InputError({"", 0, "--preset"}, "unknown preset '" + opt.preset + "' (thesis)");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  ThermalSimOptions o = ThesisPreset(opt.seed);
  if (opt.cycles > 0) o.cycles = opt.cycles;
  // Given unless negative (the "preset" default): NaN is handed on, for Validate to refuse.
  if (!(opt.sensor_noise_mm < 0.0)) o.sensor_noise_mm = o.tool_sensor_noise_mm = opt.sensor_noise_mm;
  if (!(opt.repeatability_mm < 0.0)) o.repeatability_mm = opt.repeatability_mm;
  CheckOutputAgainstInputs(opt.out_dir, {opt.robot_path}, "--out");
  const ThermalSimResult r = SimulateThermal(model, o);
  AddProvenanceFile(&provenance, opt.robot_path);
  WriteThermalSimulation(r, o, opt.preset, opt.out_dir, opt.force, provenance);
  const double max_drift = LargestBallDriftMm(r);
  std::cout << "simulated " << o.cycles << " cycles (" << o.ball_poses << " ball poses, " << o.monitoring_points
            << " monitoring points) into " << opt.out_dir << "\n"
            << "drifting parameters (truth): " << ParamListToString(r.drifting_params) << "\n"
            << "largest ball-centre drift from the cold cycle: " << Fmt("%.3f", max_drift) << " mm\n";
  return kExitOk;
}

// ---------------------------------------------------------------- thermal identify
struct IdentifyOptions {
  ExperimentInputs in;
  std::string out_path;   // ΔX per cycle CSV with a sigma column per parameter
  std::string json_path;  // the same with the guard and the covariance scaling, JSON
};

nlohmann::json GuardJson(const IdentifiabilitySummary& g) {
  nlohmann::json j;
  j["condition_number"] = g.condition_number;
  j["max_condition"] = g.max_condition;
  j["column_scaling"] = "unit norm";
  j["singular_values"] = std::vector<double>(g.singular_values.data(), g.singular_values.data() + g.singular_values.size());
  j["requested"] = ParamListToString(g.requested);
  j["dropped"] = ParamListToString(g.dropped);
  j["combinations"] = nlohmann::json::array();
  for (const UnobservableCombination& c : g.combinations) {
    nlohmann::json cj;
    cj["combination"] = c.Describe();
    cj["condition_number"] = c.condition_number;
    cj["cause"] = c.cause;
    j["combinations"].push_back(cj);
  }
  j["message"] = g.message;
  return j;
}

int RunIdentify(const IdentifyOptions& opt, Provenance provenance) {
  CheckOutputs(opt.in, {{"--out", opt.out_path}, {"--json", opt.json_path}});
  for (const std::string& f : {opt.in.robot_path, opt.in.setup_path, opt.in.ball_path, opt.in.monitoring_path})
    AddProvenanceFile(&provenance, f);
  const LoadedExperiment e = Load(opt.in);
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  IdentificationOptions id = MakeIdOptions(opt.in, e, dm, ParseParamList(opt.in.params, e.model, "--params"));
  IdentifiabilitySummary g;
  if (!GuardIdentification(opt.in, dm, &id, &g)) return kExitNoSolution;
  const std::vector<int>& params = id.params;
  IdentificationSummary s;
  const Eigen::MatrixXd x = dm.Solve(e.ball.DifferencesFromReference(id.poses), id, &s);
  std::cout << s.BriefReport() << "\n";
  std::cout << "poses: " << (id.poses.empty() ? std::string("all") : IntList(PoseIds(e, id))) << "\n";
  std::cout << "singular values (equilibrated columns):";
  for (int i = 0; i < s.singular_values.size(); ++i) std::cout << Fmt(" %.4g", s.singular_values[i]);
  std::cout << "\n";
  if (s.rank < static_cast<int>(params.size())) {
    // Not a unique solution even though the guard passed (its limit was raised): refuse.
    std::cerr << "ramtk: error: rank deficient (" << s.rank << " of " << params.size()
              << " parameters identifiable with these poses): the drift is not unique; drop parameters or add "
                 "poses; nothing written\n";
    return kExitNoSolution;
  }
  std::cout << s.covariance_scaling << "\n";
  // Every output is assembled first and written as one unit.
  std::string csv = "cycle,time_s";
  for (int p : params) csv += "," + kinematics::ParamName(p) + "," + kinematics::ParamName(p) + "_sigma";
  csv += "\n";
  nlohmann::json j;
  j["params"] = ParamListToString(params);
  j["poses"] = PoseIds(e, id);
  j["identifiability"] = GuardJson(g);
  j["rank"] = s.rank;
  j["rms_residual_mm"] = s.rms_residual_mm;
  j["weighted"] = s.weighted;
  j["residual_dof"] = s.residual_dof;
  j["reduced_chi2"] = s.reduced_chi2;
  j["covariance_scale"] = s.covariance_scale;
  j["covariance_scaling"] = s.covariance_scaling;
  j["units"] = "mm for d and a, deg for theta, alpha and beta";
  j["cycles"] = nlohmann::json::array();
  for (int c = 0; c < e.ball.NumCycles(); ++c) {
    csv += std::to_string(e.ball.cycles[c].cycle) + Fmt(",%.3f", e.ball.cycles[c].time_s);
    nlohmann::json cj;
    cj["cycle"] = e.ball.cycles[c].cycle;
    cj["time_s"] = e.ball.cycles[c].time_s;
    for (std::size_t k = 0; k < params.size(); ++k) {
      const int p = params[k];
      const double v = ToFileUnits(p, x(p, c));
      const double sd = SigmaToFileUnits(p, s.Sigma(static_cast<int>(k), c));
      csv += Fmt(",%.9g", v) + Fmt(",%.9g", sd);
      cj["delta_x"][kinematics::ParamName(p)] = v;
      cj["sigma"][kinematics::ParamName(p)] = sd;
    }
    csv += "\n";
    j["cycles"].push_back(cj);
  }
  const int last = e.ball.NumCycles() - 1;
  std::cout << "last cycle " << e.ball.cycles[last].cycle << " (mm, deg; value ± sigma):\n";
  for (std::size_t k = 0; k < params.size(); ++k) {
    const int p = params[k];
    std::cout << "  " << kinematics::ParamName(p) << " = "
              << ValueWithSigma(p, x(p, last), s.Sigma(static_cast<int>(k), last)) << "\n";
  }
  std::vector<std::pair<std::string, std::string>> files;
  if (!opt.out_path.empty()) files.emplace_back(opt.out_path, csv);
  if (!opt.json_path.empty()) files.emplace_back(opt.json_path, j.dump(2) + "\n");
  StampOutputs(&files, provenance);
  WriteFilesAtomically(files);
  for (const auto& f : files) std::cout << "wrote " << f.first << "\n";
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
    sub->callback([opt, exit_code, sub]() { *exit_code = RunSimulateThermal(*opt, CommandProvenance(sub)); });
  }
  CLI::App* thermal =
      GetOrAddSubcommand(app, "thermal", "Thermal drift: identify, screen parameters, compensate, predict");
  {
    auto opt = std::make_shared<IdentifyOptions>();
    CLI::App* sub = thermal->add_subcommand("identify", "Identify the parameter drift per cycle (eqs. 3-5..3-10)");
    AddInputs(sub, &opt->in, false);
    sub->add_option("--params", opt->in.params, "Parameters: names (d4,alpha3,...), 'traditional' or 'all'");
    sub->add_option("--poses", opt->in.poses, "Pose positions to use (0-based, comma list); default all");
    sub->add_option("--pose-budget", opt->in.pose_budget, "Choose this many poses D-optimally for --params");
    sub->add_option("--out", opt->out_path, "ΔX per cycle CSV (mm, deg), each parameter followed by its sigma");
    sub->add_option("--json", opt->json_path, "ΔX and sigma per cycle, the guard and the covariance scaling (JSON)");
    AddGuardOptions(sub, &opt->in);
    sub->callback([opt, exit_code, sub]() { *exit_code = RunIdentify(*opt, CommandProvenance(sub)); });
  }
  RegisterThermalScreen(thermal, exit_code);
  RegisterThermalCompensate(thermal, exit_code);
  RegisterThermalPredict(thermal, exit_code);
}

}  // namespace ramtk::tools
