// ramtk calib cameras: single or stereo camera calibration from board images (ramtk::calib).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/calib/board_pose.h"
#include "ramtk/calib/camera_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/natural_sort.h"
#include "ramtk/core/outputs.h"
#include "ramtk/image/image_file.h"

namespace ramtk::tools {
namespace {

struct CamerasCommandOptions {
  std::string left;      // folder (or single image) of left-camera views
  std::string right;     // folder of right-camera views; empty → single camera
  std::string board;     // board description, e.g. chessboard:9x6:25
  std::string output;    // calibration YAML
  std::string coverage;  // PNG picture; default: output with _coverage.png
  double outlier_factor = 3.0;
  double outlier_min_px = 0.25;
  bool free_k3 = false;
  std::string model = "pinhole5";  // lens model: pinhole5, rational, thin-prism, fisheye
  std::string corners = "subpix";  // chessboards: subpix, sector or auto
  std::string poses_out;           // board poses with covariance (CSV); empty: none
};

// The board-pose file of --poses-out: the (left) camera's used views, named by file.
// `pose` is the image's number in the folder's natural order (1, 2, 10): the flange pose it pairs with.
std::string BoardPosesCsv(const calib::CameraCalibrationResult& r, const std::vector<calib::ViewPoints>& views,
                          const calib::CameraCalibrationOptions& co, std::vector<std::string> files) {
  SortNaturally(&files);
  std::vector<calib::BoardPoseEstimate> poses = calib::BoardPosesFromCalibration(r, views, co);
  for (calib::BoardPoseEstimate& p : poses) {
    p.pose = static_cast<int>(std::find(files.begin(), files.end(), p.name) - files.begin()) + 1;
    p.name = std::filesystem::path(p.name).filename().string();
  }
  return calib::FormatBoardPoseEstimates(
      poses, "camera_from_board per used view (x,y,z mm; KUKA a,b,c deg) with its covariance cov_ij in\n"
             "[rotation vector (deg, applied on the left, camera frame); translation (mm)] from the calibration's "
             "Jacobian");
}

std::string ShortName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

int RunCameras(const CamerasCommandOptions& opt, const Provenance& provenance) {
  const calib::BoardSpec board = calib::ReadBoardSpecArgument(opt.board);
  calib::CameraCalibrationOptions co;
  co.outlier_factor = opt.outlier_factor;
  co.outlier_min_px = opt.outlier_min_px;
  co.model = calib::ParseCalibrationModel(opt.model, {"", 0, "--model"});
  // k3 = 0 is the 5-coefficient model's default; the other models estimate all their coefficients.
  co.fix_k3 = !opt.free_k3 && co.model == calib::CalibrationModel::kPinhole5;
  const std::string bad = co.Validate();
  if (!bad.empty()) throw InputError({"", 0, "--outlier-factor/--outlier-min-px"}, bad);
  const calib::CornerChoice choice = calib::ParseCornerChoice(opt.corners, {"", 0, "--corners"});
  // Chessboards: both corner sets come from one detection and both are calibrated (reported side
  // by side); other boards have one set.
  const bool compare = board.type == calib::BoardType::kChessboard;
  const std::vector<std::string> left_files = calib::ListBoardImages(opt.left);
  cv::Size size;
  std::vector<calib::RejectedView> not_found;
  std::vector<calib::ViewPoints> left_sector, right_sector;
  std::vector<calib::ViewPoints> left =
      calib::DetectBoardInImages(left_files, board, &size, &not_found, {}, compare ? &left_sector : nullptr);
  const std::string coverage_path =
      !opt.coverage.empty() ? opt.coverage
                            : std::filesystem::path(opt.output).replace_extension("").string() + "_coverage.png";
  calib::CameraCalibrationSummary summary;
  calib::CornerComparison corners;
  std::string yaml, poses_csv;
  cv::Mat picture;
  auto kept = [&](const std::vector<calib::ViewPoints>& subpix, const std::vector<calib::ViewPoints>& sector) {
    return compare && corners.chosen == calib::CornerRefinement::kSectorBased ? sector : subpix;
  };
  if (opt.right.empty()) {
    const calib::CameraCalibrationResult r =
        compare ? calib::CalibrateCameraComparingCorners(left, left_sector, size, co, choice, &summary, &corners)
                : calib::CalibrateCamera(left, size, co, &summary);
    yaml =
        calib::CameraCalibrationYaml(r, board, compare ? &corners : nullptr, camera::CalibrationFormatOf(opt.output));
    picture = calib::DrawCoverage(r, kept(left, left_sector));
    if (!opt.poses_out.empty()) poses_csv = BoardPosesCsv(r, kept(left, left_sector), co, left_files);
  } else {
    const std::vector<std::string> right_files = calib::ListBoardImages(opt.right);
    if (right_files.size() != left_files.size()) {
      throw InputError({opt.right, 0, "--right"}, std::to_string(right_files.size()) + " images, but " +
                                                      std::to_string(left_files.size()) + " in " + opt.left);
    }
    cv::Size right_size = size;
    std::vector<calib::ViewPoints> right =
        calib::DetectBoardInImages(right_files, board, &right_size, &not_found, {}, compare ? &right_sector : nullptr);
    const calib::StereoCalibrationResult st =
        compare ? calib::CalibrateStereoComparingCorners(left, right, left_sector, right_sector, size, co, choice,
                                                         &summary, &corners)
                : calib::CalibrateStereo(left, right, size, co, &summary);
    yaml =
        calib::StereoCalibrationYaml(st, board, compare ? &corners : nullptr, camera::CalibrationFormatOf(opt.output));
    if (!opt.poses_out.empty()) poses_csv = BoardPosesCsv(st.left, kept(left, left_sector), co, left_files);
    cv::hconcat(calib::DrawCoverage(st.left, kept(left, left_sector)),
                calib::DrawCoverage(st.right, kept(right, right_sector)), picture);
  }
  const std::vector<unsigned char> png = image::EncodePng(picture, coverage_path);
  WriteFileAtomically(opt.output, yaml);
  WriteProvenanceSidecar(opt.output, provenance);  // the YAML is OpenCV's FileStorage: the block goes beside it
  WriteFileAtomically(coverage_path, std::string(png.begin(), png.end()));
  if (!opt.poses_out.empty()) WriteFileAtomically(opt.poses_out, poses_csv);
  std::printf("%s\n", summary.BriefReport().c_str());
  if (compare) std::printf("%s\n", corners.BriefReport().c_str());
  for (const calib::RejectedView& r : not_found)
    std::printf("skipped %s: %s\n", ShortName(r.name).c_str(), r.reason.c_str());
  for (const calib::RejectedView& r : summary.rejected) {
    std::printf("rejected %s: %s\n", r.name.c_str(), r.reason.c_str());
  }
  std::printf("wrote %s and %s\n", opt.output.c_str(), coverage_path.c_str());
  if (!opt.poses_out.empty()) std::printf("wrote %s (board poses with covariance)\n", opt.poses_out.c_str());
  return kExitOk;
}

}  // namespace

void RegisterCalibCameras(CLI::App* calib, int* exit_code) {
  {
    auto opt = std::make_shared<CamerasCommandOptions>();
    CLI::App* sub = calib->add_subcommand("cameras", "Single or stereo camera calibration from board images");
    sub->add_option("--left", opt->left, "Folder of (left) camera images, sorted by name")->required();
    sub->add_option("--right", opt->right, "Folder of right camera images (same count and order); stereo if given");
    sub->add_option("--board", opt->board,
                    "Board: chessboard:9x6:25 | circles:7x5:25 | acircles:4x11:20 | charuco:10x7:25:18[:DICT_5X5_100] "
                    "(COLSxROWS, then mm), or a file holding that text")
        ->required();
    sub->add_option("--output", opt->output,
                    "Calibration file (OpenCV FileStorage: K1 D1 [K2 D2 R T] image_size ...): YAML, or JSON / XML "
                    "when named .json / .xml")
        ->required();
    sub->add_option("--coverage", opt->coverage, "Coverage/residual picture (PNG); default <output>_coverage.png");
    sub->add_option("--outlier-factor", opt->outlier_factor, "Reject a view above this times the median view RMS");
    sub->add_option("--outlier-min-px", opt->outlier_min_px, "... and above this RMS (px)");
    sub->add_flag("--free-k3", opt->free_k3, "Estimate k3 too (pinhole5; default: k3 = 0)");
    sub->add_option("--model", opt->model,
                    "Lens model: pinhole5 (k1 k2 p1 p2 [k3]), rational (8 coefficients), thin-prism (12) or fisheye "
                    "(cv::fisheye, k1..k4)")
        ->check(CLI::IsMember({"pinhole5", "rational", "thin-prism", "fisheye"}))
        ->capture_default_str();
    sub->add_option("--corners", opt->corners,
                    "Chessboard corners to calibrate from: subpix (refined, unbiased on rendered boards), sector "
                    "(findChessboardCornersSB's accurate corners) or auto (the lower RMS). Both are calibrated and "
                    "reported either way")
        ->check(CLI::IsMember({"subpix", "sector", "auto"}))
        ->capture_default_str();
    sub->add_option("--poses-out", opt->poses_out,
                    "Board poses CSV: each used view's camera_from_board (of the left camera) with its 6x6 "
                    "covariance, the camera columns of the hand-eye pose files (calib hand-eye --poses with "
                    "--flange-poses)");
    sub->callback([opt, exit_code, sub]() { *exit_code = RunCameras(*opt, CommandProvenance(sub)); });
  }
}

}  // namespace ramtk::tools
