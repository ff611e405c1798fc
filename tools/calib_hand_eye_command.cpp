// ramtk calib hand-eye | calib hand-eye-flange | simulate hand-eye: thin wrappers over ramtk::calib.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/calib/sensor_robot_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct HandEyeCommandOptions {
  std::string robot_path;
  std::string poses_path;   // board-pose CSV
  std::string output_path;  // result JSON
  std::string method = "shah";
  bool no_refine = false;
};

int RunHandEye(const HandEyeCommandOptions& opt) {
  CheckOutputAgainstInputs(opt.output_path, {opt.robot_path, opt.poses_path}, "--output");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  const std::vector<calib::BoardPoseObservation> obs = calib::ReadBoardPoseObservations(opt.poses_path);
  calib::HandEyeOptions o;
  o.method = opt.method == "li" ? calib::HandEyeMethod::kLi : calib::HandEyeMethod::kShah;
  o.refine = !opt.no_refine;
  calib::HandEyeSummary summary;
  calib::HandEyeResult r;
  try {
    r = calib::CalibrateCameraToRobot(model, obs, o, &summary);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({opt.poses_path, 0, e.where().field}, e.message());
  }
  WriteFileAtomically(opt.output_path, calib::HandEyeResultJson(r, summary));
  const KukaAbc abc = KukaAbcFromRotation(r.camera_from_base.linear());
  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf("camera_from_base  t (mm) %12.4f %12.4f %12.4f   A,B,C (deg) %10.5f %10.5f %10.5f\n",
              r.camera_from_base.translation().x(), r.camera_from_base.translation().y(),
              r.camera_from_base.translation().z(), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  std::printf("wrote %s\n", opt.output_path.c_str());
  return kExitOk;
}

struct HandEyeFlangeCommandOptions {
  std::string poses_path;   // flange-camera CSV
  std::string output_path;  // result JSON
  std::string flange_units = "mm";
  std::string method = "park";
  bool no_refine = false;              // OpenCV's closed form only
  double sigma_deg = 0, sigma_mm = 0;  // measurement noise for the refinement (0: estimated)
};

int RunHandEyeFlange(const HandEyeFlangeCommandOptions& opt) {
  CheckOutputAgainstInputs(opt.output_path, {opt.poses_path}, "--output");
  const calib::EyeInHandMethod method = calib::ParseEyeInHandMethod(opt.method, {"", 0, "--method"});
  const auto obs = calib::ReadFlangeCameraObservations(opt.poses_path, opt.flange_units);
  calib::EyeInHandResult r;
  try {
    r = calib::CalibrateCameraOnFlange(obs, method);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({opt.poses_path, 0, e.where().field}, e.message());
  }
  std::string json;
  std::string brief;
  if (opt.no_refine) {
    json = calib::EyeInHandResultJson(r, method);
    brief = calib::EyeInHandBriefReport(r, method);
  } else {
    calib::EyeInHandRefineOptions ro;
    ro.sigma_deg = opt.sigma_deg, ro.sigma_mm = opt.sigma_mm;
    if (const std::string bad = ro.Validate(); !bad.empty()) throw InputError({"", 0, "--sigma-deg/--sigma-mm"}, bad);
    calib::EyeInHandRefinement ref;
    r = calib::RefineCameraOnFlange(obs, r, ro, &ref);
    json = calib::EyeInHandResultJson(r, method, &ref);
    brief = calib::EyeInHandBriefReport(r, method, &ref);
  }
  WriteFileAtomically(opt.output_path, json);
  std::printf("%s\nwrote %s\n", brief.c_str(), opt.output_path.c_str());
  return kExitOk;
}

struct SimulateHandEyeOptions {
  std::string robot_path;
  std::string csv_path;
  std::string truth_path;
  int poses = 12;
  double rotation_noise_deg = 0.02;
  double translation_noise_mm = 0.1;
  unsigned seed = 1;
};

int RunSimulateHandEye(const SimulateHandEyeOptions& opt) {
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  calib::SensorRobotSimOptions so;  // robot poses and camera (= the thesis sensor frame, eq. 5-1)
  so.num_poses = opt.poses;
  so.seed = opt.seed;
  const calib::SensorRobotSimulation sim = calib::SimulateSensorRobot(model, so);
  Isometry3 flange_from_board = Isometry3::Identity();
  flange_from_board.linear() = RotZ(DegToRad(30.0)) * RotX(DegToRad(10.0));
  flange_from_board.translation() = so.ball_in_flange;
  std::vector<kinematics::JointVector> joints;
  for (const calib::BallObservation& b : sim.observations) joints.push_back(b.q_controller);
  const std::vector<calib::BoardPoseObservation> obs =
      calib::SimulateBoardPoses(model, joints, sim.sensor_from_base, flange_from_board, opt.rotation_noise_deg,
                                opt.translation_noise_mm, opt.seed);
  calib::HandEyeResult truth;
  truth.camera_from_base = sim.sensor_from_base;
  truth.flange_from_board = flange_from_board;
  calib::HandEyeSummary ts;
  ts.method = "truth";
  WriteFileAtomically(opt.csv_path, calib::FormatBoardPoseObservations(obs));
  WriteFileAtomically(opt.truth_path, calib::HandEyeResultJson(truth, ts));
  std::printf("simulated %d board poses (noise %.4f deg, %.4f mm); wrote %s and %s\n", opt.poses,
              opt.rotation_noise_deg, opt.translation_noise_mm, opt.csv_path.c_str(), opt.truth_path.c_str());
  return kExitOk;
}

}  // namespace

