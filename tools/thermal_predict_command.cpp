// ramtk thermal predict: the drift between ball windows, temperature model or Kalman filter against hold-last.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "ramtk/thermal/predictor.h"
#include "ramtk/thermal/thermal_report.h"
#include "thermal_inputs.h"

namespace ramtk::tools {
namespace {

using namespace thermal;

// ---------------------------------------------------------------- thermal predict
struct PredictOptions {
  ExperimentInputs in;
  int window_every = 10;
  int min_windows = 4;
  std::string train_ball;      // optional characterisation run (identified every cycle, all poses)
  std::string train_setup;     // its setup (default: --setup)
  double kalman_ratio = -1.0;  // >= 0: Kalman filter with this process/measurement ratio per hour
};

int RunPredict(const PredictOptions& opt) {
  const LoadedExperiment e = Load(opt.in);
  const ThermalExperiment ex = MakeExperiment(e.model, e.setup, e.ball, e.monitoring);
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  IdentificationOptions id = MakeIdOptions(opt.in, e, dm, ParseParamList(opt.in.params, e.model, "--params"));
  if (!GuardIdentification(opt.in, dm, &id)) return kExitNoSolution;
  const std::vector<int> params = id.params;
  const Eigen::MatrixXd x = IdentifyForMonitoring(ex, dm, id);
  Eigen::MatrixXd temps;
  std::vector<double> times;
  CycleTemperatures(e.ball, ex.ball_column, &temps, &times);
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
    CycleTemperatures(train, all, &ttemps, &ttimes);
    offline = std::make_unique<TemperatureDriftModel>(FitTemperatureModel(tx, ttemps, ttimes, params, po.model));
  }
  DriftPredictionSummary ps;
  DriftPrediction pred = PredictDrift(x, temps, times, params, po, offline.get(), &ps);
  if (!(opt.kalman_ratio < 0.0)) {  // given (NaN too, for Validate to refuse)
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
  const PredictionScore score = ScorePredictionOnMonitoring(MonitoringModel(e.model, e.setup, e.monitoring), pred, x);
  std::cout << ps.BriefReport() << "\n"
            << "between-window error on the monitoring points vs the held-out per-cycle identification (RMS 3-D):\n"
            << "  hold-last " << Fmt("%.4f", score.hold_last_rms_mm) << " mm, "
            << (opt.kalman_ratio >= 0.0 ? "Kalman filter " : "temperature model ")
            << Fmt("%.4f", score.predicted_rms_mm) << " mm\n"
            << "(the reference itself carries the per-cycle identification noise; score against truth in tests)\n";
  return kExitOk;
}

}  // namespace

void RegisterThermalPredict(CLI::App* thermal, int* exit_code) {
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
  AddGuardOptions(sub, &opt->in);
  sub->callback([opt, exit_code]() { *exit_code = RunPredict(*opt); });
}

}  // namespace ramtk::tools
