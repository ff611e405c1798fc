// Writes a rendered hand-eye session for the `ramtk calib hand-eye[-flange] --images` tests:
//   render_hand_eye_session <out_dir> <flange|stand> <count> <seed>
// → <out_dir>/images/view_1.png … view_<count>.png (unpadded: natural order matters) plus one
// blank image (no board) at the middle pose, <out_dir>/flange_poses.txt (one row-major 4×4
// base_from_flange per line, metres), <out_dir>/camera.yml (the truth camera). Truth: camera on
// the flange, flange_from_camera t = (45, -12, 110) mm; camera on a stand, camera_from_base
// t = (-300, 150, 1800) mm.
#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "camera_test_util.h"
#include "ramtk/camera/stereo_calibration.h"

namespace {

ramtk::Isometry3 Pose(const ramtk::Vec3& t, const ramtk::Vec3& axis, double deg) {
  ramtk::Isometry3 p = ramtk::Isometry3::Identity();
  p.linear() = Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  p.translation() = t;
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ramtk::calib;
  if (argc != 5) {
    std::fprintf(stderr, "usage: render_hand_eye_session <out_dir> <flange|stand> <count> <seed>\n");
    return 2;
  }
  const std::filesystem::path out(argv[1]);
  const bool stand = std::string(argv[2]) == "stand";
  const int count = std::atoi(argv[3]);
  std::filesystem::create_directories(out / "images");
  const BoardSpec board = ParseBoardSpec("chessboard:9x6:20", {});
  const ramtk::camera::CameraIntrinsics cam = testing::TruthCamera();
  BoardRenderOptions ro;
  ro.noise_sigma = 2.0;
  const BoardRenderer renderer(board, cam, ro);
  std::vector<cv::Vec3d> rvecs, tvecs;
  testing::RandomBoardPoses(board, cam, count, static_cast<unsigned>(std::atoi(argv[4])), &rvecs, &tvecs);
  const ramtk::Isometry3 flange_from_camera = Pose({45.0, -12.0, 110.0}, {0.2, 1.0, 0.1}, 14.0);
  const ramtk::Isometry3 base_from_board = Pose({1520.0, 30.0, 210.0}, {0.1, 0.05, 1.0}, 160.0);
  const ramtk::Isometry3 camera_from_base = Pose({-300.0, 150.0, 1800.0}, {1.0, -0.2, 0.3}, 120.0);
  const ramtk::Isometry3 flange_from_board = Pose({10.0, 20.0, 80.0}, {0.3, 0.1, 1.0}, 30.0);
  std::ofstream poses(out / "flange_poses.txt");
  poses << "# base_from_flange, one row-major 4x4 per line, metres\n";
  poses.precision(12);
  int number = 1;
  auto write_pose = [&](const ramtk::Isometry3& f) {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) poses << (i < 3 && j == 3 ? f(i, j) / 1000.0 : f(i, j)) << (i == 3 && j == 3 ? "\n" : " ");
  };
  for (int v = 0; v < count; ++v) {
    cv::Matx33d r;
    cv::Rodrigues(rvecs[v], r);
    ramtk::Isometry3 cb = ramtk::Isometry3::Identity();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) cb.linear()(i, j) = r(i, j);
      cb.translation()[i] = tvecs[v][i];
    }
    const ramtk::Isometry3 f = stand ? camera_from_base.inverse() * cb * flange_from_board.inverse()
                                     : base_from_board * cb.inverse() * flange_from_camera.inverse();
    if (v == count / 2) {  // a view where the board is not found: listed and skipped
      const cv::Mat blank(ramtk::camera::ImageSize(cam), CV_8U, cv::Scalar(100));
      cv::imwrite((out / "images" / ("view_" + std::to_string(number++) + ".png")).string(), blank);
      write_pose(f);
    }
    cv::imwrite((out / "images" / ("view_" + std::to_string(number++) + ".png")).string(),
                renderer.Render(rvecs[v], tvecs[v], 100 + v));
    write_pose(f);
  }
  std::ofstream(out / "camera.yml") << ramtk::camera::CameraCalibrationText(cam, 0.0, {}, {});
  std::printf("wrote %d views and a blank one to %s\n", count, argv[1]);
  return 0;
}
