// Hand-eye from rendered board images with known truth, both set-ups: the board renderer draws
// the board at camera_from_board poses derived from known robot, camera and board poses; the
// detections go through PnP with each view's covariance and the weighted SE(3) refinement. Over
// 20 image-noise seeds the errors must lie within 3σ of the truth and the reported σ must match
// the scatter (0.8–1.25); OpenCV's closed forms on the same detections are printed beside them.
// The board poses' own covariance (PnP with known intrinsics, and from the calibration's
// Jacobian) is checked against the scatter of the same sessions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <opencv2/calib3d.hpp>

#include "camera_test_util.h"
#include "ramtk/calib/board_pose.h"
#include "ramtk/calib/hand_eye_flange.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/calib/hand_eye_images.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

namespace t = testing;

constexpr int kSeeds = 20;
constexpr int kViews = 12;
constexpr double kNoiseGrey = 4.0;  // image noise (grey levels, 1σ): the corners' random error dominates

Isometry3 Pose(const Vec3& t, const Vec3& axis, double deg) {
  Isometry3 p = Isometry3::Identity();
  p.linear() = Eigen::AngleAxisd(DegToRad(deg), axis.normalized()).toRotationMatrix();
  p.translation() = t;
  return p;
}

// Truth of both set-ups. Camera on the flange: X = flange_from_camera, Z = base_from_board.
// Camera on a stand: C = camera_from_base, B = flange_from_board.
const Isometry3 kFlangeFromCamera = Pose(Vec3(45.0, -12.0, 110.0), Vec3(0.2, 1.0, 0.1), 14.0);
const Isometry3 kBaseFromBoard = Pose(Vec3(1520.0, 30.0, 210.0), Vec3(0.1, 0.05, 1.0), 160.0);
const Isometry3 kCameraFromBase = Pose(Vec3(-300.0, 150.0, 1800.0), Vec3(1.0, -0.2, 0.3), 120.0);
const Isometry3 kFlangeFromBoard = Pose(Vec3(10.0, 20.0, 80.0), Vec3(0.3, 0.1, 1.0), 30.0);

Isometry3 FromCv(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Isometry3 p = Isometry3::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r(i, j);
    p.translation()[i] = tvec[i];
  }
  return p;
}

// [ω; δt] of `est` against `truth` (ω applied on the left, rad; mm).
Eigen::Matrix<double, 6, 1> PoseError(const Isometry3& est, const Isometry3& truth) {
  Eigen::Matrix<double, 6, 1> e;
  const Eigen::AngleAxisd aa(est.linear() * truth.linear().transpose());
  e.head<3>() = aa.angle() * aa.axis();
  e.tail<3>() = est.translation() - truth.translation();
  return e;
}

// One rendered session per seed: its own board poses (so that the renderer's geometry-fixed
// corner errors are drawn anew too) and image noise.
struct Session {
  std::vector<Isometry3> camera_from_board;  // truth per view
  std::vector<ViewPoints> views;             // detections of the rendered images
};

// The kSeeds sessions, rendered once for all tests.
const std::vector<Session>& Sessions() {
  static const std::vector<Session> s = [] {
    std::vector<Session> out;
    const BoardSpec board = ParseBoardSpec("chessboard:9x6:20", {});
    const camera::CameraIntrinsics cam = t::TruthCamera();
    BoardRenderOptions ro;
    ro.noise_sigma = kNoiseGrey;
    ro.supersample = 2;
    const BoardRenderer renderer(board, cam, ro);
    for (int seed = 0; seed < kSeeds; ++seed) {
      Session session;
      std::vector<cv::Vec3d> rvecs, tvecs;
      t::RandomBoardPoses(board, cam, kViews, 100 + seed, &rvecs, &tvecs);
      std::vector<cv::Mat> images;
      for (int v = 0; v < kViews; ++v) {
        session.camera_from_board.push_back(FromCv(rvecs[v], tvecs[v]));
        images.push_back(renderer.Render(rvecs[v], tvecs[v], 1000ULL * seed + v + 1));
      }
      session.views = t::DetectViews(images, board, BoardDetectOptions(), "view");
      out.push_back(session);
    }
    return out;
  }();
  return s;
}

