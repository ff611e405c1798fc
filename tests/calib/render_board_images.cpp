// Writes rendered stereo board images for the `ramtk calib cameras` command-line tests:
//   render_board_images <out_dir> <board spec> <count> <seed>
// → <out_dir>/left/view_NN.png, <out_dir>/right/view_NN.png, plus one blank pair (no board)
// and <out_dir>/blank/ with five blank images.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "camera_test_util.h"

int main(int argc, char** argv) {
  using namespace ramtk::calib;
  if (argc != 5) {
    std::fprintf(stderr, "usage: render_board_images <out_dir> <board> <count> <seed>\n");
    return 2;
  }
  const std::filesystem::path out(argv[1]);
  std::filesystem::create_directories(out / "left");
  std::filesystem::create_directories(out / "right");
  const BoardSpec board = ParseBoardSpec(argv[2], {});
  const int count = std::atoi(argv[3]);
  const ramtk::camera::CameraIntrinsics cl = testing::TruthCamera(false), cr = testing::TruthCamera(true);
  cv::Matx33d r_rl;
  cv::Vec3d t_rl;
  testing::TruthStereo(&r_rl, &t_rl);
  BoardRenderOptions ro;
  ro.noise_sigma = 2.0;
  const BoardRenderer rl(board, cl, ro), rr(board, cr, ro);
  std::vector<cv::Vec3d> rvecs, tvecs;
  testing::RandomBoardPoses(board, cl, count, static_cast<unsigned>(std::atoi(argv[4])), &rvecs, &tvecs, &cr, &r_rl,
                            &t_rl);
  char name[64];
  for (int v = 0; v < count; ++v) {
    cv::Matx33d r;
    cv::Rodrigues(rvecs[v], r);
    cv::Vec3d rv_right;
    cv::Rodrigues(r_rl * r, rv_right);
    std::snprintf(name, sizeof(name), "view_%02d.png", v);
    cv::imwrite((out / "left" / name).string(), rl.Render(rvecs[v], tvecs[v], 2 * v));
    cv::imwrite((out / "right" / name).string(), rr.Render(rv_right, r_rl * tvecs[v] + t_rl, 2 * v + 1));
  }
  std::snprintf(name, sizeof(name), "view_%02d.png", count);
  const cv::Mat blank(ramtk::camera::ImageSize(cl), CV_8U, cv::Scalar(100));
  cv::imwrite((out / "left" / name).string(), blank);
  cv::imwrite((out / "right" / name).string(), blank);
  std::filesystem::create_directories(out / "blank");
  for (int v = 0; v < 5; ++v) {
    std::snprintf(name, sizeof(name), "blank_%02d.png", v);
    cv::imwrite((out / "blank" / name).string(), blank);
  }
  std::printf("wrote %d stereo pairs and a blank pair to %s\n", count, argv[1]);
  return 0;
}
