// Stereo calibration, other board types and the calibration file, on rendered boards.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>

#include "camera_test_util.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/file_io.h"

namespace ramtk::calib {
namespace {

using testing::RandomBoardPoses;
using testing::RigRotation;
using testing::RigStdRt;
using testing::RigTranslation;
using testing::TruthCamera;
using testing::TruthStereo;

struct StereoSession {
  std::vector<ViewPoints> left, right;
};

StereoSession RenderStereo(const BoardSpec& board, int count, unsigned seed, double noise) {
  BoardRenderOptions ro;
  ro.noise_sigma = noise;
  const BoardRenderer rl(board, TruthCamera(false), ro), rr(board, TruthCamera(true), ro);
  const testing::StereoImages images = testing::RenderStereoImages(board, rl, rr, count, seed, 0);
  return {testing::DetectViews(images.left, board, {}, "left"), testing::DetectViews(images.right, board, {}, "right")};
}

TEST(StereoCalibration, RecoversRigAndWritesTheCalibrationFile) {
  const BoardSpec board = ParseBoardSpec("chessboard:9x6:20", {});
  const StereoSession s = RenderStereo(board, 12, 11, 2.0);
  CameraCalibrationSummary sum;
  const StereoCalibrationResult st = CalibrateStereo(s.left, s.right, cv::Size(640, 480), {}, &sum);
  cv::Matx33d r_true;
  cv::Vec3d t_true;
  TruthStereo(&r_true, &t_true);
  cv::Vec3d dr;
  cv::Rodrigues(RigRotation(st) * r_true.t(), dr);
  const cv::Vec3d translation = RigTranslation(st);
  const cv::Vec6d std_rt = RigStdRt(st);
  // Noise-derived bound: the per-view extrinsic σ of both cameras, averaged over the pairs.
  double var_t = 0.0, var_r = 0.0;
  for (std::size_t i = 0; i < st.left.std_extrinsics.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      var_r += (std::pow(st.left.std_extrinsics[i][k], 2) + std::pow(st.right.std_extrinsics[i][k], 2)) / 3.0;
      var_t += (std::pow(st.left.std_extrinsics[i][3 + k], 2) + std::pow(st.right.std_extrinsics[i][3 + k], 2)) / 3.0;
    }
  }
  const double n = static_cast<double>(st.pair_names.size());
  // Plus the intrinsics: a principal-point error δc turns a camera
  // by δc/f (rad), which moves T by about that angle times the board distance, and a focal error
  // scales T.
  double angle_var = 0.0, scale_var = 0.0, distance = 0.0;
  for (const CameraCalibrationResult* c : {&st.left, &st.right}) {
    const double f = c->intrinsics.fx;
    angle_var += (std::pow(c->std_intrinsics[2], 2) + std::pow(c->std_intrinsics[3], 2)) / (f * f);
    scale_var += std::pow(c->std_intrinsics[0] / f, 2);
  }
  for (const cv::Vec3d& t : st.left.tvecs) distance += cv::norm(t) / n;
  const double sigma_r = std::sqrt(var_r / n / n + angle_var);
  const double sigma_t =
      std::sqrt(var_t / n / n + distance * distance * angle_var + scale_var * cv::norm(t_true) * cv::norm(t_true));
  std::printf(
      "%s\nstereo RMS %.4f px; |dR| %.4f deg (sigma %.4f), |dT| %.4f mm (sigma %.4f per axis), T = (%.3f, %.3f, "
      "%.3f)\n",
      sum.BriefReport().c_str(), st.rig.rms_px, cv::norm(dr) * 180 / CV_PI, sigma_r * 180 / CV_PI,
      cv::norm(translation - t_true), sigma_t, translation[0], translation[1], translation[2]);
  EXPECT_EQ(st.pair_names.size(), 12u);
  EXPECT_LT(cv::norm(dr), 5.0 * sigma_r);
  EXPECT_LT(cv::norm(translation - t_true), 5.0 * sigma_t);
  // The σ the tool reports for R and T (joint Jacobian, intrinsics included): each component of
  // the error within 3.5σ, and of the size of the hand-propagated σ above.
  std::printf(
      "reported std: R (deg) %.4f %.4f %.4f, T (mm) %.4f %.4f %.4f; errors R %.4f %.4f %.4f, T %.4f %.4f %.4f\n",
      std_rt[0] * 180 / CV_PI, std_rt[1] * 180 / CV_PI, std_rt[2] * 180 / CV_PI, std_rt[3], std_rt[4], std_rt[5],
      dr[0] * 180 / CV_PI, dr[1] * 180 / CV_PI, dr[2] * 180 / CV_PI, translation[0] - t_true[0],
      translation[1] - t_true[1], translation[2] - t_true[2]);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(dr[k]), 3.5 * std_rt[k]) << k;
    EXPECT_LT(std::abs(translation[k] - t_true[k]), 3.5 * std_rt[3 + k]) << k;
  }
  // The file: standard keys, read back with cv::FileStorage as any OpenCV user would.
  const std::string path = ::testing::TempDir() + "/stereo.yml";
  WriteFileAtomically(path, StereoCalibrationYaml(st, board));
  cv::FileStorage fs(path, cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat k1, d1, k2, d2, r, t;
  std::vector<double> pve, std_all;
  cv::Size size;
  fs["K1"] >> k1;
  fs["D1"] >> d1;
  fs["K2"] >> k2;
  fs["D2"] >> d2;
  fs["R"] >> r;
  fs["T"] >> t;
  fs["image_size"] >> size;
  fs["per_view_errors_px"] >> pve;
  fs["parameter_std"] >> std_all;
  EXPECT_EQ(size, cv::Size(640, 480));
  EXPECT_LT(cv::norm(k1 - cv::Mat(camera::CameraMatrix(st.rig.left))), 1e-9);
  EXPECT_LT(cv::norm(k2 - cv::Mat(camera::CameraMatrix(st.rig.right))), 1e-9);
  EXPECT_EQ(d1.total(), 5u);
  EXPECT_EQ(d2.total(), 5u);
  EXPECT_LT(cv::norm(r - cv::Mat(RigRotation(st))), 1e-9);
  EXPECT_LT(cv::norm(t - cv::Mat(translation)), 1e-9);
  EXPECT_EQ(pve, st.rig.per_view_errors_px);  // left, right per pair
  EXPECT_EQ(pve.size(), 24u);
  EXPECT_EQ(std_all, st.rig.parameter_std);
  EXPECT_EQ(std_all.size(), 24u);
  EXPECT_DOUBLE_EQ(static_cast<double>(fs["rms_px"]), st.rig.rms_px);
  // Coverage picture: the size of the image, not blank.
  const cv::Mat pic = DrawCoverage(st.left, s.left);
  EXPECT_EQ(pic.size(), cv::Size(640, 480));
  EXPECT_GT(cv::norm(pic, cv::NORM_L1), 0.0);
}

