// ramtk calib robot | simulate robot-calibration: thin wrappers over ramtk::calib's robot
// calibration (calib/robot_calibration.h).

#include <cstdio>
#include <filesystem>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "ramtk/calib/robot_calibration.h"
#include "ramtk/calib/robot_calibration_io.h"
#include "ramtk/calib/robot_calibration_report.h"
#include "ramtk/calib/robot_calibration_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::tools {
namespace {

struct CalibRobotCommandOptions {
  std::string robot_path;
  std::string data_path;
  std::string format_path;
  std::vector<std::string> predict_paths;
  std::string out;
  bool force = false;
  bool setup_only = false;
  bool no_rotation = false;
  bool no_cyclic = false;
  bool no_compliance = false;
  bool remove_drift = false;
  bool report = false;  // DIR/report.html
  std::string split = "random";
  std::string loss = "none";
  std::string covariance = "scaled";
  calib::RobotCalibrationOptions calib;
};

kinematics::TrackerMeasurements ReadData(const std::string& path, const kinematics::TrackerFormat& format,
                                         bool remove_drift) {
  kinematics::TrackerMeasurements data = kinematics::ReadTrackerMeasurements(path, format);
  if (remove_drift) {
    const double rms = kinematics::RemoveTrackerDrift(&data);
    std::printf("%s: tracker drift removed with the reference targets (RMS correction %.4f mm)\n", path.c_str(), rms);
  }
  return data;
}

void PrintStats(const char* what, const calib::ResidualStats& s) {
  std::printf("  %-28s RMS per coordinate %8.4f mm   3-D RMS %8.4f mm   max %8.4f mm", what, s.rms_per_coordinate_mm,
              s.rms_3d_mm, s.max_3d_mm);
  if (s.rms_rotation_deg > 0) std::printf("   rotation RMS %.4f deg", s.rms_rotation_deg);
  std::printf("\n");
}

int RunCalibRobot(CalibRobotCommandOptions opt, Provenance provenance) {
  std::vector<std::string> inputs = {opt.robot_path, opt.data_path};
  if (!opt.format_path.empty()) inputs.push_back(opt.format_path);
  inputs.insert(inputs.end(), opt.predict_paths.begin(), opt.predict_paths.end());
  CheckOutputAgainstInputs(opt.out, inputs, "--out");
  const kinematics::RobotChain nominal = kinematics::ReadRobotChain(opt.robot_path);
  const kinematics::TrackerFormat format =
      opt.format_path.empty() ? kinematics::TrackerFormat{} : kinematics::ReadTrackerFormat(opt.format_path);
  const kinematics::TrackerMeasurements data = ReadData(opt.data_path, format, opt.remove_drift);
  std::vector<kinematics::TrackerMeasurements> others;
  for (const std::string& p : opt.predict_paths) others.push_back(ReadData(p, format, opt.remove_drift));
  StagedFolder staged(opt.out, opt.force, "--out");
  for (const std::string& f : inputs) AddProvenanceFile(&provenance, f);

  calib::RobotCalibrationOptions& o = opt.calib;
  o.identify_links = !opt.setup_only;
  o.use_rotation = !opt.no_rotation;
  o.try_cyclic = !opt.no_cyclic;
  o.try_compliance = !opt.no_compliance;
  o.split = opt.split == "blocks" ? calib::HoldoutSplit::kBlocks : calib::HoldoutSplit::kRandom;
  o.loss = opt.loss == "huber" ? calib::RobustLoss::kHuber
           : opt.loss == "cauchy" ? calib::RobustLoss::kCauchy
                                  : calib::RobustLoss::kNone;
  o.covariance = opt.covariance == "sandwich" ? calib::CovarianceKind::kSandwich
                 : opt.covariance == "nominal" ? calib::CovarianceKind::kNominal
                                               : calib::CovarianceKind::kScaled;
  o.progress = ProgressPrinter("steps");
  calib::RobotCalibrationSummary summary;
  const calib::RobotCalibration result = calib::CalibrateRobot(nominal, data, o, &summary);

  // The robot file holds the best links without terms: the commands that read it know no terms.
  kinematics::RobotChain out_chain = result.links_only;
  out_chain.source = "calibrated by ramtk calib robot from " + std::filesystem::path(opt.data_path).filename().string() +
                     (nominal.source.empty() ? "" : "; nominal: " + nominal.source);
  kinematics::WriteRobotChain(out_chain, (staged.path() / "robot.yaml").string());
  WriteFileAtomically((staged.path() / "calibration.json").string(), WithProvenance(calib::RobotCalibrationJson(result, summary), provenance));
  WriteFileAtomically((staged.path() / "residuals.csv").string(), calib::RobotCalibrationResidualsCsv(data, summary));
  if (opt.report) {
    report::HtmlReport page = calib::RobotCalibrationReport(result, summary, data);
    page.AddProvenance(provenance);
    WriteFileAtomically((staged.path() / "report.html").string(), page.Page());
  }

  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf("%s", calib::RobotCalibrationTable(result).c_str());
  PrintStats("nominal links, set-up fitted", summary.before);
  PrintStats("calibrated (fit)", summary.after);
  PrintStats("held-out, links only", summary.held_out_geometric);
  PrintStats("held-out, final model", summary.held_out);
  std::printf("  predicted held-out RMS per coordinate %.4f mm (from the fit's sigma); terms kept:",
              summary.predicted_held_out_mm);
  for (const std::string& t : summary.terms_kept) std::printf(" %s", t.c_str());
  std::printf("%s\n", summary.terms_kept.empty() ? " none" : "");
  std::printf("  identifiability: %d identified, %d eliminated, condition number %.3g, O1 %.3g, noise amplification %.3g\n",
              summary.num_identified, summary.num_eliminated, summary.condition_number, summary.observability_index,
              summary.noise_amplification_index);
  std::printf("  coverage: targets spread %.0f mm RMS (reach %.0f mm); joint ranges (deg)", summary.workspace_spread_mm,
              summary.reach_mm);
  for (double r : summary.joint_range_deg) std::printf(" %.0f", r);
  std::printf("\n");
  // Other series: the calibrated links with the set-up re-fitted (the tracker may have moved).
  for (std::size_t i = 0; i < others.size(); ++i) {
    calib::RobotCalibrationOptions po;
    po.identify_links = false;
    po.try_cyclic = false;
    po.try_compliance = false;
    po.use_rotation = o.use_rotation;
    po.folds = o.folds;
    calib::RobotCalibrationSummary ps, nominal_summary;
    calib::CalibrateRobot(result.links_only, others[i], po, &ps);
    calib::CalibrateRobot(nominal, others[i], po, &nominal_summary);
    std::printf("%s (%d poses), set-up re-fitted:\n", opt.predict_paths[i].c_str(), ps.num_poses);
    PrintStats("nominal links", nominal_summary.after);
    PrintStats("calibrated links", ps.after);
  }
  for (const std::string& w : summary.warnings) std::printf("warning: %s\n", w.c_str());
  staged.Commit();
  std::printf("wrote %s/{robot.yaml,calibration.json,residuals.csv%s}\n", opt.out.c_str(), opt.report ? ",report.html" : "");
  return summary.termination == Termination::kSuccess || summary.termination == Termination::kPartial
             ? kExitOk
             : kExitNoSolution;
}

struct SimulateRobotCommandOptions {
  std::string robot_path;
  std::string csv_path;
  std::string truth_path;
  calib::RobotCalibrationSimOptions sim;
};

// Points only, in the default tracker columns: pose,q1..qN (deg),x,y,z (mm).
std::string SimulatedCsv(const kinematics::TrackerMeasurements& data) {
  std::string out = "pose";
  for (int j = 1; j <= data.num_joints; ++j) out += ",q" + std::to_string(j);
  out += ",x,y,z\n";
  char cell[64];
  for (std::size_t i = 0; i < data.poses.size(); ++i) {
    out += std::to_string(i);
    for (double q : data.poses[i].q_rad) {
      std::snprintf(cell, sizeof cell, ",%.9f", RadToDeg(q));
      out += cell;
    }
    const Vec3& p = data.poses[i].targets[0].position_mm;
    std::snprintf(cell, sizeof cell, ",%.6f,%.6f,%.6f\n", p.x(), p.y(), p.z());
    out += cell;
  }
  return out;
}

int RunSimulateRobot(const SimulateRobotCommandOptions& opt, Provenance provenance) {
  CheckOutputsDistinct({{"--output", opt.csv_path}, {"--truth", opt.truth_path}});
  CheckOutputAgainstInputs(opt.csv_path, {opt.robot_path}, "--output");
  CheckOutputAgainstInputs(opt.truth_path, {opt.robot_path}, "--truth");
  const kinematics::RobotChain nominal = kinematics::ReadRobotChain(opt.robot_path);
  const calib::RobotCalibrationSimulation sim = calib::SimulateRobotCalibration(nominal, opt.sim);
  kinematics::RobotChain truth = sim.truth;
  truth.source = "ramtk simulate robot-calibration (seed " + std::to_string(opt.sim.seed) + ")";
  AddProvenanceFile(&provenance, opt.robot_path);
  WriteFileAtomically(opt.csv_path, SimulatedCsv(sim.data));
  kinematics::WriteRobotChain(truth, opt.truth_path);
  WriteProvenanceSidecar(opt.csv_path, provenance);
  WriteProvenanceSidecar(opt.truth_path, provenance);
  std::printf("simulated %d poses of %s (link errors %.3f mm / %.4f deg, noise %.4f mm); wrote %s and %s\n",
              opt.sim.num_poses, nominal.name.c_str(), opt.sim.length_error_mm, opt.sim.angle_error_deg,
              opt.sim.position_noise_mm, opt.csv_path.c_str(), opt.truth_path.c_str());
  return kExitOk;
}

}  // namespace