// The flange poses that put the board at a session's camera_from_board poses.
std::vector<Isometry3> FlangePoses(const Session& session, bool stand) {
  std::vector<Isometry3> f;
  for (const Isometry3& cb : session.camera_from_board)
    f.push_back(stand ? kCameraFromBase.inverse() * cb * kFlangeFromBoard.inverse()
                      : kBaseFromBoard * cb.inverse() * kFlangeFromCamera.inverse());
  return f;
}

// z-scores of errors against a covariance's diagonal, pooled into the RMS of each block.
struct Scatter {
  double rot_ss = 0, trans_ss = 0;
  int n = 0;
  void Add(const Eigen::Matrix<double, 6, 1>& e, const Eigen::Matrix<double, 6, 6>& cov) {
    for (int k = 0; k < 3; ++k) {
      rot_ss += e[k] * e[k] / cov(k, k);
      trans_ss += e[3 + k] * e[3 + k] / cov(3 + k, 3 + k);
    }
    ++n;
  }
  double RotRms() const { return std::sqrt(rot_ss / (3.0 * n)); }
  double TransRms() const { return std::sqrt(trans_ss / (3.0 * n)); }
};

// Mahalanobis distance² of a 3-vector block; the 99.73 % (3σ) quantile of χ²(3) is 14.16.
double Mahalanobis2(const Vec3& e, const Mat3& cov) { return e.dot(cov.ldlt().solve(e)); }
constexpr double kChi2ThreeSigma3 = 14.16;

struct MethodErrors {
  double rot_ss = 0, trans_ss = 0;
  int n = 0;
  void Add(const Isometry3& est, const Isometry3& truth) {
    const auto e = PoseError(est, truth);
    rot_ss += e.head<3>().squaredNorm(), trans_ss += e.tail<3>().squaredNorm(), ++n;
  }
};

void PrintTable(const char* title, const std::map<std::string, MethodErrors>& rows) {
  std::printf("%s: RMS error over %d seeds (%d views, image noise %.0f grey levels)\n", title, kSeeds, kViews,
              kNoiseGrey);
  std::printf("| method | rotation (deg) | translation (mm) |\n|---|---|---|\n");
  for (const auto& [name, m] : rows)
    std::printf("| %s | %.5f | %.4f |\n", name.c_str(), RadToDeg(std::sqrt(m.rot_ss / m.n)), std::sqrt(m.trans_ss / m.n));
}

void CheckWithinSigma(const std::vector<Eigen::Matrix<double, 6, 1>>& errors,
                      const std::vector<Eigen::Matrix<double, 6, 6>>& covariances, const char* what) {
  Scatter scatter;
  for (std::size_t s = 0; s < errors.size(); ++s) {
    const auto& e = errors[s];
    const auto& c = covariances[s];
    EXPECT_LT(Mahalanobis2(e.head<3>(), c.topLeftCorner<3, 3>()), kChi2ThreeSigma3) << what << " rotation, seed " << s;
    EXPECT_LT(Mahalanobis2(e.tail<3>(), c.bottomRightCorner<3, 3>()), kChi2ThreeSigma3)
        << what << " translation, seed " << s;
    scatter.Add(e, c);
  }
  std::printf("%s: scatter / reported sigma: rotation %.3f, translation %.3f\n", what, scatter.RotRms(),
              scatter.TransRms());
  {  // per axis: mean error, scatter and mean reported σ
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero(), var = mean, sig = mean;
    for (std::size_t s = 0; s < errors.size(); ++s) mean += errors[s] / errors.size();
    for (std::size_t s = 0; s < errors.size(); ++s) {
      var += (errors[s] - mean).cwiseAbs2() / (errors.size() - 1);
      sig += covariances[s].diagonal().cwiseSqrt() / errors.size();
    }
    for (int k = 0; k < 6; ++k)
      std::printf("  axis %d: mean %.3g, std %.3g, sigma %.3g\n", k, mean[k], std::sqrt(var[k]), sig[k]);
  }
  EXPECT_GT(scatter.RotRms(), 0.8) << what;
  EXPECT_LT(scatter.RotRms(), 1.25) << what;
  EXPECT_GT(scatter.TransRms(), 0.8) << what;
  EXPECT_LT(scatter.TransRms(), 1.25) << what;
}

