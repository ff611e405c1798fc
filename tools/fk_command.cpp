// ramtk fk: forward kinematics of a robot model at controller joint angles.
#include <iostream>

#include "commands.h"
#include "pose_print.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct FkCommandOptions {
  std::string robot_path;  // robot model YAML
  std::string joints;      // controller joints q1..q6, degrees
  std::string measured;    // optional measured flange position x,y,z, mm
  bool json = false;       // print JSON instead of text
};

int RunFk(const FkCommandOptions& opt) {
  using namespace kinematics;
  const RobotModel model = ReadRobotModel(opt.robot_path);
  const std::vector<double> q_deg = ParseDoubleList(opt.joints, {"", 0, "--joints"}, kNumJoints);
  JointVector q;
  for (int i = 0; i < kNumJoints; ++i) q[i] = DegToRad(q_deg[i]);
  const Isometry3 base_from_flange = BaseFromFlange(model, q);

  nlohmann::json j;
  j["robot"] = model.name;
  j["joints_deg"] = q_deg;
  j["base_from_flange"] = PoseToJson(base_from_flange);
  std::string text = "robot " + model.name + ", controller joints (deg) " + opt.joints + "\n" +
                     FormatPose("base_from_flange (flange in the base frame)", base_from_flange);
  if (!opt.measured.empty()) {
    const std::vector<double> m = ParseDoubleList(opt.measured, {"", 0, "--measured"}, 3);
    const Vec3 measured(m[0], m[1], m[2]);
    const Vec3 diff = measured - base_from_flange.translation();
    j["measured_position_mm"] = m;
    j["measured_minus_model_mm"] = {diff.x(), diff.y(), diff.z()};
    j["distance_mm"] = diff.norm();
    char buf[256];
    std::snprintf(buf, sizeof(buf), "  measured - model (mm) x %12.4f   y %12.4f   z %12.4f   |d| %.4f\n", diff.x(),
                  diff.y(), diff.z(), diff.norm());
    text += buf;
  }
  if (opt.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << text;
  }
  return kExitOk;
}

}  // namespace

void RegisterFkCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<FkCommandOptions>();
  CLI::App* sub = app.add_subcommand("fk", "Forward kinematics: flange pose at controller joint angles");
  sub->add_option("--robot", opt->robot_path, "Robot model file (YAML, datasets/robots/)")->required();
  sub->add_option("--joints", opt->joints, "Controller joint angles q1,...,q6 in degrees")->required();
  sub->add_option("--measured", opt->measured, "Measured flange position x,y,z in mm; prints measured - model");
  sub->add_flag("--json", opt->json, "Print JSON");
  sub->callback([opt, exit_code]() { *exit_code = RunFk(*opt); });
}

}  // namespace ramtk::tools