void RegisterSimulateRobot(CLI::App* simulate, int* exit_code) {
  auto opt = std::make_shared<SimulateRobotCommandOptions>();
  CLI::App* sub = simulate->add_subcommand(
      "robot-calibration", "A tracker measuring a target on a robot whose links differ from the file by known errors");
  sub->add_option("--robot", opt->robot_path, "Nominal robot file (YAML, any number of joints)")->required();
  sub->add_option("--output", opt->csv_path, "Tracker CSV to write (pose,q1..qN,x,y,z)")->required();
  sub->add_option("--truth", opt->truth_path, "The true robot file to write (YAML)")->required();
  sub->add_option("--poses", opt->sim.num_poses, "Number of poses")->capture_default_str();
  sub->add_option("--length-error", opt->sim.length_error_mm, "Link length errors (mm, 1 sigma)")->capture_default_str();
  sub->add_option("--angle-error", opt->sim.angle_error_deg, "Link angle errors (deg, 1 sigma)")->capture_default_str();
  sub->add_option("--noise", opt->sim.position_noise_mm, "Tracker noise per coordinate (mm, 1 sigma)")
      ->capture_default_str();
  sub->add_option("--seed", opt->sim.seed, "Seed of the errors and poses")->capture_default_str();
  sub->add_option("--noise-seed", opt->sim.noise_seed, "Seed of the noise")->capture_default_str();
  sub->callback([opt, exit_code, sub]() { *exit_code = RunSimulateRobot(*opt, CommandProvenance(sub)); });
}

