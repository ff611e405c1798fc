// ramtk simulate campaign: the digital twin of a thermal measurement campaign, run end to end.
#include <cstdio>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "ramtk/campaign/campaign.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct CampaignCommandOptions {
  std::string robot_path;
  std::string out_dir;
  campaign::CampaignOptions o;
  bool quiet = false;
  bool force = false;
};

int RunCampaign(const CampaignCommandOptions& opt, Provenance provenance) {
  CheckOutputAgainstInputs(opt.out_dir, {opt.robot_path}, "--out");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  AddProvenanceFile(&provenance, opt.robot_path);
  campaign::CampaignOptions o = opt.o;
  const std::string bad = o.Validate();
  if (!bad.empty()) throw InputError({"", 0, "campaign options"}, bad);
  if (!opt.quiet) {
    o.progress = ProgressPrinter("sets");
  }
  const campaign::CampaignSummary s = campaign::SimulateAndRunCampaign(model, o, opt.out_dir, opt.force, provenance);
  if (s.cancelled) {
    std::fprintf(stderr, "cancelled: nothing written to %s\n", opt.out_dir.c_str());
    return kExitFailure;
  }
  std::printf("%s", campaign::BudgetMarkdown(s).c_str());
  if (!s.screened.empty())
    std::printf("\nScreening (image-derived centres), Table 5-1 form:\n%s\nTable 5-2 form:\n%s",
                s.screening_elimination.c_str(), s.screening_comparison.c_str());
  for (const std::string& l : s.left_out) std::printf("left out: %s\n", l.c_str());
  std::printf(
      "%s\ntimes: render %.1f s, scan %.1f s, chain %.1f s\nwrote %s/budget.json, budget.md, monitoring_error.png\n",
      s.BriefReport().c_str(), s.render_s, s.scan_s, s.chain_s, opt.out_dir.c_str());
  if (o.html_report) std::printf("wrote %s/report.html\n", opt.out_dir.c_str());
  return kExitOk;
}

}  // namespace

void RegisterCampaignCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<CampaignCommandOptions>();
  CLI::App* sub = SimulateCommand(app)->add_subcommand(
      "campaign",
      "Digital twin of a thermal campaign: render the ball's fringe sets per cycle and pose, write the controller "
      "log and truth, then run scan -> measure -> calib sensor-robot (cold cycle) -> thermal identify -> compensate "
      "and write the error budget (budget.json, budget.md, monitoring_error.png)");
  sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
  sub->add_option("--out", opt->out_dir, "Output folder (new or empty; written as a unit)")->required();
  sub->add_flag("--force", opt->force, "Replace an existing output folder (only once the new one is complete)");
  sub->add_option("--cycles", opt->o.cycles, "Measurement cycles")->capture_default_str();
  sub->add_option("--poses", opt->o.ball_poses, "Ball poses per cycle")->capture_default_str();
  sub->add_option("--points", opt->o.monitoring_points, "Monitoring points per cycle")->capture_default_str();
  sub->add_option("--period", opt->o.cycle_period_s, "Time between cycles, s")->capture_default_str();
  sub->add_option("--scale", opt->o.image_scale, "Camera window scale (1 = 640x512 around the ball)")
      ->capture_default_str();
  sub->add_option("--supersampling", opt->o.supersampling, "n x n rays per pixel")->capture_default_str();
  sub->add_option("--repeatability", opt->o.repeatability_mm, "Robot repeatability sigma per axis, mm")
      ->capture_default_str();
  sub->add_option("--seed", opt->o.seed, "Random seed")->capture_default_str();
  sub->add_option("--jobs", opt->o.jobs, "Sets rendered / scanned at once")->capture_default_str();
  sub->add_option("--screen-keep", opt->o.screen_keep,
                  "Parameter screening on the image-derived centres (Tables 5-1/5-2, chain/screening.txt): "
                  "parameters kept; 0 = by held-out error; -1 = skip")
      ->capture_default_str();
  sub->add_option("--scan-min-depth", opt->o.scan_min_depth_mm,
                  "Nearest depth the scan searches, mm (ramtk scan --min-depth; the simulated scene lies 600-900 mm away)")
      ->capture_default_str();
  sub->add_option("--scan-max-depth", opt->o.scan_max_depth_mm,
                  "Farthest depth the scan searches, mm (ramtk scan --max-depth)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", opt->quiet, "No progress on stderr");
  sub->add_flag("--report", opt->o.html_report,
                "Also write report.html: the budget, calibration errors and the monitoring "
                "figure on one self-contained page");
  sub->callback([opt, exit_code, sub]() { *exit_code = RunCampaign(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
