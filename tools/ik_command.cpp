// ramtk ik: joint angles that put the flange at a target pose (damped least squares from a seed).
#include <iostream>

#include "commands.h"
#include "pose_print.h"
#include "ramtk/core/log.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/inverse.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct IkCommandOptions {
  std::string robot_path;  // robot model YAML
  std::string pose;        // target x,y,z,A,B,C (mm, KUKA A,B,C in degrees)
  std::string joints;      // alternative target: the flange pose at these controller joints (deg)
  std::string seed = "0,0,0,0,0,0";  // start joints (deg)
  bool json = false;
};

std::string FormatJoints(const kinematics::JointVector& q) {
  std::string s;
  char buf[32];
  for (int i = 0; i < kinematics::kNumJoints; ++i) {
    std::snprintf(buf, sizeof(buf), "%s%.9f", i ? "," : "", RadToDeg(q[i]));
    s += buf;
  }
  return s;
}

int RunIk(const IkCommandOptions& opt) {
  using namespace kinematics;
  const RobotModel model = ReadRobotModel(opt.robot_path);
  if (opt.pose.empty() == opt.joints.empty()) {
    throw InputError({"", 0, "--pose/--joints"}, "give exactly one target: --pose x,y,z,A,B,C or --joints q1..q6");
  }
  Isometry3 target = Isometry3::Identity();
  if (!opt.pose.empty()) {
    const std::vector<double> p = ParseDoubleList(opt.pose, {"", 0, "--pose"}, 6);
    target.translation() = Vec3(p[0], p[1], p[2]);
    target.linear() = RotationFromKukaAbc({DegToRad(p[3]), DegToRad(p[4]), DegToRad(p[5])});
  } else {
    const std::vector<double> qd = ParseDoubleList(opt.joints, {"", 0, "--joints"}, kNumJoints);
    JointVector q;
    for (int i = 0; i < kNumJoints; ++i) q[i] = DegToRad(qd[i]);
    target = BaseFromFlange(model, q);
  }
  const std::vector<double> sd = ParseDoubleList(opt.seed, {"", 0, "--seed"}, kNumJoints);
  JointVector seed;
  for (int i = 0; i < kNumJoints; ++i) seed[i] = DegToRad(sd[i]);

  const InverseKinematicsSummary summary = SolveInverseKinematics(model, target, seed);
  const Isometry3 reached = BaseFromFlange(model, summary.q_controller);
  if (opt.json) {
    nlohmann::json j;
    j["robot"] = model.name;
    j["target"] = PoseToJson(target);
    j["converged"] = summary.Converged();
    j["joints_deg"] = nlohmann::json::array();
    for (int i = 0; i < kNumJoints; ++i) j["joints_deg"].push_back(RadToDeg(summary.q_controller[i]));
    j["iterations"] = summary.iterations;
    j["position_error_mm"] = summary.final_position_error_mm;
    j["rotation_error_deg"] = RadToDeg(summary.final_rotation_error_rad);
    j["report"] = summary.BriefReport();
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << "robot " << model.name << "\n" << FormatPose("target base_from_flange", target);
    std::cout << summary.BriefReport() << "\n";
    std::cout << "controller joints (deg) " << FormatJoints(summary.q_controller) << "\n";
    std::cout << FormatPose("reached base_from_flange", reached);
  }
  if (!summary.Converged()) {
    RAMTK_LOG(kError) << "target not reached: the closest pose found is " << summary.final_position_error_mm
                      << " mm and " << RadToDeg(summary.final_rotation_error_rad)
                      << " deg away (outside the workspace, or try another --seed)";
    return kExitNoSolution;
  }
  return kExitOk;
}

}  // namespace

void RegisterIkCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<IkCommandOptions>();
  CLI::App* sub = app.add_subcommand("ik", "Inverse kinematics: controller joints for a target flange pose");
  sub->add_option("--robot", opt->robot_path, "Robot model file (YAML, datasets/robots/)")->required();
  sub->add_option("--pose", opt->pose, "Target flange pose x,y,z,A,B,C (mm; KUKA A,B,C in degrees)");
  sub->add_option("--joints", opt->joints, "Target = flange pose at these controller joints (degrees)");
  sub->add_option("--seed", opt->seed, "Start joints q1,...,q6 in degrees")->capture_default_str();
  sub->add_flag("--json", opt->json, "Print JSON");
  sub->callback([opt, exit_code]() { *exit_code = RunIk(*opt); });
}

}  // namespace ramtk::tools
