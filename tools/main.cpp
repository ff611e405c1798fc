// The ramtk command line: one binary, one thin subcommand per job (see `ramtk --help`).
#include <iostream>

#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"

int main(int argc, char** argv) {
  CLI::App app{"ramtk — robot accuracy maintenance toolkit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ramtk 0.1.0");
  app.add_flag_callback("-v,--verbose", [] { ramtk::SetLogThreshold(ramtk::LogLevel::kDebug); },
                        "Log debug messages");
  ramtk::SetLogSink([](ramtk::LogLevel level, const std::string& message) {
    std::cerr << "ramtk: " << ramtk::LogLevelName(level) << ": " << message << '\n';
  });

  int exit_code = ramtk::tools::kExitOk;
  ramtk::tools::RegisterFkCommand(app, &exit_code);
  ramtk::tools::RegisterIkCommand(app, &exit_code);
  ramtk::tools::RegisterThermalCommands(app, &exit_code);
  ramtk::tools::RegisterTcfCommand(app, &exit_code);
  ramtk::tools::RegisterCalibCommands(app, &exit_code);
  ramtk::tools::RegisterPatternsCommand(app, &exit_code);
  ramtk::tools::RegisterDecodeCommand(app, &exit_code);
  ramtk::tools::RegisterSimulateFringeCommand(app, &exit_code);
  ramtk::tools::RegisterDiagnoseCommand(app, &exit_code);
  ramtk::tools::RegisterScanCommand(app, &exit_code);
  ramtk::tools::RegisterMeasureCommand(app, &exit_code);
  ramtk::tools::RegisterCampaignCommand(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : ramtk::tools::kExitUsage;
  } catch (const ramtk::InputError& e) {
    std::cerr << "ramtk: error: " << e.what() << '\n';
    return ramtk::tools::kExitBadInput;
  }
  return exit_code;
}