void CheckCameraOnFlange() {
  std::vector<Eigen::Matrix<double, 6, 1>> errors;
  std::vector<Eigen::Matrix<double, 6, 6>> covariances;
  std::map<std::string, MethodErrors> table;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const Session& session = Sessions()[seed];
    const HandEyeViews hv = HandEyeViewsFromDetections(session.views, t::TruthCamera(), FlangePoses(session, false));
    ASSERT_EQ(hv.observations.size(), static_cast<std::size_t>(kViews)) << seed;
    for (EyeInHandMethod m : {EyeInHandMethod::kTsai, EyeInHandMethod::kPark, EyeInHandMethod::kHoraud,
                              EyeInHandMethod::kAndreff, EyeInHandMethod::kDaniilidis})
      table[std::string("OpenCV calibrateHandEye ") + EyeInHandMethodName(m)].Add(
          CalibrateCameraOnFlange(hv.observations, m).flange_from_camera, kFlangeFromCamera);
    EyeInHandRefinement ref;
    const EyeInHandResult r = RefineCameraOnFlange(
        hv.observations, CalibrateCameraOnFlange(hv.observations, EyeInHandMethod::kPark), {}, &ref);
    ASSERT_TRUE(ref.pose_covariance);
    table["ramtk (per-view covariance, SE(3))"].Add(r.flange_from_camera, kFlangeFromCamera);
    errors.push_back(PoseError(r.flange_from_camera, kFlangeFromCamera));
    covariances.push_back(ref.flange_from_camera_covariance);
  }
  PrintTable("camera on the flange, flange_from_camera", table);
  CheckWithinSigma(errors, covariances, "flange_from_camera");
}

void CheckCameraOnStand() {
  std::vector<Eigen::Matrix<double, 6, 1>> errors;
  std::vector<Eigen::Matrix<double, 6, 6>> covariances;
  std::map<std::string, MethodErrors> table;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const Session& session = Sessions()[seed];
    const HandEyeViews hv = HandEyeViewsFromDetections(session.views, t::TruthCamera(), FlangePoses(session, true));
    ASSERT_EQ(hv.observations.size(), static_cast<std::size_t>(kViews)) << seed;
    for (HandEyeMethod m : {HandEyeMethod::kShah, HandEyeMethod::kLi}) {
      HandEyeOptions o;
      o.method = m;
      o.refine = false;
      table[std::string("OpenCV calibrateRobotWorldHandEye ") + (m == HandEyeMethod::kShah ? "shah" : "li")].Add(
          CalibrateStandCamera(hv.observations, o).camera_from_base, kCameraFromBase);
    }
    EyeInHandRefinement ref;
    const HandEyeResult r = CalibrateStandCameraWithCovariance(hv.observations, {}, {}, nullptr, &ref);
    ASSERT_TRUE(ref.pose_covariance);
    table["ramtk (per-view covariance, SE(3))"].Add(r.camera_from_base, kCameraFromBase);
    errors.push_back(PoseError(r.camera_from_base, kCameraFromBase));
    covariances.push_back(ref.flange_from_camera_covariance);
  }
  PrintTable("camera on a stand, camera_from_base", table);
  CheckWithinSigma(errors, covariances, "camera_from_base");
}

