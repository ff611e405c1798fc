// ramtk calib sensor-robot | calib cameras | simulate sensor-robot: thin wrappers over ramtk::calib.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "ramtk/calib/camera_calibration.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/calib/sensor_robot.h"
#include "ramtk/calib/sensor_robot_io.h"
#include "ramtk/calib/sensor_robot_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"
#include "ramtk/image/image_file.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct SensorRobotCommandOptions {
  std::string robot_path;         // robot model YAML
  std::string measurements_path;  // ball measurement CSV
  std::string output_path;        // result JSON
  std::string method = "manifold";
  std::string loss = "huber";
  double loss_scale_mm = 0.1;
  double penalty = 1e8;
  int min_poses = 5;
  int cycle = -1;           // only the rows of this cycle (-1: every row)
  bool unweighted = false;  // ignore the centre covariance columns
  double robot_noise_mm = 0.0;  // robot repeatability σ per axis added to every centre's covariance
};

int RunSensorRobot(const SensorRobotCommandOptions& opt) {
  CheckOutputAgainstInputs(opt.output_path, {opt.robot_path, opt.measurements_path}, "--output");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  kinematics::RobotMeasurementSet set = kinematics::ReadRobotMeasurements(opt.measurements_path);
  if (opt.cycle >= 0) {
    std::vector<kinematics::RobotMeasurement> rows;
    for (const auto& r : set.rows) {
      if (r.cycle == opt.cycle) rows.push_back(r);
    }
    if (rows.empty()) {
      throw InputError({opt.measurements_path, 0, "cycle"}, "no row of cycle " + std::to_string(opt.cycle) + " (--cycle)");
    }
    set.rows = rows;
  }
  const std::vector<calib::BallObservation> obs = calib::BallObservationsFromMeasurements(set, opt.measurements_path);
  calib::SensorRobotSummary summary;
  calib::SensorRobotCalibration result;
  try {
    if (opt.method == "thesis") {
      calib::ThesisCalibrationOptions o;
      o.penalty_factor = opt.penalty;
      o.checks.min_poses = opt.min_poses;
      result = calib::CalibrateSensorRobotThesis(model, obs, o, &summary);
    } else {
      calib::SensorRobotOptions o;
      o.loss = opt.loss == "none"     ? calib::RobustLoss::kNone
               : opt.loss == "cauchy" ? calib::RobustLoss::kCauchy
                                      : calib::RobustLoss::kHuber;
      o.loss_scale_mm = opt.loss_scale_mm;
      o.checks.min_poses = opt.min_poses;
      o.use_covariance = !opt.unweighted;
      o.robot_noise_mm = opt.robot_noise_mm;
      result = calib::CalibrateSensorRobot(model, obs, o, &summary);
    }
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({opt.measurements_path, 0, e.where().field}, e.message());
  }
  calib::WriteSensorRobotResult(opt.output_path, result, summary, obs);
  const Isometry3& t = result.sensor_from_base;
  const KukaAbc abc = KukaAbcFromRotation(t.linear());
  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf("sensor_from_base  t (mm) %12.4f %12.4f %12.4f   A,B,C (deg) %10.5f %10.5f %10.5f\n", t.translation().x(),
              t.translation().y(), t.translation().z(), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  std::printf("ball_in_flange      (mm) %12.4f %12.4f %12.4f\n", result.ball_in_flange.x(), result.ball_in_flange.y(),
              result.ball_in_flange.z());
  if (result.has_covariance) {
    const Vec3 sr = result.RotationStdArcsec(), st = result.TranslationStdMm(), sb = result.BallStdMm();
    std::printf("std: rotation (arcsec) %.2f %.2f %.2f  translation (mm) %.4f %.4f %.4f  ball (mm) %.4f %.4f %.4f\n",
                sr.x(), sr.y(), sr.z(), st.x(), st.y(), st.z(), sb.x(), sb.y(), sb.z());
  }
  for (const std::string& w : summary.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("wrote %s\n", opt.output_path.c_str());
  if (summary.termination != calib::SensorRobotTermination::kConverged) {
    // The result file is written for diagnosis, but it is not a solution: say so, exit 3.
    std::fprintf(stderr, "ramtk: error: the calibration did not converge (%s); %s holds the last iterate\n",
                 calib::TerminationName(summary.termination), opt.output_path.c_str());
    return kExitNoSolution;
  }
  return kExitOk;
}

struct SimulateSensorRobotOptions {
  std::string robot_path;
  std::string csv_path;
  std::string truth_path;
  int poses = 9;
  double center_noise_mm = 0.010;
  double repeatability_mm = 0.05;
  double max_tilt_deg = 35.0;
  std::uint64_t seed = 1;
  std::uint64_t noise_seed = 1;
};

int RunSimulateSensorRobot(const SimulateSensorRobotOptions& opt) {
  CheckOutputsDistinct({{"--output", opt.csv_path}, {"--truth", opt.truth_path}});
  CheckOutputAgainstInputs(opt.csv_path, {opt.robot_path}, "--output");
  CheckOutputAgainstInputs(opt.truth_path, {opt.robot_path}, "--truth");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  calib::SensorRobotSimOptions o;
  o.num_poses = opt.poses;
  o.center_noise_mm = opt.center_noise_mm;
  o.repeatability_mm = opt.repeatability_mm;
  o.max_tilt_deg = opt.max_tilt_deg;
  o.seed = opt.seed;
  o.noise_seed = opt.noise_seed;
  const calib::SensorRobotSimulation sim = calib::SimulateSensorRobot(model, o);
  const std::string truth = calib::SensorRobotTruthJson(sim, o);
  kinematics::WriteRobotMeasurements(calib::MeasurementsFromObservations(sim.observations), opt.csv_path);
  WriteFileAtomically(opt.truth_path, truth);
  std::printf("simulated %d poses (centre noise %.4f mm, repeatability %.4f mm); wrote %s and %s\n", opt.poses,
              opt.center_noise_mm, opt.repeatability_mm, opt.csv_path.c_str(), opt.truth_path.c_str());
  return kExitOk;
}

struct CamerasCommandOptions {
  std::string left;      // folder (or single image) of left-camera views
  std::string right;     // folder of right-camera views; empty → single camera
  std::string board;     // board description, e.g. chessboard:9x6:25
  std::string output;    // calibration YAML
  std::string coverage;  // PNG picture; default: output with _coverage.png
  double outlier_factor = 3.0;
  double outlier_min_px = 0.25;
  bool free_k3 = false;
};

std::vector<std::string> ListImages(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  if (!fs::is_directory(dir)) throw InputError({dir, 0, ""}, "not a folder of images");
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png" || ext == ".bmp" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff") {
      files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError({dir, 0, ""}, "no images (png, bmp, jpg, tif) in the folder");
  return files;
}

std::string ShortName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

int RunCameras(const CamerasCommandOptions& opt) {
  // --board is the description itself or a file holding it (first line that is not a comment).
  std::string board_text = opt.board;
  InputLocation board_where{"", 0, "--board"};
  if (std::filesystem::is_regular_file(opt.board)) {
    const std::string contents = ReadTextFile(opt.board);
    std::size_t start = 0;
    int line = 0;
    board_text.clear();
    while (start <= contents.size() && board_text.empty()) {
      const std::size_t end = std::min(contents.find('\n', start), contents.size());
      std::string l = contents.substr(start, end - start);
      ++line;
      l.erase(0, l.find_first_not_of(" \t\r"));
      l.erase(l.find_last_not_of(" \t\r") + 1);
      if (!l.empty() && l[0] != '#') {
        board_text = l;
        board_where = {opt.board, line, "board"};
      }
      start = end + 1;
    }
    if (board_text.empty()) throw InputError({opt.board, 0, "board"}, "no board description in the file");
  }
  const calib::BoardSpec board = calib::ParseBoardSpec(board_text, board_where);
  calib::CameraCalibrationOptions co;
  co.outlier_factor = opt.outlier_factor;
  co.outlier_min_px = opt.outlier_min_px;
  co.fix_k3 = !opt.free_k3;
  const std::string bad = co.Validate();
  if (!bad.empty()) throw InputError({"", 0, "--outlier-factor/--outlier-min-px"}, bad);
  const std::vector<std::string> left_files = ListImages(opt.left);
  cv::Size size;
  std::vector<calib::RejectedView> not_found;
  std::vector<calib::ViewPoints> left = calib::DetectBoardInImages(left_files, board, &size, &not_found);
  const std::string coverage_path =
      !opt.coverage.empty() ? opt.coverage
                            : std::filesystem::path(opt.output).replace_extension("").string() + "_coverage.png";
  calib::CameraCalibrationSummary summary;
  std::string yaml;
  cv::Mat picture;
  if (opt.right.empty()) {
    const calib::CameraCalibrationResult r = calib::CalibrateCamera(left, size, co, &summary);
    yaml = calib::CameraCalibrationYaml(r, board);
    picture = calib::DrawCoverage(r, left);
  } else {
    const std::vector<std::string> right_files = ListImages(opt.right);
    if (right_files.size() != left_files.size()) {
      throw InputError({opt.right, 0, "--right"}, std::to_string(right_files.size()) + " images, but " +
                                                      std::to_string(left_files.size()) + " in " + opt.left);
    }
    cv::Size right_size = size;
    std::vector<calib::ViewPoints> right = calib::DetectBoardInImages(right_files, board, &right_size, &not_found);
    const calib::StereoCalibrationResult st = calib::CalibrateStereo(left, right, size, co, &summary);
    yaml = calib::StereoCalibrationYaml(st, board);
    cv::hconcat(calib::DrawCoverage(st.left, left), calib::DrawCoverage(st.right, right), picture);
  }
  const std::vector<unsigned char> png = image::EncodePng(picture, coverage_path);
  WriteFileAtomically(opt.output, yaml);
  WriteFileAtomically(coverage_path, std::string(png.begin(), png.end()));
  std::printf("%s\n", summary.BriefReport().c_str());
  for (const calib::RejectedView& r : not_found)
    std::printf("skipped %s: %s\n", ShortName(r.name).c_str(), r.reason.c_str());
  for (const calib::RejectedView& r : summary.rejected) {
    std::printf("rejected %s: %s\n", r.name.c_str(), r.reason.c_str());
  }
  std::printf("wrote %s and %s\n", opt.output.c_str(), coverage_path.c_str());
  return kExitOk;
}

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
  bool no_refine = false;                // OpenCV's closed form only
  double sigma_deg = 0, sigma_mm = 0;    // measurement noise for the refinement (0: estimated)
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

void RegisterCalibCommands(CLI::App& app, int* exit_code) {
  CLI::App* calib = GetOrAddSubcommand(app, "calib", "Calibrations: sensor-to-robot, camera sessions");
  {
    auto opt = std::make_shared<SensorRobotCommandOptions>();
    CLI::App* sub = calib->add_subcommand(
        "sensor-robot", "sensor_from_base and ball_in_flange from ball centres measured at several robot poses");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--measurements", opt->measurements_path, "Ball measurement CSV (cycle,time_s,pose,q1..q6,x,y,z)")
        ->required();
    sub->add_option("--output", opt->output_path, "Result JSON")->required();
    sub->add_option("--method", opt->method, "manifold (closed form + Ceres on SO(3)) or thesis (eqs. 3-11..3-19)")
        ->check(CLI::IsMember({"manifold", "thesis"}));
    sub->add_option("--loss", opt->loss, "Robust loss of the manifold method: huber, cauchy or none")
        ->check(CLI::IsMember({"huber", "cauchy", "none"}));
    sub->add_option("--loss-scale", opt->loss_scale_mm, "Robust loss scale (mm)");
    sub->add_option("--penalty", opt->penalty, "Orthogonality penalty factor M of the thesis method (eq. 3-18)");
    sub->add_option("--min-poses", opt->min_poses, "Fewest poses accepted");
    sub->add_option("--cycle", opt->cycle, "Use only the rows of this cycle (e.g. 0, the cold cycle of a campaign)");
    sub->add_flag("--unweighted", opt->unweighted,
                  "Ignore the centre covariance columns cov_xx..cov_yz (default: the manifold method weights each "
                  "centre by its covariance when the file has them)");
    sub->add_option("--robot-noise", opt->robot_noise_mm,
                    "Robot repeatability sigma per axis (mm) added to every centre's covariance when weighting");
    sub->callback([opt, exit_code]() { *exit_code = RunSensorRobot(*opt); });
  }
  {
    auto opt = std::make_shared<CamerasCommandOptions>();
    CLI::App* sub = calib->add_subcommand("cameras", "Single or stereo camera calibration from board images");
    sub->add_option("--left", opt->left, "Folder of (left) camera images, sorted by name")->required();
    sub->add_option("--right", opt->right, "Folder of right camera images (same count and order); stereo if given");
    sub->add_option("--board", opt->board,
                    "Board: chessboard:9x6:25 | circles:7x5:25 | acircles:4x11:20 | charuco:10x7:25:18[:DICT_5X5_100] "
                    "(COLSxROWS, then mm), or a file holding that text")
        ->required();
    sub->add_option("--output", opt->output, "Calibration YAML (OpenCV FileStorage: K1 D1 [K2 D2 R T] image_size ...)")
        ->required();
    sub->add_option("--coverage", opt->coverage, "Coverage/residual picture (PNG); default <output>_coverage.png");
    sub->add_option("--outlier-factor", opt->outlier_factor, "Reject a view above this times the median view RMS");
    sub->add_option("--outlier-min-px", opt->outlier_min_px, "... and above this RMS (px)");
    sub->add_flag("--free-k3", opt->free_k3, "Estimate k3 too (default: k3 = 0)");
    sub->callback([opt, exit_code]() { *exit_code = RunCameras(*opt); });
  }
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
    CLI::App* sub = calib->add_subcommand(
        "hand-eye-flange", "Camera on the flange, board fixed: flange_from_camera from flange poses (OpenCV "
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
    auto opt = std::make_shared<SimulateSensorRobotOptions>();
    CLI::App* sub = simulate->add_subcommand(
        "sensor-robot", "Ball centres measured by a fixed sensor at N robot poses (truth: thesis eqs. 5-1, 5-2)");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--output", opt->csv_path, "Ball measurement CSV to write")->required();
    sub->add_option("--truth", opt->truth_path, "Truth JSON to write")->required();
    sub->add_option("--poses", opt->poses, "Number of poses");
    sub->add_option("--center-noise", opt->center_noise_mm, "Sphere-centre noise per axis (mm, 1 sigma)");
    sub->add_option("--repeatability", opt->repeatability_mm, "Robot repeatability ISO 9283 RP (mm)");
    sub->add_option("--max-tilt", opt->max_tilt_deg, "Largest flange tilt from the nominal orientation (deg)");
    sub->add_option("--seed", opt->seed, "Seed of the pose geometry");
    sub->add_option("--noise-seed", opt->noise_seed, "Seed of the noise");
    sub->callback([opt, exit_code]() { *exit_code = RunSimulateSensorRobot(*opt); });
  }
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
