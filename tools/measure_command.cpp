// ramtk measure: scan batch results + controller log -> robot-measurement CSV with centre covariance.
#include <cstdio>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/campaign/controller_log.h"
#include "ramtk/campaign/measure.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"

namespace ramtk::tools {
namespace {

struct MeasureCommandOptions {
  std::string scans;              // results.csv of `ramtk scan --batch`
  std::string log;                // controller log CSV
  std::string out = "ball.csv";   // robot-measurement CSV
  double time_tolerance = 0.5;    // s
  bool by_time = false;           // match by time even if the log names the sets
};

int RunMeasure(const MeasureCommandOptions& opt, Provenance provenance) {
  campaign::MeasureOptions options;
  options.time_tolerance_s = opt.time_tolerance;
  options.by_time = opt.by_time;
  const std::string bad = options.Validate();
  if (!bad.empty()) throw InputError({"", 0, "--time-tolerance"}, bad);
  CheckOutputAgainstInputs(opt.out, {opt.scans, opt.log}, "--out");
  const std::vector<campaign::CaptureCentre> captures = campaign::ReadScanResults(opt.scans);
  const campaign::ControllerLog log = campaign::ReadControllerLog(opt.log);
  campaign::MeasureSummary summary;
  const kinematics::RobotMeasurementSet set = campaign::JoinCentresWithLog(captures, log, options, &summary);
  if (set.rows.empty()) throw InputError({opt.scans, 0, "status"}, "no capture has a sphere centre: nothing to write");
  kinematics::WriteRobotMeasurements(set, opt.out);
  for (const std::string& f : {opt.scans, opt.log}) AddProvenanceFile(&provenance, f);
  const std::string sidecar = WriteProvenanceSidecar(opt.out, provenance);
  for (const campaign::LeftOut& l : summary.left_out) {
    std::printf("left out: %s (cycle %d, pose %d): %s\n", l.set.c_str(), l.cycle, l.pose, l.reason.c_str());
  }
  for (const std::string& w : summary.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("%s\nwrote %s (provenance in %s)\n", summary.BriefReport().c_str(), opt.out.c_str(), sidecar.c_str());
  return kExitOk;
}

}  // namespace

void RegisterMeasureCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<MeasureCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "measure",
      "Join scan-batch centres with the controller log into the robot-measurement CSV (cycle,time_s,pose,q1..q6,x,y,z "
      "+ centre covariance cov_xx..cov_yz in mm^2 + the log's extra columns)");
  sub->add_option("--scans", opt->scans, "results.csv written by `ramtk scan --batch` (covariance from each spheres.json)")
      ->required();
  sub->add_option("--log", opt->log, "Controller log CSV: [set,]time_s,cycle,pose,q1..q6[,temp_j1..] (docs/formats.md)")
      ->required();
  sub->add_option("--out", opt->out, "Robot-measurement CSV to write")->capture_default_str();
  sub->add_option("--time-tolerance", opt->time_tolerance,
                  "Largest |capture time - log time| (s) when matching by time (manifest capture_time_s)")
      ->capture_default_str();
  sub->add_flag("--by-time", opt->by_time, "Match captures to log rows by time even when the log has a set column");
  sub->callback([opt, exit_code, sub]() { *exit_code = RunMeasure(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
