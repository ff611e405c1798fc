#pragma once
// Subcommands of the `ramtk` tool. Each Register* binds a CLI11 subcommand to an options struct
// and sets the function that runs it. Commands return the process exit code:
//   0 success, 1 bad input (file, field or value), 2 command-line usage, 3 no solution,
//   4 failure that is not the input's fault (out of memory, a library error, an internal error);
//   128 + n when ended by signal n (130 SIGINT, 143 SIGTERM), after removing unfinished outputs.

#include <CLI/CLI.hpp>
#include <string>

namespace ramtk::tools {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitNoSolution = 3;
inline constexpr int kExitFailure = 4;

// The `name` subcommand of `app` (a group such as `calib`), created by the first module that asks.
CLI::App* GetOrAddSubcommand(CLI::App& app, const std::string& name, const std::string& description);
// `ramtk simulate`: every module's simulator registers below it.
CLI::App* SimulateCommand(CLI::App& app);

// Sets *exit_code when the subcommand runs.
void RegisterFkCommand(CLI::App& app, int* exit_code);
void RegisterIkCommand(CLI::App& app, int* exit_code);
void RegisterThermalCommands(CLI::App& app, int* exit_code);  // simulate thermal, thermal ...
void RegisterTcfCommand(CLI::App& app, int* exit_code);       // tcf … and simulate tcf
void RegisterCalibCommands(CLI::App& app,
                           int* exit_code);  // calib sensor-robot|cameras|hand-eye, simulate sensor-robot|hand-eye
void RegisterPatternsCommand(CLI::App& app, int* exit_code);
void RegisterDecodeCommand(CLI::App& app, int* exit_code);
void RegisterSimulateFringeCommand(CLI::App& app, int* exit_code);
void RegisterDiagnoseCommand(CLI::App& app, int* exit_code);  // diagnose DATA
void RegisterScanCommand(CLI::App& app, int* exit_code);  // scan SET | --batch LIST [--shard K/N]
void RegisterMergeCommand(CLI::App& app, int* exit_code);  // merge --batch LIST --out DIR
void RegisterMeasureCommand(CLI::App& app, int* exit_code);  // measure --scans --log
void RegisterCampaignCommand(CLI::App& app, int* exit_code);  // simulate campaign
void RegisterPlanCommands(CLI::App& app, int* exit_code);     // plan poses
void RegisterManifestCommand(CLI::App& app, int* exit_code);  // manifest DIR --sequence SPEC

}  // namespace ramtk::tools
