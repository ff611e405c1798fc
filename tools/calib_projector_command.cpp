// ramtk calib projector and ramtk simulate projector-session: camera + projector calibration from
// a board captured under fringes (ramtk::calib_projector).

#include <cstdio>
#include <filesystem>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "ramtk/calib/projector/projector_session_calibration.h"
#include "ramtk/calib/projector/projector_session_sim.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/vision/projector/projector_calibration.h"

namespace ramtk::tools {

void RegisterCalibProjector(CLI::App* calib, CLI::App* simulate, int* exit_code);

namespace {

struct CalibProjectorOptions {
  std::string session;  // session folder or its session.json
  std::string board;    // board description or file; "" = the session's
  std::string out;      // projector calibration file (YAML, or JSON / XML)
  std::string summary;  // summary JSON; "" = <out without extension>_summary.json
  int half_window = 15;
  double outlier_factor = 3.0;
  double outlier_min_px = 0.25;
  bool quiet = false;
};

int RunCalibProjector(const CalibProjectorOptions& opt, Provenance provenance) {
  const calib::ProjectorSession session = calib::ReadProjectorSession(opt.session);
  if (opt.board.empty() && session.board.empty())
    throw InputError({session.path, 0, "board"}, "the session names no board; give --board");
  const calib::BoardSpec board = opt.board.empty() ? calib::ParseBoardSpec(session.board, {session.path, 0, "board"})
                                                   : calib::ReadBoardSpecArgument(opt.board);
  const std::string summary_path =
      !opt.summary.empty() ? opt.summary
                           : std::filesystem::path(opt.out).replace_extension("").string() + "_summary.json";
  CheckOutputsDistinct({{"--out", opt.out}, {"--summary", summary_path}});
  CheckOutputAgainstInputs(opt.out, {session.path}, "--out");
  CheckOutputAgainstInputs(summary_path, {session.path}, "--summary");
  calib::ProjectorSessionOptions o;
  o.corners.half_window_px = opt.half_window;
  o.calibration.outlier_factor = opt.outlier_factor;
  o.calibration.outlier_min_px = opt.outlier_min_px;
  ThrowIfInvalid(o.Validate(), "--half-window/--outlier-factor/--outlier-min-px");
  if (!opt.quiet) o.progress = ProgressPrinter("poses");
  calib::ProjectorSessionSummary summary;
  const calib::ProjectorSessionResult result = calib::CalibrateProjectorSession(session, board, o, &summary);
  AddProvenanceFile(&provenance, session.path);
  // The rig as `calib cameras` writes it (per-pose errors: camera then projector px per used pose).
  std::vector<std::pair<std::string, std::string>> files = {
      {opt.out, camera::StereoCalibrationText(result.stereo.rig, camera::CalibrationFormatOf(opt.out),
                                              "ramtk calib projector: camera = camera 1, projector = camera 2, R T = "
                                              "projector_from_camera (mm)")},
      {summary_path, calib::ProjectorSessionResultJson(result, board)}};
  StampOutputs(&files, provenance);
  WriteFilesAtomically(files);
  std::printf("%s\n", summary.BriefReport().c_str());
  const vision::ProjectorCalibration& c = result.calibration;
  std::printf("projector %dx%d: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.5f k2 %.5f\n", c.projector.width,
              c.projector.height, c.projector.fx, c.projector.fy, c.projector.cx, c.projector.cy,
              c.projector.distortion.k1, c.projector.distortion.k2);
  const Vec3 t = c.projector_from_camera.translation();
  std::printf("projector_from_camera T (mm) %.3f %.3f %.3f\n", t.x(), t.y(), t.z());
  for (const calib::ProjectorPoseReport& p : result.poses) {
    if (p.used) {
      std::printf(
          "  %s: %d corners, %d in the projector (median sigma %.3f px); RMS %.3f camera px, %.3f projector px\n",
          p.name.c_str(), p.camera_corners, p.projector_corners, p.median_corner_sigma_px, p.camera_rms_px,
          p.projector_rms_px);
    } else {
      std::printf("  %s: not used: %s\n", p.name.c_str(), p.reason.c_str());
    }
  }
  std::printf("wrote %s and %s\n", opt.out.c_str(), summary_path.c_str());
  return kExitOk;
}

struct SimulateProjectorSessionOptions {
  std::string out;
  std::string rig;        // projector calibration file giving camera, projector and projector_from_camera
  std::string board;      // board text; "" = the default 9x6 chessboard
  double distance = 0.0;  // board distance along the camera's image-centre ray (mm); 0 = the default
  int poses = 12;
  std::uint64_t seed = 1;
  int supersampling = 2;
  bool no_noise = false;
  bool force = false;
  bool quiet = false;
};

int RunSimulateProjectorSession(const SimulateProjectorSessionOptions& opt) {
  calib::ProjectorSessionSimOptions o = calib::ProjectorSessionSimOptions::Defaults();
  o.poses = opt.poses;
  o.seed = opt.seed;
  o.supersampling = opt.supersampling;
  o.sensor.noise = !opt.no_noise;
  if (!opt.board.empty()) o.board = calib::ReadBoardSpecArgument(opt.board);
  if (!opt.rig.empty()) {
    const vision::ProjectorCalibration rig = vision::ReadProjectorCalibration(opt.rig);
    o.camera = rig.camera;
    o.projector = rig.projector;
    o.projector_from_camera = rig.projector_from_camera;
  }
  if (!opt.rig.empty() || opt.distance > 0.0) o.AimAtImageCentre(opt.distance > 0.0 ? opt.distance : 500.0);
  const std::string bad = o.Validate();
  if (!bad.empty()) throw InputError({"", 0, "--poses/--supersampling"}, bad);
  ProgressCallback progress;
  if (!opt.quiet) progress = ProgressPrinter("poses");
  const calib::ProjectorSessionSimSummary summary = calib::SimulateProjectorSession(o, opt.out, opt.force, progress);
  std::printf("%s\n", summary.BriefReport().c_str());
  return kExitOk;
}

}  // namespace

void RegisterCalibProjector(CLI::App* calib, CLI::App* simulate, int* exit_code) {
  {
    auto opt = std::make_shared<CalibProjectorOptions>();
    CLI::App* sub = calib->add_subcommand(
        "projector", "Camera + projector calibration from a board captured under fringes in both directions");
    sub->add_option("--session", opt->session, "Session folder, or its session.json (docs/formats.md)")->required();
    sub->add_option("--board", opt->board,
                    "Board, e.g. chessboard:9x6:20 (or a file holding it); default: the session's \"board\"");
    sub->add_option("--out", opt->out,
                    "Projector calibration file (the projector as camera 2; `projector_calibration` of a scan "
                    "manifest): YAML, or JSON / XML when named so")
        ->required();
    sub->add_option("--summary", opt->summary, "Summary JSON; default <out>_summary.json");
    sub->add_option("--half-window", opt->half_window,
                    "Half side (camera px) of the window of each corner's local homography")
        ->capture_default_str();
    sub->add_option("--outlier-factor", opt->outlier_factor, "Reject a pose above this times the median pose RMS")
        ->capture_default_str();
    sub->add_option("--outlier-min-px", opt->outlier_min_px, "... and above this RMS (px)")->capture_default_str();
    sub->add_flag("-q,--quiet", opt->quiet, "No progress on stderr");
    sub->callback([opt, exit_code, sub]() { *exit_code = RunCalibProjector(*opt, CommandProvenance(sub)); });
  }
  {
    auto opt = std::make_shared<SimulateProjectorSessionOptions>();
    CLI::App* sub = simulate->add_subcommand(
        "projector-session",
        "Render a projector calibration session (a chessboard in N poses under fringes in both directions) with "
        "its truth");
    sub->add_option("--out", opt->out, "Output folder (must not exist, or be empty, unless --force)")->required();
    sub->add_option("--poses", opt->poses, "Board poses")->capture_default_str();
    sub->add_option("--rig", opt->rig,
                    "Camera, projector and projector_from_camera from this projector calibration file (e.g. the "
                    "projector_calibration.yml of `simulate fringe --monocular`); default: the built-in rig");
    sub->add_option("--board", opt->board, "Chessboard, e.g. chessboard:9x6:6 (default chessboard:9x6:20)");
    sub->add_option("--distance", opt->distance,
                    "Board distance (mm) along the ray of the camera's image centre; the poses' spread scales with "
                    "the field there (default 500 for the built-in rig and for --rig)");
    sub->add_option("--seed", opt->seed, "Seed of the poses and the sensor noise")->capture_default_str();
    sub->add_option("--supersampling", opt->supersampling, "n: n x n rays per camera pixel")->capture_default_str();
    sub->add_flag("--no-noise", opt->no_noise, "Render without shot and read noise");
    sub->add_flag("--force", opt->force, "Replace an existing output folder");
    sub->add_flag("-q,--quiet", opt->quiet, "No progress on stderr");
    sub->callback([opt, exit_code]() { *exit_code = RunSimulateProjectorSession(*opt); });
  }
}

}  // namespace ramtk::tools
