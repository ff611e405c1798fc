// Shared inputs of the `ramtk thermal` subcommands (thermal_inputs.h).
#include "thermal_inputs.h"

#include <cstdio>
#include <iostream>

#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/parse.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {

using namespace thermal;

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

void AddInputs(CLI::App* sub, ExperimentInputs* in, bool monitoring_required) {
  sub->add_option("--robot", in->robot_path, "Robot model file (YAML)")->required();
  sub->add_option("--setup", in->setup_path, "Thermal setup (JSON: sensor_from_base, ball_in_flange_mm, ...)")
      ->required();
  sub->add_option("--ball", in->ball_path, "Ball measurements CSV (cycle,time_s,pose,q1..q6,x,y,z)")->required();
  auto* m = sub->add_option("--monitoring", in->monitoring_path,
                            "Monitoring-point CSV (cycle,time_s,point,q1..q6,x,y,z in the tool-sensor frame)");
  if (monitoring_required) m->required();
  sub->add_option("--reference-cycle", in->reference_cycle, "Cold reference cycle number (default 0)");
  sub->add_option("--joint-tolerance-deg", in->joint_tolerance_deg,
                  "Largest joint difference of a pose between cycles (deg, default 0.01)");
  sub->add_flag("--unweighted", in->unweighted,
                "Ignore the ball file's centre covariance columns (default: weight each centre by its covariance)");
  sub->add_option(
      "--robot-noise", in->robot_noise_mm,
      "Robot repeatability sigma per axis (mm) added to every centre's covariance when weighting (default 0)");
}

void AddGuardOptions(CLI::App* sub, ExperimentInputs* in) {
  sub->add_option("--max-condition", in->max_condition,
                  "Identifiability guard: largest condition number of the identification matrix with every column "
                  "scaled to unit norm")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1e300));
  sub->add_flag("--reduce", in->reduce,
                "When the parameters are not identifiable from these poses, drop one parameter of each unobservable "
                "combination and identify the rest (default: refuse, exit 3)");
}

void CheckOutputs(const ExperimentInputs& in, const std::vector<std::pair<std::string, std::string>>& outputs,
                  const std::vector<std::string>& more_inputs) {
  std::vector<std::string> inputs = {in.robot_path, in.setup_path, in.ball_path, in.monitoring_path};
  inputs.insert(inputs.end(), more_inputs.begin(), more_inputs.end());
  for (const auto& [field, path] : outputs) CheckOutputAgainstInputs(path, inputs, field);
  CheckOutputsDistinct(outputs);
}

LoadedExperiment Load(const ExperimentInputs& in) {
  LoadedExperiment e;
  e.model = kinematics::ReadRobotModel(in.robot_path);
  e.setup = ReadThermalSetup(in.setup_path);
  CycleOptions co;
  co.reference_cycle = in.reference_cycle;
  co.joint_tolerance_deg = in.joint_tolerance_deg;
  const kinematics::RobotMeasurementSet ball = kinematics::ReadRobotMeasurements(in.ball_path);
  if (ball.kind != kinematics::MeasurementKind::kBall)
    throw InputError({in.ball_path, 1, "pose"},
                     "not a ball file: expected a 'pose' column (this one has 'point': "
                     "a monitoring file?)");
  e.ball = GroupCycles(ball, in.ball_path, co);
  if (!in.monitoring_path.empty()) {
    const kinematics::RobotMeasurementSet mon = kinematics::ReadRobotMeasurements(in.monitoring_path);
    if (mon.kind != kinematics::MeasurementKind::kMonitoring)
      throw InputError({in.monitoring_path, 1, "point"},
                       "not a monitoring file: expected a 'point' column (this one "
                       "has 'pose': a ball file?)");
    e.monitoring = GroupCycles(mon, in.monitoring_path, co);
    e.has_monitoring = true;
  }
  return e;
}

std::vector<std::vector<Mat3>> Weights(const ExperimentInputs& in, const LoadedExperiment& e) {
  ThrowIfInvalid(CheckNoise("--robot-noise", in.robot_noise_mm, kMaxNoiseMm, "mm"), "--robot-noise");
  return in.unweighted ? std::vector<std::vector<Mat3>>{} : e.ball.DifferenceCovariances(in.robot_noise_mm);
}

IdentificationOptions MakeIdOptions(const ExperimentInputs& in, const LoadedExperiment& e, const DriftModel& dm,
                                    const std::vector<int>& params) {
  IdentificationOptions id;
  id.params = params;
  id.difference_covariance_mm2 = Weights(in, e);
  if (!in.poses.empty()) {
    for (double p : ParseDoubleList(in.poses, {"", 0, "--poses"})) {
      const int k = static_cast<int>(p);
      if (k != p || k < 0 || k >= e.ball.NumPoses()) {
        throw InputError({"", 0, "--poses"},
                         "pose positions are integers in 0.." + std::to_string(e.ball.NumPoses() - 1));
      }
      id.poses.push_back(k);
    }
  } else if (in.pose_budget < 0) {
    throw InputError({"", 0, "--pose-budget"}, "must be a number of poses >= 1 (0 or absent: every pose)");
  } else if (in.pose_budget > 0) {
    id.poses = SelectPoses(dm, params, in.pose_budget);
  }
  return id;
}

bool GuardIdentification(const ExperimentInputs& in, const DriftModel& dm, IdentificationOptions* id,
                         IdentifiabilitySummary* summary) {
  IdentifiabilityOptions go;
  go.max_condition = in.max_condition;
  go.reduce = in.reduce;
  const IdentifiabilitySummary g = CheckIdentifiability(dm, id->params, id->poses, go);
  if (summary != nullptr) *summary = g;
  std::cout << g.BriefReport() << "\n";
  if (!g.Identifiable()) {
    std::cerr << "ramtk: error: " << ParamListToString(g.params) << " " << g.message
              << " (condition number " << Fmt("%.3g", g.condition_number) << " > " << Fmt("%.3g", g.max_condition)
              << "; --reduce drops them); nothing written\n";
    return false;
  }
  id->params = g.params;
  return true;
}

std::string ValueWithSigma(int p, double value, double sigma) {
  const char* f = kinematics::IsAngleParam(p) ? "%.6f" : "%.5f";
  return Fmt(f, ToFileUnits(p, value)) + " ± " + Fmt(f, SigmaToFileUnits(p, sigma));
}

std::vector<int> PoseIds(const LoadedExperiment& e, const IdentificationOptions& id) {
  std::vector<int> out;
  for (int p : id.poses) out.push_back(e.ball.ids[p]);
  return out;
}

std::string IntList(const std::vector<int>& v) {
  std::string s;
  for (int x : v) s += (s.empty() ? "" : ",") + std::to_string(x);
  return s;
}

}  // namespace ramtk::tools
