// The ramtk command line: one binary, one thin subcommand per job (see `ramtk --help`).
//
// The error boundary of every command: whatever a command throws ends here as one line on
// stderr and a documented exit code (commands.h), never as an abort.
#include <filesystem>
#include <iostream>
#include <new>
#include <opencv2/core.hpp>

#include "command_provenance.h"
#include "commands.h"
#include "huge_pages.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/provenance.h"

namespace {

// One line: OpenCV's what() spans several lines and repeats the source location.
std::string OneLine(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

int Fail(const std::string& message, int code) {
  ramtk::RemoveRegisteredTemporaries();
  std::cerr << "ramtk: error: " << OneLine(message) << '\n';
  ramtk::LogToFile(ramtk::LogLevel::kError, OneLine(message));
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // Before anything else: the heap's settings and huge pages (huge_pages.h).
  ramtk::tools::UseHugePagesForTheHeap(argc, argv);
  // Before any other thread exists: SIGINT/SIGTERM remove unfinished outputs, then exit 128+n.
  ramtk::InstallInterruptCleanup("ramtk");
  // Every output records the command line that made it (command_provenance.h).
  ramtk::tools::RecordCommandLine(argc, argv);
  CLI::App app{"ramtk — robot accuracy maintenance toolkit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ramtk " + ramtk::RamtkVersion());
  app.add_flag_callback(
      "-v,--verbose", [] { ramtk::SetLogThreshold(ramtk::LogLevel::kDebug); }, "Log debug messages");
  // Before the subcommand runs (CLI11 calls an option's callback as it parses it).
  app.add_option_function<std::string>(
         "--log-file", [](const std::string& path) { ramtk::SetLogFile(path); },
         "Also write every message (debug and above) into FILE, appended, one time-stamped line each "
         "(2026-11-29T09:41:07.125Z warning: ...), with the progress lines; stderr is unchanged")
      ->type_name("FILE")
      ->trigger_on_parse();
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
  ramtk::tools::RegisterMergeCommand(app, &exit_code);
  ramtk::tools::RegisterMeasureCommand(app, &exit_code);
  ramtk::tools::RegisterCampaignCommand(app, &exit_code);
  ramtk::tools::RegisterPlanCommands(app, &exit_code);
  ramtk::tools::RegisterManifestCommand(app, &exit_code);
  using ramtk::tools::kExitBadInput;
  using ramtk::tools::kExitFailure;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : ramtk::tools::kExitUsage;
  } catch (const ramtk::InputError& e) {
    return Fail(e.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return Fail("out of memory (an input asks for more memory than this machine has; check image sizes and counts)",
                kExitFailure);
  } catch (const std::filesystem::filesystem_error& e) {
    return Fail(e.what(), kExitBadInput);  // names the path(s)
  } catch (const cv::Exception& e) {
    if (e.code == cv::Error::StsNoMem) return Fail("out of memory (OpenCV: " + e.err + ")", kExitFailure);
    return Fail("OpenCV " + e.func + ": " + e.err, kExitFailure);
  } catch (const std::exception& e) {
    return Fail(std::string("internal error: ") + e.what(), kExitFailure);
  } catch (...) {
    return Fail("internal error: unknown exception", kExitFailure);
  }
  return exit_code;
}