// Each view's board pose: PnP with the true intrinsics, and the calibration's own (intrinsics
// estimated from the same views, their uncertainty included), against the truth.
void CheckBoardPoses() {
  Scatter pnp, calibrated;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const std::vector<ViewPoints>& views = Sessions()[seed].views;
    const std::vector<Isometry3>& truth = Sessions()[seed].camera_from_board;
    const std::vector<BoardPoseEstimate> p = EstimateBoardPoses(views, t::TruthCamera());
    ASSERT_EQ(p.size(), static_cast<std::size_t>(kViews));
    for (int v = 0; v < kViews; ++v) pnp.Add(PoseError(p[v].camera_from_board, truth[v]), p[v].covariance);
    const CameraCalibrationOptions co;
    const CameraCalibrationResult cal = CalibrateCamera(views, cv::Size(640, 480), co);
    ASSERT_EQ(cal.view_names.size(), static_cast<std::size_t>(kViews)) << seed;
    const std::vector<BoardPoseEstimate> c = BoardPosesFromCalibration(cal, views, co);
    for (int v = 0; v < kViews; ++v)
      calibrated.Add(PoseError(c[v].camera_from_board, truth[v]), c[v].covariance);
  }
  std::printf("board poses, PnP: scatter / sigma rotation %.3f, translation %.3f\n", pnp.RotRms(), pnp.TransRms());
  std::printf("board poses, calibration: scatter / sigma rotation %.3f, translation %.3f\n", calibrated.RotRms(),
              calibrated.TransRms());
  for (const Scatter* s : {&pnp, &calibrated}) {
    EXPECT_GT(s->RotRms(), 0.8);
    EXPECT_LT(s->RotRms(), 1.25);
    EXPECT_GT(s->TransRms(), 0.8);
    EXPECT_LT(s->TransRms(), 1.25);
  }
}

// One test for the three checks: the 240 renders and detections are its cost (~25 s CPU), paid once.
TEST(HandEyeImages, BothSetUpsAndTheBoardPosesWithinTheirSigma) {
  {
    SCOPED_TRACE("camera on the flange");
    CheckCameraOnFlange();
  }
  {
    SCOPED_TRACE("camera on a stand");
    CheckCameraOnStand();
  }
  {
    SCOPED_TRACE("board poses");
    CheckBoardPoses();
  }
}

// The pose Jacobian against central differences of cv::projectPoints under the same perturbation.
TEST(BoardPose, JacobianMatchesFiniteDifferences) {
  const camera::CameraIntrinsics cam = t::TruthCamera();
  const std::vector<cv::Point3f> pts = BoardObjectPoints(ParseBoardSpec("chessboard:9x6:20", {}));
  const std::vector<cv::Point3d> pts_d(pts.begin(), pts.end());
  const Isometry3 pose = Pose(Vec3(-40, 20, 450), Vec3(0.3, -1, 0.2), 25);
  const Eigen::MatrixXd j = BoardPoseJacobian(cam, pts, pose);
  auto project = [&](const Isometry3& p) {
    std::vector<cv::Point2d> out;
    const Eigen::AngleAxisd aa(p.linear());
    const cv::Vec3d r(aa.axis().x() * aa.angle(), aa.axis().y() * aa.angle(), aa.axis().z() * aa.angle());
    cv::projectPoints(pts_d, r, cv::Vec3d(p.translation().x(), p.translation().y(), p.translation().z()),
                      camera::CameraMatrix(cam), camera::DistortionCoefficients(cam), out);
    return out;
  };
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 1e-6 : 1e-4;  // rad, mm
    Isometry3 plus = pose, minus = pose;
    if (k < 3) {
      plus.linear() = Eigen::AngleAxisd(h, Vec3::Unit(k)).toRotationMatrix() * pose.linear();
      minus.linear() = Eigen::AngleAxisd(-h, Vec3::Unit(k)).toRotationMatrix() * pose.linear();
    } else {
      plus.translation()[k - 3] += h;
      minus.translation()[k - 3] -= h;
    }
    const auto a = project(plus), b = project(minus);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double scale = 1.0 + std::abs(j(2 * i, k));
      EXPECT_NEAR(j(2 * i, k), (a[i].x - b[i].x) / (2 * h), 1e-4 * scale) << k << " " << i;
      EXPECT_NEAR(j(2 * i + 1, k), (a[i].y - b[i].y) / (2 * h), 1e-4 * scale) << k << " " << i;
    }
  }
}


