// ramtk calib hand-eye | calib hand-eye-flange | simulate hand-eye: thin wrappers over ramtk::calib.

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/calib/hand_eye_images.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/natural_sort.h"
#include "ramtk/calib/sensor_robot_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {
namespace {

struct HandEyeCommandOptions {
  std::string robot_path;   // robot model, needed when the poses are joints
  std::string poses_path;   // pose CSV (joints or flange poses + camera_from_board)
  std::string images_dir;   // board images, one per flange pose (natural order)
  std::string board;        // board description or file, with --images
  std::string camera_path;  // camera calibration file, with --images
  std::string flange_poses_path;  // flange poses alone (CSV or one matrix per line)
  std::string output_path;  // result JSON
  std::string flange_units = "mm";
  std::string method;
  bool no_refine = false;              // OpenCV's closed form only
  double sigma_deg = 0, sigma_mm = 0;  // measurement noise for the refinement (0: estimated)
};

// The views of an --images run: the images used and those skipped, with the PnP figures.
struct ImageViews {
  std::vector<std::string> files;  // every image, natural order
  calib::HandEyeViews views;
};

std::string FileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// The observations from --poses (camera and flange poses in one file), --poses with
// --flange-poses, or --images with --board, --camera and --flange-poses.
std::vector<calib::FlangePoseObservation> ReadPoses(const HandEyeCommandOptions& opt, ImageViews* images) {
  std::unique_ptr<kinematics::RobotModel> model;
  if (!opt.robot_path.empty())
    model = std::make_unique<kinematics::RobotModel>(kinematics::ReadRobotModel(opt.robot_path));
  if (opt.images_dir.empty() == opt.poses_path.empty())
    throw InputError({"", 0, "--poses/--images"}, "give either --poses (camera_from_board per pose) or --images");
  if (!opt.images_dir.empty()) {
    if (opt.board.empty() || opt.camera_path.empty() || opt.flange_poses_path.empty())
      throw InputError({"", 0, "--images"}, "--images needs --board, --camera and --flange-poses");
    const calib::BoardSpec board = calib::ReadBoardSpecArgument(opt.board);
    const camera::CameraIntrinsics camera = camera::ReadCameraCalibration(opt.camera_path);
    const std::vector<Isometry3> flange = calib::ReadFlangePoses(opt.flange_poses_path, opt.flange_units, model.get());
    images->files = calib::ListBoardImages(opt.images_dir);
    SortNaturally(&images->files);
    if (images->files.size() != flange.size())
      throw InputError({opt.flange_poses_path, 0, "--flange-poses"},
                       std::to_string(flange.size()) + " flange poses, but " + std::to_string(images->files.size()) +
                           " images in " + opt.images_dir);
    images->views = calib::HandEyeViewsFromImages(images->files, board, camera, flange);
    return images->views.observations;
  }
  if (!opt.flange_poses_path.empty())
    return calib::ReadCameraPosesWithFlange(opt.poses_path,
                                            calib::ReadFlangePoses(opt.flange_poses_path, opt.flange_units, model.get()));
  return calib::ReadFlangePoseObservations(opt.poses_path, opt.flange_units, model.get());
}

// The inputs of a run for provenance: the pose files, the robot, the camera and the images.
std::vector<std::string> InputFiles(const HandEyeCommandOptions& opt, const ImageViews& images) {
  std::vector<std::string> files = {opt.poses_path, opt.robot_path, opt.flange_poses_path, opt.camera_path};
  files.insert(files.end(), images.files.begin(), images.files.end());
  return files;
}

// The result JSON with the images used and skipped (an --images run).
std::string WithImages(const std::string& json, const ImageViews& images) {
  if (images.files.empty()) return json;
  nlohmann::json j = nlohmann::json::parse(json);
  nlohmann::json used = nlohmann::json::array(), skipped = nlohmann::json::array();
  for (const std::string& n : images.views.names) used.push_back(FileName(n));
  for (const calib::RejectedView& r : images.views.poses.skipped)
    skipped.push_back({{"image", FileName(r.name)}, {"reason", r.reason}});
  j["images"] = {{"used", used},
                 {"skipped", skipped},
                 {"pnp_rms_px", images.views.poses.rms_px},
                 {"corner_sigma_px", images.views.poses.sigma_px}};
  return j.dump(2) + "\n";
}

void PrintImages(const ImageViews& images) {
  if (images.files.empty()) return;
  std::printf("%s\n", images.views.poses.BriefReport().c_str());
  for (const calib::RejectedView& r : images.views.poses.skipped)
    std::printf("skipped %s: %s\n", FileName(r.name).c_str(), r.reason.c_str());
}

calib::EyeInHandRefineOptions RefineOptions(const HandEyeCommandOptions& opt) {
  calib::EyeInHandRefineOptions ro;
  ro.sigma_deg = opt.sigma_deg, ro.sigma_mm = opt.sigma_mm;
  if (const std::string bad = ro.Validate(); !bad.empty()) throw InputError({"", 0, "--sigma-deg/--sigma-mm"}, bad);
  return ro;
}

// The solvers' InputErrors about the pose set name the pose file.
template <typename F>
auto NamingThePoseFile(const std::string& poses_path, F&& solve) {
  try {
    return solve();
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({poses_path, 0, e.where().field}, e.message());
  }
}

int RunHandEye(const HandEyeCommandOptions& opt, Provenance provenance) {
  CheckOutputAgainstInputs(opt.output_path, {opt.robot_path, opt.poses_path, opt.flange_poses_path, opt.camera_path},
                           "--output");
  ImageViews images;
  const std::vector<calib::StandCameraObservation> obs = ReadPoses(opt, &images);
  PrintImages(images);
  calib::HandEyeOptions o;
  o.method = opt.method == "li" ? calib::HandEyeMethod::kLi : calib::HandEyeMethod::kShah;
  o.refine = false;
  const calib::EyeInHandRefineOptions ro = RefineOptions(opt);
  calib::HandEyeSummary summary;
  calib::EyeInHandRefinement ref;
  const calib::HandEyeResult r = NamingThePoseFile(opt.poses_path, [&] {
    return opt.no_refine ? calib::CalibrateStandCamera(obs, o, &summary)
                         : calib::CalibrateStandCameraWithCovariance(obs, o, ro, &summary, &ref);
  });
  for (const std::string& f : InputFiles(opt, images)) AddProvenanceFile(&provenance, f);
  WriteFileAtomically(opt.output_path,
                      WithProvenance(WithImages(calib::HandEyeResultJson(r, summary, opt.no_refine ? nullptr : &ref),
                                                images),
                                     provenance));
  const KukaAbc abc = KukaAbcFromRotation(r.camera_from_base.linear());
  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf("camera_from_base  t (mm) %12.4f %12.4f %12.4f   A,B,C (deg) %10.5f %10.5f %10.5f\n",
              r.camera_from_base.translation().x(), r.camera_from_base.translation().y(),
              r.camera_from_base.translation().z(), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  if (!opt.no_refine) {
    std::printf(
        "sigma             t (mm) %12.4f %12.4f %12.4f   rotation (deg) %8.5f %8.5f %8.5f; noise %s %.4f deg, "
        "%.4f mm per axis\n",
        ref.translation_sigma_mm.x(), ref.translation_sigma_mm.y(), ref.translation_sigma_mm.z(),
        ref.rotation_sigma_deg.x(), ref.rotation_sigma_deg.y(), ref.rotation_sigma_deg.z(),
        ref.pose_covariance ? "per-image covariance; residual RMS"
                            : (ref.noise_estimated ? "estimated" : "given"),
        ref.sigma_deg, ref.sigma_mm);
    if (ref.pose_covariance)
      std::printf("variance factor %.3f (chi2 / dof of the weighted residuals); noise beyond the images' %.4f deg, "
                  "%.4f mm per axis\n",
                  ref.variance_factor, ref.extra_noise_deg, ref.extra_noise_mm);
  }
  std::printf("wrote %s\n", opt.output_path.c_str());
  return kExitOk;
}

int RunHandEyeFlange(const HandEyeCommandOptions& opt, Provenance provenance) {
  CheckOutputAgainstInputs(opt.output_path, {opt.robot_path, opt.poses_path, opt.flange_poses_path, opt.camera_path},
                           "--output");
  const calib::EyeInHandMethod method = calib::ParseEyeInHandMethod(opt.method, {"", 0, "--method"});
  ImageViews images;
  const std::vector<calib::FlangeCameraObservation> obs = ReadPoses(opt, &images);
  PrintImages(images);
  const calib::EyeInHandRefineOptions ro = RefineOptions(opt);
  calib::EyeInHandResult r =
      NamingThePoseFile(opt.poses_path, [&] { return calib::CalibrateCameraOnFlange(obs, method); });
  std::string json;
  std::string brief;
  if (opt.no_refine) {
    json = calib::EyeInHandResultJson(r, method);
    brief = calib::EyeInHandBriefReport(r, method);
  } else {
    calib::EyeInHandRefinement ref;
    r = calib::RefineCameraOnFlange(obs, r, ro, &ref);
    json = calib::EyeInHandResultJson(r, method, &ref);
    brief = calib::EyeInHandBriefReport(r, method, &ref);
  }
  for (const std::string& f : InputFiles(opt, images)) AddProvenanceFile(&provenance, f);
  WriteFileAtomically(opt.output_path, WithProvenance(WithImages(json, images), provenance));
  std::printf("%s\nwrote %s\n", brief.c_str(), opt.output_path.c_str());
  return kExitOk;
}

struct SimulateHandEyeOptions {
  std::string robot_path;
  std::string csv_path;
  std::string truth_path;
  std::string setup = "stand";       // stand: camera fixed, board on the flange; flange: camera on the flange
  std::string pose_form = "joints";  // joints, abc, quaternion, matrix
  std::string flange_units = "mm";
  int poses = 12;
  double rotation_noise_deg = 0.02;
  double translation_noise_mm = 0.1;
  unsigned seed = 1;
};

// Truth of the flange set-up: a camera 110 mm out on the flange, turned 14 deg; the board where
// the thesis sensor stands, facing the robot.
Isometry3 SimulatedFlangeFromCamera() {
  Isometry3 x = Isometry3::Identity();
  x.linear() = Eigen::AngleAxisd(DegToRad(14.0), Vec3(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  x.translation() = Vec3(45.0, -12.0, 110.0);
  return x;
}

int RunSimulateHandEye(const SimulateHandEyeOptions& opt, Provenance provenance) {
  CheckOutputAgainstInputs(opt.csv_path, {opt.robot_path}, "--output");
  CheckOutputAgainstInputs(opt.truth_path, {opt.robot_path, opt.csv_path}, "--truth");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  calib::SensorRobotSimOptions so;  // robot poses and camera (= the thesis sensor frame, eq. 5-1)
  so.num_poses = opt.poses;
  so.seed = opt.seed;
  const calib::SensorRobotSimulation sim = calib::SimulateSensorRobot(model, so);
  std::vector<kinematics::JointVector> joints;
  std::vector<Isometry3> flange;
  for (const calib::BallObservation& b : sim.observations) {
    joints.push_back(b.q_controller);
    flange.push_back(kinematics::BaseFromFlange(model, b.q_controller));
  }
  std::vector<calib::FlangePoseObservation> obs;
  std::string truth_json;
  if (opt.setup == "stand") {
    Isometry3 flange_from_board = Isometry3::Identity();
    flange_from_board.linear() = RotZ(DegToRad(30.0)) * RotX(DegToRad(10.0));
    flange_from_board.translation() = so.ball_in_flange;
    const auto board = calib::SimulateBoardPoses(model, joints, sim.sensor_from_base, flange_from_board,
                                                 opt.rotation_noise_deg, opt.translation_noise_mm, opt.seed);
    for (std::size_t i = 0; i < board.size(); ++i) obs.push_back({flange[i], board[i].camera_from_board});
    calib::HandEyeResult truth;
    truth.camera_from_base = sim.sensor_from_base;
    truth.flange_from_board = flange_from_board;
    calib::HandEyeSummary ts;
    ts.method = "truth";
    truth_json = calib::HandEyeResultJson(truth, ts);
  } else {
    calib::EyeInHandResult truth;
    truth.flange_from_camera = SimulatedFlangeFromCamera();
    truth.base_from_board = sim.sensor_from_base.inverse();
    obs = calib::SimulateFlangeCameraPoses(flange, truth.flange_from_camera, truth.base_from_board,
                                           opt.rotation_noise_deg, opt.translation_noise_mm, opt.seed);
    truth_json = calib::EyeInHandResultJson(truth, calib::EyeInHandMethod::kPark);
  }
  std::string csv;
  if (opt.pose_form == "joints") {
    std::vector<calib::BoardPoseObservation> rows;
    for (std::size_t i = 0; i < obs.size(); ++i) rows.push_back({joints[i], obs[i].camera_from_board});
    csv = calib::FormatBoardPoseObservations(rows);
  } else {
    const calib::FlangePoseForm form = opt.pose_form == "abc"          ? calib::FlangePoseForm::kKukaAbc
                                       : opt.pose_form == "quaternion" ? calib::FlangePoseForm::kQuaternion
                                                                       : calib::FlangePoseForm::kMatrix;
    csv = calib::FormatFlangePoseObservations(obs, form, opt.flange_units, "flange translation in " + opt.flange_units);
  }
  AddProvenanceFile(&provenance, opt.robot_path);
  std::vector<std::pair<std::string, std::string>> files = {{opt.csv_path, csv}, {opt.truth_path, truth_json}};
  StampOutputs(&files, provenance);
  for (const auto& [path, text] : files) WriteFileAtomically(path, text);
  std::printf("simulated %d %s poses (camera %s; noise %.4f deg, %.4f mm); wrote %s and %s\n", opt.poses,
              opt.pose_form.c_str(), opt.setup == "stand" ? "on a stand" : "on the flange", opt.rotation_noise_deg,
              opt.translation_noise_mm, opt.csv_path.c_str(), opt.truth_path.c_str());
  return kExitOk;
}

void AddPoseFileOptions(CLI::App* sub, HandEyeCommandOptions* opt) {
  sub->add_option("--poses", opt->poses_path,
                  "Pose CSV: x,y,z,a,b,c (camera_from_board, mm, KUKA deg) and the flange pose as q1..q6 (joints, "
                  "deg; needs --robot), flange_x..flange_c (KUKA deg), flange_x..z + flange_qw..qz, or "
                  "flange_m00..flange_m23; with --flange-poses only the camera columns (and cov_ij) are read");
  sub->add_option("--images", opt->images_dir,
                  "Folder of board images, one per flange pose in natural order (1, 2, 10): detection, PnP with each "
                  "view's covariance, then hand-eye; needs --board, --camera, --flange-poses");
  sub->add_option("--board", opt->board, "Board of --images: chessboard:9x6:25 | ... (as calib cameras), or a file");
  sub->add_option("--camera", opt->camera_path, "Camera calibration file of --images (K1 D1 image_size, YAML/JSON)");
  sub->add_option("--flange-poses", opt->flange_poses_path,
                  "Flange poses base_from_flange, one per image / --poses row: CSV with flange columns (or q1..q6 "
                  "with --robot), or one row-major 4x4 or 3x4 matrix per line (units: --flange-units)");
  sub->add_option("--robot", opt->robot_path, "Robot model file (YAML); needed when the poses are joints");
  sub->add_option("--flange-units", opt->flange_units, "Units of the flange translation: mm or m")
      ->check(CLI::IsMember({"mm", "m"}))
      ->capture_default_str();
  sub->add_option("--output", opt->output_path, "Result JSON")->required();
  sub->add_flag("--no-refine", opt->no_refine,
                "Keep OpenCV's closed form: no least-squares refinement on SE(3), no covariance");
  sub->add_option("--sigma-deg", opt->sigma_deg,
                  "Noise of one board pose, rotation per axis (deg), for the refinement's weights and "
                  "covariance; with --sigma-mm. Default: estimated from the residuals");
  sub->add_option("--sigma-mm", opt->sigma_mm, "Noise of one board pose, translation per axis (mm)");
}

// One hand-eye subcommand: the pose-file options, --method among `methods` (the first is the
// default), and `run` on the parsed options.
void AddHandEyeCommand(CLI::App* calib, const std::string& name, const std::string& description,
                       const std::vector<std::string>& methods, int (*run)(const HandEyeCommandOptions&, Provenance),
                       int* exit_code) {
  auto opt = std::make_shared<HandEyeCommandOptions>();
  opt->method = methods.front();
  CLI::App* sub = calib->add_subcommand(name, description);
  AddPoseFileOptions(sub, opt.get());
  std::string listed;
  for (const std::string& m : methods) listed += (listed.empty() ? "" : ", ") + m;
  sub->add_option("--method", opt->method, listed)->check(CLI::IsMember(methods))->capture_default_str();
  sub->callback([opt, run, exit_code, sub]() { *exit_code = run(*opt, CommandProvenance(sub)); });
}

}  // namespace

void RegisterCalibHandEye(CLI::App& app, CLI::App* calib, int* exit_code) {
  AddHandEyeCommand(calib, "hand-eye",
                    "Camera on a stand, board on the flange (AX = ZB): camera_from_base and flange_from_board with "
                    "their covariance (OpenCV calibrateRobotWorldHandEye + SE(3) least squares)",
                    {"shah", "li"}, RunHandEye, exit_code);
  AddHandEyeCommand(calib, "hand-eye-flange",
                    "Camera on the flange, board fixed (AX = XB): flange_from_camera with its covariance (OpenCV "
                    "calibrateHandEye + SE(3) least squares)",
                    {"park", "tsai", "horaud", "andreff", "daniilidis"}, RunHandEyeFlange, exit_code);
  CLI::App* simulate = SimulateCommand(app);
  {
    auto opt = std::make_shared<SimulateHandEyeOptions>();
    CLI::App* sub = simulate->add_subcommand(
        "hand-eye",
        "Board poses at N robot poses: a fixed camera (the thesis sensor frame) seeing a board on the "
        "flange, or a camera on the flange seeing a fixed board");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--output", opt->csv_path, "Pose CSV to write")->required();
    sub->add_option("--truth", opt->truth_path, "Truth JSON to write")->required();
    sub->add_option("--setup", opt->setup, "stand (camera fixed) or flange (camera on the flange)")
        ->check(CLI::IsMember({"stand", "flange"}))
        ->capture_default_str();
    sub->add_option("--pose-form", opt->pose_form,
                    "How the flange pose is written: joints (q1..q6), abc (KUKA A,B,C), quaternion or matrix")
        ->check(CLI::IsMember({"joints", "abc", "quaternion", "matrix"}))
        ->capture_default_str();
    sub->add_option("--flange-units", opt->flange_units, "Units of a written flange translation: mm or m")
        ->check(CLI::IsMember({"mm", "m"}))
        ->capture_default_str();
    sub->add_option("--poses", opt->poses, "Number of poses");
    sub->add_option("--rotation-noise", opt->rotation_noise_deg, "Board-pose rotation noise (deg, 1 sigma)");
    sub->add_option("--translation-noise", opt->translation_noise_mm, "Board-pose translation noise (mm per axis)");
    sub->add_option("--seed", opt->seed, "Seed of poses and noise");
    sub->callback([opt, exit_code, sub]() { *exit_code = RunSimulateHandEye(*opt, CommandProvenance(sub)); });
  }
}

}  // namespace ramtk::tools
