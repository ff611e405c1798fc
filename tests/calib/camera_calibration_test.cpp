// Camera calibration on rendered boards with known intrinsics and extrinsics.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <opencv2/calib3d.hpp>

#include "camera_test_util.h"
#include "ramtk/core/error.h"

namespace ramtk::calib {
namespace {

using testing::RandomBoardPoses;
using testing::TruthCamera;

BoardSpec Chessboard() { return ParseBoardSpec("chessboard:9x6:20", {}); }

TEST(BoardRenderer, RaysReprojectExactlyAndCornersAreUnbiased) {
  const camera::CameraIntrinsics cam = TruthCamera();
  BoardRenderOptions ro;
  ro.noise_sigma = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  const BoardRenderer renderer(Chessboard(), cam, ro);
  const auto t1 = std::chrono::steady_clock::now();
  std::printf("ray map %.0f ms\n", std::chrono::duration<double, std::milli>(t1 - t0).count());
  EXPECT_LT(renderer.RayMapError(), 1e-6);
  std::vector<cv::Vec3d> rv, tv;
  RandomBoardPoses(Chessboard(), cam, 3, 5, &rv, &tv);
  for (CornerRefinement refinement : {CornerRefinement::kSectorBased, CornerRefinement::kSubPix}) {
    BoardDetectOptions o;
    o.refinement = refinement;
    double sum2 = 0.0;
    int n = 0;
    for (int v = 0; v < 3; ++v) {
      const cv::Mat img = renderer.Render(rv[v], tv[v], 1);
      const BoardDetection d = DetectBoard(img, Chessboard(), o);
      ASSERT_TRUE(d.found) << d.reason;
      std::vector<cv::Point2f> truth;
      cv::projectPoints(d.object_points, rv[v], tv[v], camera::CameraMatrix(cam), camera::DistortionCoefficients(cam),
                        truth);
      cv::Point2f mean(0, 0);
      for (std::size_t i = 0; i < truth.size(); ++i) {
        sum2 += std::pow(cv::norm(truth[i] - d.image_points[i]), 2);
        mean += (d.image_points[i] - truth[i]) / static_cast<float>(truth.size());
        ++n;
      }
      // A half-pixel convention error would be 0.5 px here.
      std::printf("view %d: mean corner offset %.4f px\n", v, cv::norm(mean));
      EXPECT_LT(cv::norm(mean), 0.05) << "view " << v;
    }
    const double rms = std::sqrt(sum2 / n);
    std::printf("noise-free rendered chessboard, %s: corner RMS vs projected truth %.4f px\n",
                refinement == CornerRefinement::kSubPix ? "cornerSubPix" : "sector-based", rms);
    // A rendering error (wrong pixel convention, wrong distortion inversion) would show as a
    // mean offset or an RMS well above the detector's own. Measured here: sector-based 0.047 px
    // RMS (largest view mean 0.02 px), the adaptive cornerSubPix 0.090 px (largest view mean
    // 0.031 px): larger, but far less correlated across the board (docs/calib.md).
    EXPECT_LT(rms, refinement == CornerRefinement::kSubPix ? 0.12 : 0.06);
  }
}

struct Session {
  std::vector<ViewPoints> views;
  std::vector<cv::Vec3d> rvecs, tvecs;
};

Session RenderSession(const BoardSpec& board, const camera::CameraIntrinsics& cam, int count, unsigned seed,
                      double noise) {
  BoardRenderOptions ro;
  ro.noise_sigma = noise;
  const BoardRenderer renderer(board, cam, ro);
  Session s;
  RandomBoardPoses(board, cam, count, seed, &s.rvecs, &s.tvecs);
  for (int v = 0; v < count; ++v) {
    const BoardDetection d = DetectBoard(renderer.Render(s.rvecs[v], s.tvecs[v], seed * 100 + v), board);
    ViewPoints vp;
    vp.name = "view" + std::to_string(v);
    if (d.found) vp.image_points = d.image_points, vp.object_points = d.object_points, vp.ids = d.ids;
    s.views.push_back(vp);
  }
  return s;
}

// Normalized errors (estimate − truth)/σ_reported of fx fy cx cy k1 k2 p1 p2 and of every view's
// rvec and tvec.
void CollectZ(const CameraCalibrationResult& r, const camera::CameraIntrinsics& truth, const Session& s,
              std::vector<double>* z_intr, std::vector<double>* z_extr) {
  const std::vector<double> t = testing::IntrinsicValues(truth);
  const std::vector<double> e = testing::IntrinsicValues(r.intrinsics);
  for (int i = 0; i < 8; ++i) z_intr->push_back((e[i] - t[i]) / r.std_intrinsics[i]);
  for (std::size_t v = 0; v < r.view_names.size(); ++v) {
    const int idx = std::stoi(r.view_names[v].substr(4));
    for (int k = 0; k < 3; ++k) {
      z_extr->push_back((r.rvecs[v][k] - s.rvecs[idx][k]) / r.std_extrinsics[v][k]);
      z_extr->push_back((r.tvecs[v][k] - s.tvecs[idx][k]) / r.std_extrinsics[v][3 + k]);
    }
  }
}

TEST(CameraCalibration, RecoversTruthWithinReportedStdAtTwoNoiseLevels) {
  const camera::CameraIntrinsics cam = TruthCamera();
  for (double noise : {1.0, 8.0}) {
    std::vector<double> z_intr, z_extr;
    double mean_std_fx = 0.0;
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const Session s = RenderSession(Chessboard(), cam, 12, seed, noise);
      CameraCalibrationSummary sum;
      const CameraCalibrationResult r = CalibrateCamera(s.views, camera::ImageSize(cam), {}, &sum);
      std::printf(
          "noise %.1f seed %u: %s; fx %.3f±%.3f fy %.3f±%.3f cx %.3f±%.3f cy %.3f±%.3f k1 %.5f±%.5f k2 %.4f±%.4f\n",
          noise, seed, sum.BriefReport().c_str(), r.intrinsics.fx, r.std_intrinsics[0], r.intrinsics.fy,
          r.std_intrinsics[1], r.intrinsics.cx, r.std_intrinsics[2], r.intrinsics.cy, r.std_intrinsics[3],
          r.intrinsics.distortion.k1, r.std_intrinsics[4], r.intrinsics.distortion.k2, r.std_intrinsics[5]);
      CollectZ(r, cam, s, &z_intr, &z_extr);
      mean_std_fx += r.std_intrinsics[0] / 3;
    }
    double max_zi = 0, rms_zi = 0, rms_ze = 0;
    int beyond3 = 0;
    for (double z : z_intr) max_zi = std::max(max_zi, std::abs(z)), rms_zi += z * z / z_intr.size();
    for (double z : z_extr) rms_ze += z * z / z_extr.size(), beyond3 += std::abs(z) > 3.0;
    std::printf("noise %.1f: intrinsics |z| max %.2f rms %.2f; extrinsics rms z %.2f, %d of %zu beyond 3 sigma\n",
                noise, max_zi, std::sqrt(rms_zi), std::sqrt(rms_ze), beyond3, z_extr.size());
    // Every intrinsic within 3.5 reported σ of the truth, and the reported σ not too optimistic
    // on average (a consistent σ gives rms z ≈ 1).
    EXPECT_LT(max_zi, 3.5) << "noise " << noise;
    EXPECT_LT(std::sqrt(rms_zi), 2.0) << "noise " << noise;
    EXPECT_LT(std::sqrt(rms_ze), 2.0) << "noise " << noise;
    EXPECT_LE(beyond3, static_cast<int>(0.03 * z_extr.size()) + 1) << "noise " << noise;
  }
}

TEST(CameraCalibration, OutlierViewIsRejectedWithTheReason) {
  const camera::CameraIntrinsics cam = TruthCamera();
  Session s = RenderSession(Chessboard(), cam, 12, 4, 1.0);
  // A view whose corners were mis-detected: every other corner off by 2 px.
  for (std::size_t i = 0; i < s.views[5].image_points.size(); i += 2)
    s.views[5].image_points[i] += cv::Point2f(2.0f, -1.5f);
  CameraCalibrationSummary sum;
  const CameraCalibrationResult r = CalibrateCamera(s.views, camera::ImageSize(cam), {}, &sum);
  ASSERT_EQ(r.rejected.size(), 1u) << sum.BriefReport();
  EXPECT_EQ(r.rejected[0].name, "view5");
  EXPECT_NE(r.rejected[0].reason.find("x median"), std::string::npos) << r.rejected[0].reason;
  EXPECT_EQ(r.view_names.size(), 11u);
  EXPECT_LT(r.rms_px, 0.2);
}

TEST(CameraCalibration, TooFewViewsIsAnError) {
  const camera::CameraIntrinsics cam = TruthCamera();
  const Session s = RenderSession(Chessboard(), cam, 3, 6, 1.0);
  EXPECT_THROW(CalibrateCamera(s.views, camera::ImageSize(cam), {}), InputError);
}

TEST(BoardSpecParse, TextFormsAndErrors) {
  EXPECT_EQ(ParseBoardSpec("charuco:10x7:25:18:DICT_4X4_50", {}).ToString(), "charuco:10x7:25:18:DICT_4X4_50");
  EXPECT_EQ(ParseBoardSpec("acircles:4x11:20", {}).type, BoardType::kAsymmetricCircles);
  try {
    ParseBoardSpec("hexagons:3x3:1", {"", 0, "--board"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--board"), std::string::npos);
  }
  EXPECT_THROW(ParseBoardSpec("charuco:10x7:25:30", {}), InputError);  // marker larger than square
}

}  // namespace
}  // namespace ramtk::calib