// Flange poses one matrix per line: 4×4 with tabs, 3×4 with commas, a comment; metres → mm.
TEST(FlangePoseFile, MatrixPerLineReadsInEitherShape) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "ramtk_flange_matrix_test";
  std::filesystem::create_directories(dir);
  const Isometry3 a = Pose(Vec3(1205.0, -808.0, 524.0), Vec3(0.3, -0.2, 1.0), 40.0);
  const Isometry3 b = Pose(Vec3(900.0, 100.0, 700.0), Vec3(1.0, 0.5, 0.0), 75.0);
  auto row = [](const Isometry3& p, int rows, const char* sep) {
    std::ostringstream s;
    s.precision(12);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < 4; ++j)
        s << (i < 3 && j == 3 ? p(i, j) / 1000.0 : p(i, j)) << (i == rows - 1 && j == 3 ? "\n" : sep);
    return s.str();
  };
  const std::string good = (dir / "poses.txt").string();
  std::ofstream(good) << "# base_from_flange, metres\n" << row(a, 4, "\t") << "\n" << row(b, 3, ", ");
  const std::vector<Isometry3> poses = ReadFlangePoses(good, "m");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_LT((poses[0].matrix() - a.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((poses[1].matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  // Metres read as millimetres: every flange within 20 mm of the base.
  EXPECT_THROW(ReadFlangePoses(good, "mm"), InputError);
  const std::string bad = (dir / "bad.txt").string();
  std::ofstream(bad) << row(a, 4, " ") << "1 0 0 1 0 1 0 2 0 0 1 3 0 0 0\n";
  try {
    ReadFlangePoses(bad, "m");
    ADD_FAILURE() << "15 numbers accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_NE(std::string(e.what()).find("16 (4x4) or 12 (3x4)"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// One camera from a file: the `calib cameras` single-camera text and OpenCV's sample keys.
TEST(CameraFile, ReadsOneCameraFromEitherLayout) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "ramtk_camera_file_test";
  std::filesystem::create_directories(dir);
  const camera::CameraIntrinsics truth = t::TruthCamera();
  const std::string ramtk_file = (dir / "camera.yml").string();
  std::ofstream(ramtk_file) << camera::CameraCalibrationText(truth, 0.1, {}, {});
  const std::string opencv_file = (dir / "out_camera_data.yml").string();
  std::ofstream(opencv_file) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                "   data: [ 750., 0., 328., 0., 752., 236., 0., 0., 1. ]\n"
                                "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
                                "   data: [ -0.12, 0.08, 0.0005, -0.0003, 0. ]\n";
  for (const std::string& f : {ramtk_file, opencv_file}) {
    const camera::CameraIntrinsics c = camera::ReadCameraCalibration(f);
    EXPECT_EQ(c.width, 640) << f;
    EXPECT_EQ(c.height, 480) << f;
    EXPECT_DOUBLE_EQ(c.fx, truth.fx) << f;
    EXPECT_DOUBLE_EQ(c.cy, truth.cy) << f;
    EXPECT_DOUBLE_EQ(c.distortion.k1, truth.distortion.k1) << f;
    EXPECT_DOUBLE_EQ(c.distortion.p2, truth.distortion.p2) << f;
  }
  std::ofstream(dir / "no_k.yml") << "%YAML:1.0\n---\nimage_size: [640, 480]\n";
  EXPECT_THROW(camera::ReadCameraCalibration((dir / "no_k.yml").string()), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ramtk::calib
