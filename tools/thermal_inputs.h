#pragma once
// What the `ramtk thermal` subcommands share: the experiment's input files as options, loading
// them, output checks and the identification options built from them.
#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ramtk/kinematics/robot_model.h"
#include "ramtk/thermal/cycles.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::tools {

// printf-style formatting of one number.
std::string Fmt(const char* format, double v);

struct ExperimentInputs {
  std::string robot_path;
  std::string setup_path;
  std::string ball_path;
  std::string monitoring_path;
  int reference_cycle = 0;
  double joint_tolerance_deg = 0.01;
  std::string params;           // names, "traditional", "all"
  std::string poses;            // pose positions, comma list
  int pose_budget = 0;          // choose this many poses D-optimally for `params`
  bool unweighted = false;      // ignore the ball file's centre covariance (cov_xx..cov_yz)
  double robot_noise_mm = 0.0;  // robot repeatability σ per axis added to every centre's covariance
  double max_condition = 1e3;   // guard: largest condition number of the column-scaled matrix
  bool reduce = false;          // guard: drop unobservable parameters instead of refusing
};

void AddInputs(CLI::App* sub, ExperimentInputs* in, bool monitoring_required);
// --max-condition and --reduce (the identifiability guard).
void AddGuardOptions(CLI::App* sub, ExperimentInputs* in);

// The named outputs may not be an input of the experiment or each other (core/outputs.h).
void CheckOutputs(const ExperimentInputs& in, const std::vector<std::pair<std::string, std::string>>& outputs,
                  const std::vector<std::string>& more_inputs = {});

struct LoadedExperiment {
  kinematics::RobotModel model;
  thermal::ThermalSetup setup;
  thermal::CycleSeries ball;
  thermal::CycleSeries monitoring;
  bool has_monitoring = false;
};

LoadedExperiment Load(const ExperimentInputs& in);

// Weights from the ball file's centre covariance (when it has the columns and --unweighted is off).
std::vector<std::vector<Mat3>> Weights(const ExperimentInputs& in, const LoadedExperiment& e);

thermal::IdentificationOptions MakeIdOptions(const ExperimentInputs& in, const LoadedExperiment& e,
                                             const thermal::DriftModel& dm, const std::vector<int>& params);

// Runs the identifiability guard (thermal::CheckIdentifiability) on id's parameters and poses and
// prints its report. Refused: prints the error to stderr and returns false. With --reduce,
// id->params becomes the reduced set.
bool GuardIdentification(const ExperimentInputs& in, const thermal::DriftModel& dm, thermal::IdentificationOptions* id,
                         thermal::IdentifiabilitySummary* summary = nullptr);

// "0.01234 ± 0.00056" of parameter p (SI) in file units (mm, deg).
std::string ValueWithSigma(int p, double value, double sigma);

// The ball file's pose ids of the identification's pose positions.
std::vector<int> PoseIds(const LoadedExperiment& e, const thermal::IdentificationOptions& id);

std::string IntList(const std::vector<int>& v);

// The `thermal` subcommands beside identify (thermal_command.cpp).
void RegisterThermalScreen(CLI::App* thermal, int* exit_code);
void RegisterThermalCompensate(CLI::App* thermal, int* exit_code);
void RegisterThermalPredict(CLI::App* thermal, int* exit_code);

}  // namespace ramtk::tools
