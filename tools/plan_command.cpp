// ramtk plan poses: a thin wrapper over ramtk::calib's pose planning (calib/pose_planning.h).

#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/calib/pose_planning.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::tools {
namespace {

struct PlanPosesCommandOptions {
  std::string robot_path;
  std::string candidates_path;
  std::string format_path;
  int sample = 0;
  std::string limits = "170";
  std::string out;
  calib::PosePlanningOptions plan;
};

std::vector<double> ParseLimits(const std::string& text) {
  std::vector<double> out;
  std::stringstream s(text);
  std::string cell;
  while (std::getline(s, cell, ',')) {
    try {
      std::size_t used = 0;
      out.push_back(std::stod(cell, &used));
      if (cell.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(cell);
    } catch (const std::exception&) {
      throw InputError({"", 0, "--limits"}, "expected degrees separated by commas, got '" + cell + "'");
    }
  }
  return out;
}

int RunPlanPoses(const PlanPosesCommandOptions& opt, Provenance provenance) {
  std::vector<std::string> inputs = {opt.robot_path};
  if (!opt.candidates_path.empty()) inputs.push_back(opt.candidates_path);
  if (!opt.format_path.empty()) inputs.push_back(opt.format_path);
  CheckOutputAgainstInputs(opt.out, inputs, "--out");
  const kinematics::RobotChain nominal = kinematics::ReadRobotChain(opt.robot_path);
  std::vector<Eigen::VectorXd> candidates;
  std::string origin;
  if (!opt.candidates_path.empty()) {
    std::unique_ptr<kinematics::TrackerFormat> format;
    if (!opt.format_path.empty()) {
      format = std::make_unique<kinematics::TrackerFormat>(kinematics::ReadTrackerFormat(opt.format_path));
    }
    candidates = calib::ReadCandidateJoints(opt.candidates_path, format.get(), nominal.NumJoints());
    origin = opt.candidates_path;
  } else {
    const std::vector<double> limits = ParseLimits(opt.limits);
    if (limits.size() != 1 && static_cast<int>(limits.size()) != nominal.NumJoints()) {
      throw InputError({"", 0, "--limits"}, "expected one limit or " + std::to_string(nominal.NumJoints()));
    }
    candidates = calib::SampleJointConfigurations(opt.sample, limits, nominal.NumJoints(), opt.plan.seed);
    origin = "uniform within +-" + opt.limits + " deg (seed " + std::to_string(opt.plan.seed) + ")";
  }
  if (opt.plan.num_poses > static_cast<int>(candidates.size())) {
    throw InputError({"", 0, "--poses"}, std::to_string(opt.plan.num_poses) + " poses asked from " +
                                             std::to_string(candidates.size()) + " candidates");
  }
  const std::string problem = opt.plan.Validate();
  if (!problem.empty()) {
    const OptionsProblem p = SplitOptionsProblem(problem);
    const std::map<std::string, std::string> flags = {
        {"num_poses", "--poses"},       {"num_targets", "--targets"},         {"position_sigma_mm", "--sigma"},
        {"rotation_sigma_deg", "--rotation-sigma"}, {"exchange_passes", "--exchange-passes"},
        {"random_draws", "--random-draws"}};
    const auto flag = flags.find(p.field);
    throw InputError({"", 0, flag != flags.end() ? flag->second : p.field}, p.message);
  }
  const calib::PosePlanner planner(nominal, candidates, opt.plan);
  calib::PosePlanningSummary summary;
  const std::vector<int> chosen = planner.Plan(&summary);

  std::vector<Eigen::VectorXd> joints;
  for (int i : chosen) joints.push_back(candidates[i]);
  const std::string comment = "poses planned by ramtk plan poses (D-optimal) for " + nominal.name + " from " + origin;
  for (const std::string& f : inputs) AddProvenanceFile(&provenance, f);
  std::vector<std::pair<std::string, std::string>> files = {{opt.out, calib::FormatJointCsv(joints, comment)}};
  StampOutputs(&files, provenance);  // and chosen.provenance.json beside it
  WriteFilesAtomically(files);

  std::printf("%d candidates, %s, %d identifiable unknowns; %d eliminated:\n", summary.num_candidates,
              opt.plan.six_d ? "6-D poses" : (std::to_string(opt.plan.num_targets) + " target(s)").c_str(),
              static_cast<int>(summary.names.size()), static_cast<int>(summary.eliminated.size()));
  for (const std::string& e : summary.eliminated) std::printf("  %s\n", e.c_str());
  std::printf("planned %d poses: %d greedy steps, %d exchanges in %d passes; random: %d of %d draws full rank\n",
              static_cast<int>(chosen.size()), summary.greedy_steps, summary.exchanges, summary.exchange_passes,
              summary.random_full_rank, opt.plan.random_draws);
  std::printf("predicted sigma (noise %.4g mm%s), planned vs random poses:\n", opt.plan.position_sigma_mm,
              opt.plan.six_d ? (", " + std::to_string(opt.plan.rotation_sigma_deg) + " deg").c_str() : "");
  std::printf("%s", summary.Table().c_str());
  std::printf("wrote %s (%d poses)\n", opt.out.c_str(), static_cast<int>(chosen.size()));
  return kExitOk;
}

}  // namespace

void RegisterPlanCommands(CLI::App& app, int* exit_code) {
  CLI::App* plan = GetOrAddSubcommand(app, "plan", "Planning of measurements");
  auto opt = std::make_shared<PlanPosesCommandOptions>();
  CLI::App* sub = plan->add_subcommand(
      "poses", "Choose the robot poses that determine the calibration's identifiable unknowns best (D-optimal)");
  sub->add_option("--robot", opt->robot_path, "Nominal robot file (YAML, any number of joints)")->required();
  auto* candidates = sub->add_option("--candidates", opt->candidates_path,
                                     "Candidate joint sets: a tracker file, or a CSV with q1..qN in degrees");
  sub->add_option("--format", opt->format_path, "Column description of the tracker file (YAML)")->needs(candidates);
  auto* sample = sub->add_option("--sample", opt->sample, "Sample this many candidates uniformly within --limits");
  sub->add_option("--limits", opt->limits, "Joint limits for --sample: +-deg, one value or one per joint")
      ->capture_default_str()
      ->needs(sample);
  candidates->excludes(sample);
  sub->add_option("--poses", opt->plan.num_poses, "Poses to choose")->required();
  sub->add_flag("--six-d", opt->plan.six_d, "The tracker measures the tool's 6-D pose (default: points)");
  sub->add_option("--targets", opt->plan.num_targets, "Points measured per pose")->capture_default_str();
  sub->add_option("--sigma", opt->plan.position_sigma_mm, "Noise per coordinate (mm)")->capture_default_str();
  sub->add_option("--rotation-sigma", opt->plan.rotation_sigma_deg, "Noise per rotation component (deg), 6-D")
      ->capture_default_str();
  sub->add_option("--exchange-passes", opt->plan.exchange_passes, "Exchange passes after the greedy choice")
      ->capture_default_str();
  sub->add_option("--random-draws", opt->plan.random_draws, "Random sets for the comparison")->capture_default_str();
  sub->add_option("--seed", opt->plan.seed, "Seed of the sampling and the random sets")->capture_default_str();
  sub->add_option("--out", opt->out, "Chosen joint sets: CSV pose,q1..qN (deg)")->required();
  sub->callback([opt, exit_code, candidates, sample, sub]() {
    if (candidates->count() == 0 && sample->count() == 0) {
      throw InputError({"", 0, "--candidates"}, "give --candidates FILE or --sample M");
    }
    *exit_code = RunPlanPoses(*opt, CommandProvenance(sub));
  });
}

}  // namespace ramtk::tools