void RegisterCalibRobot(CLI::App* calib, int* exit_code) {
  auto opt = std::make_shared<CalibRobotCommandOptions>();
  CLI::App* sub = calib->add_subcommand(
      "robot", "Kinematic calibration of a serial robot (any joint count) from tracker points or 6-D poses");
  sub->add_option("--robot", opt->robot_path, "Nominal robot file (YAML, any number of joints)")->required();
  sub->add_option("--data", opt->data_path, "Tracker measurement file (CSV; docs/formats.md, Tracker files)")->required();
  sub->add_option("--format", opt->format_path, "Column description of the tracker file (YAML); default q1..qN,x,y,z");
  sub->add_option("--out", opt->out, "Output folder: robot.yaml, calibration.json, residuals.csv")->required();
  sub->add_flag("--force", opt->force, "Replace an existing output folder (once the new one is complete)");
  sub->add_option("--predict", opt->predict_paths,
                  "Further measurement files (same format) predicted with the calibrated links, set-up re-fitted");
  sub->add_flag("--setup-only", opt->setup_only, "Identify only tracker_from_base and the targets; links as given");
  sub->add_flag("--no-rotation", opt->no_rotation, "Use only the positions of 6-D data");
  sub->add_flag("--no-cyclic", opt->no_cyclic, "Do not try per-joint cyclic error terms");
  sub->add_flag("--no-compliance", opt->no_compliance, "Do not try gravity compliance terms");
  sub->add_flag("--remove-drift", opt->remove_drift, "Remove tracker drift with the reference targets");
  sub->add_flag("--report", opt->report,
                "Also write DIR/report.html: residuals per pose and against each joint, the targets in 3-D, the "
                "identifiability table (opens offline)");
  sub->add_option("--folds", opt->calib.folds, "Folds of the held-out validation")->capture_default_str();
  sub->add_option("--split", opt->split, "Held-out split: random (seeded) or blocks (contiguous in file order)")
      ->check(CLI::IsMember({"random", "blocks"}))
      ->capture_default_str();
  sub->add_option("--seed", opt->calib.seed, "Seed of the random split")->capture_default_str();
  sub->add_option("--harmonics", opt->calib.cyclic_harmonics, "Harmonics of the cyclic terms")->capture_default_str();
  sub->add_option("--min-term-gain", opt->calib.min_term_gain,
                  "Keep a non-geometric term group when the held-out RMS drops by this fraction")
      ->capture_default_str();
  sub->add_option("--parallel-axes", opt->calib.parallel_axes_deg,
                  "Offer beta where consecutive axes are within this angle of parallel (deg)")
      ->capture_default_str();
  sub->add_option("--loss", opt->loss, "Robust loss: none, huber or cauchy")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}))
      ->capture_default_str();
  sub->add_option("--loss-scale", opt->calib.loss_scale, "Robust loss scale (sigma units)")->capture_default_str();
  sub->add_option("--covariance", opt->covariance,
                  "Parameter sigma: scaled (by the residual), sandwich (robust) or nominal (stated sigma)")
      ->check(CLI::IsMember({"scaled", "sandwich", "nominal"}))
      ->capture_default_str();
  sub->add_option("--position-sigma", opt->calib.position_sigma_mm,
                  "Sigma of a coordinate where the file gives none (mm); re-estimated from the residuals")
      ->capture_default_str();
  sub->add_option("--rotation-sigma", opt->calib.rotation_sigma_deg,
                  "Sigma of a rotation component where the file gives none (deg); re-estimated")
      ->capture_default_str();
  sub->callback([opt, exit_code, sub]() { *exit_code = RunCalibRobot(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