void RegisterCalibHandEye(CLI::App& app, CLI::App* calib, int* exit_code) {
  {
    auto opt = std::make_shared<HandEyeCommandOptions>();
    CLI::App* sub =
        calib->add_subcommand("hand-eye",
                              "Camera on a stand, board on the flange: camera_from_base and flange_from_board (OpenCV "
                              "calibrateRobotWorldHandEye + Ceres refinement)");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--poses", opt->poses_path, "Board-pose CSV: pose,q1..q6 (deg),x,y,z (mm),a,b,c (KUKA deg)")
        ->required();
    sub->add_option("--output", opt->output_path, "Result JSON")->required();
    sub->add_option("--method", opt->method, "shah or li")->check(CLI::IsMember({"shah", "li"}));
    sub->add_flag("--no-refine", opt->no_refine, "Keep OpenCV's closed form (no Ceres refinement)");
    sub->callback([opt, exit_code]() { *exit_code = RunHandEye(*opt); });
  }
  {
    auto opt = std::make_shared<HandEyeFlangeCommandOptions>();
    CLI::App* sub =
        calib->add_subcommand("hand-eye-flange",
                              "Camera on the flange, board fixed: flange_from_camera from flange poses (OpenCV "
                              "calibrateHandEye, AX = XB)");
    sub->add_option("--poses", opt->poses_path,
                    "CSV: x,y,z,a,b,c (camera_from_board, mm, KUKA deg) and the flange pose as "
                    "flange_x..flange_c (KUKA deg), flange_x..z + flange_qw..qz, or flange_m00..flange_m23")
        ->required();
    sub->add_option("--flange-units", opt->flange_units, "Units of the flange translation: mm or m")
        ->check(CLI::IsMember({"mm", "m"}))
        ->capture_default_str();
    sub->add_option("--output", opt->output_path, "Result JSON")->required();
    sub->add_option("--method", opt->method, "tsai, park, horaud, andreff or daniilidis")
        ->check(CLI::IsMember({"tsai", "park", "horaud", "andreff", "daniilidis"}))
        ->capture_default_str();
    sub->add_flag("--no-refine", opt->no_refine,
                  "Keep OpenCV's closed form: no least-squares refinement on SE(3), no covariance");
    sub->add_option("--sigma-deg", opt->sigma_deg,
                    "Noise of one board pose, rotation per axis (deg), for the refinement's weights and "
                    "covariance; with --sigma-mm. Default: estimated from the residuals");
    sub->add_option("--sigma-mm", opt->sigma_mm, "Noise of one board pose, translation per axis (mm)");
    sub->callback([opt, exit_code]() { *exit_code = RunHandEyeFlange(*opt); });
  }
  CLI::App* simulate = SimulateCommand(app);
  {
    auto opt = std::make_shared<SimulateHandEyeOptions>();
    CLI::App* sub = simulate->add_subcommand(
        "hand-eye", "Board poses seen by a fixed camera (the thesis sensor frame) at N robot poses");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--output", opt->csv_path, "Board-pose CSV to write")->required();
    sub->add_option("--truth", opt->truth_path, "Truth JSON to write")->required();
    sub->add_option("--poses", opt->poses, "Number of poses");
    sub->add_option("--rotation-noise", opt->rotation_noise_deg, "Board-pose rotation noise (deg, 1 sigma)");
    sub->add_option("--translation-noise", opt->translation_noise_mm, "Board-pose translation noise (mm per axis)");
    sub->add_option("--seed", opt->seed, "Seed of poses and noise");
    sub->callback([opt, exit_code]() { *exit_code = RunSimulateHandEye(*opt); });
  }
}

}  // namespace ramtk::tools