// Circle grids and ChArUco: the intrinsics within the reported σ (looser for circles: the
// centroid of a projected circle is not the projected centre, a known bias of circle grids).
void CheckBoard(const std::string& spec, double z_limit) {
  const BoardSpec board = ParseBoardSpec(spec, {});
  const camera::CameraIntrinsics cam = TruthCamera();
  BoardRenderOptions ro;
  ro.noise_sigma = 2.0;
  const BoardRenderer renderer(board, cam, ro);
  std::vector<cv::Vec3d> rv, tv;
  RandomBoardPoses(board, cam, 12, 21, &rv, &tv);
  std::vector<ViewPoints> views;
  int found = 0;
  for (int v = 0; v < 12; ++v) {
    const BoardDetection d = DetectBoard(renderer.Render(rv[v], tv[v], v), board);
    ViewPoints vp;
    vp.name = "v" + std::to_string(v);
    if (d.found) vp.image_points = d.image_points, vp.object_points = d.object_points, vp.ids = d.ids, ++found;
    views.push_back(vp);
  }
  EXPECT_GE(found, 10) << spec;
  CameraCalibrationSummary sum;
  const CameraCalibrationResult r = CalibrateCamera(views, camera::ImageSize(cam), {}, &sum);
  const std::vector<double> truth = testing::IntrinsicValues(cam);
  const std::vector<double> est = testing::IntrinsicValues(r.intrinsics);
  std::printf("%s: %s; fx %.3f±%.3f fy %.3f±%.3f cx %.3f±%.3f cy %.3f±%.3f k1 %.4f±%.4f\n", spec.c_str(),
              sum.BriefReport().c_str(), est[0], r.std_intrinsics[0], est[1], r.std_intrinsics[1], est[2],
              r.std_intrinsics[2], est[3], r.std_intrinsics[3], est[4], r.std_intrinsics[4]);
  for (int i = 0; i < 4; ++i) EXPECT_LT(std::abs(est[i] - truth[i]), z_limit * r.std_intrinsics[i]) << spec << " " << i;
  EXPECT_LT(std::abs(est[4] - truth[4]), z_limit * r.std_intrinsics[4]) << spec;
}

// Each camera's own residual variance (the sandwich covariance) against one pooled variance: for
// two cameras of the same noise both must give the same σ up to the sampling of the two variances
// (≈ 10 % here); the estimate itself does not change.
TEST(StereoCalibration, PerCameraVarianceMatchesPooledForEqualNoise) {
  const BoardSpec board = ParseBoardSpec("chessboard:9x6:20", {});
  const StereoSession s = RenderStereo(board, 12, 12, 2.0);
  CameraCalibrationOptions pooled, separate;
  separate.per_camera_variance = true;
  const StereoCalibrationResult a = CalibrateStereo(s.left, s.right, cv::Size(640, 480), pooled);
  const StereoCalibrationResult b =
      CalibrateStereo(s.left, s.right, cv::Size(640, 480), cv::Size(640, 480), separate);
  ASSERT_EQ(a.rig.parameter_std.size(), 24u);
  ASSERT_EQ(b.rig.parameter_std.size(), 24u);
  for (int k = 0; k < 24; ++k) {
    if (a.rig.parameter_std[k] == 0.0) continue;  // k3 fixed
    const double ratio = b.rig.parameter_std[k] / a.rig.parameter_std[k];
    EXPECT_GT(ratio, 0.8) << k;
    EXPECT_LT(ratio, 1.25) << k;
  }
  // The same estimate: only the σ differ. OpenCV's solver sums in threads, so two runs agree to
  // its rounding (~1e-10 relative), far below a ten-thousandth of fx's σ.
  EXPECT_NEAR(a.rig.left.fx, b.rig.left.fx, 1e-4 * a.rig.parameter_std[0]);
  EXPECT_TRUE(a.rig.right_from_left.isApprox(b.rig.right_from_left, 1e-8));
}

TEST(CameraCalibration, SymmetricCircleGrid) { CheckBoard("circles:7x5:25", 4.0); }
TEST(CameraCalibration, AsymmetricCircleGrid) { CheckBoard("acircles:4x9:15", 4.0); }
TEST(CameraCalibration, Charuco) { CheckBoard("charuco:8x6:25:18:DICT_5X5_100", 3.5); }

}  // namespace
}  // namespace ramtk::calib

// The file `ramtk calib cameras` writes, read by the scan's reader: the rig, the session's RMS
// and every σ survive (issue 18: they used to be dropped), in the order
// ramtk::camera::kCalibParameterStdOrder names.
TEST(CalibrationFile, SessionFiguresSurviveTheScanReader) {
  ramtk::calib::StereoCalibrationResult st;
  st.rig.left = ramtk::camera::IntrinsicsFromOpenCv(cv::Matx33d(1000, 0, 320, 0, 1000, 256, 0, 0, 1),
                                                    {0.01, -0.02, 0.001, -0.002, 0.003}, cv::Size(640, 512));
  st.rig.right = ramtk::camera::IntrinsicsFromOpenCv(cv::Matx33d(1010, 0, 318, 0, 1009, 250, 0, 0, 1),
                                                     {0.02, -0.01, 0.0, 0.0, 0.0}, cv::Size(640, 512));
  st.rig.right_from_left.linear() = Eigen::AngleAxisd(0.07, ramtk::Vec3(0.1, 1.0, 0.2).normalized()).matrix();
  st.rig.right_from_left.translation() = ramtk::Vec3(-100, 0.5, 2);
  st.rig.rms_px = 0.1234;
  st.rig.per_view_errors_px = {0.1, 0.2, 0.3, 0.4};
  for (int i = 0; i < 24; ++i) st.rig.parameter_std.push_back(1e-3 * (i + 1));
  st.left.rms_px = st.right.rms_px = 0.11;
  const std::string path = ::testing::TempDir() + "session_stereo.yml";
  ramtk::WriteFileAtomically(
      path, ramtk::calib::StereoCalibrationYaml(st, ramtk::calib::ParseBoardSpec("chessboard:9x6:20", {})));
  const ramtk::camera::StereoCalibration v = ramtk::camera::ReadStereoCalibration(path);
  for (const auto& [read, written] : {std::pair{&v.left, &st.rig.left}, std::pair{&v.right, &st.rig.right}}) {
    EXPECT_EQ(read->K(), written->K());
    EXPECT_EQ(ramtk::camera::DistortionCoefficients(*read), ramtk::camera::DistortionCoefficients(*written));
    EXPECT_EQ(read->width, 640);
    EXPECT_EQ(read->height, 512);
  }
  EXPECT_LT((v.right_from_left.matrix() - st.rig.right_from_left.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_DOUBLE_EQ(v.rms_px, 0.1234);
  EXPECT_EQ(v.parameter_std, st.rig.parameter_std);
  EXPECT_EQ(v.per_view_errors_px, st.rig.per_view_errors_px);
}
