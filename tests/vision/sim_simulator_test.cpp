// The simulator: seeds reproduce images exactly (also across thread counts), effects do what their
// magnitudes say, and the written set (manifest, images, calibration, ground truth) reads back.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ramtk/core/error.h"
#include "ramtk/image/frame_rows.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::vision {
namespace {

namespace fs = std::filesystem;

// The small preset reduced for speed: 2×2 supersampling and a 3-step sequence.
FringeSimulationConfig FastConfig() {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.supersampling = 2;
  c.sequence = {PhaseShiftBlock(3, 64.0)};
  return c;
}

bool Identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

// ScaleCameraWindows resamples a window: a point that images at pixel u in the original window
// images at (u + 0.5)·s − 0.5 in the scaled one (pixel centres at integers: pixel 0 of the
// scaled window covers original pixels 0..1/s), for both cameras, through the lens distortion.
TEST(SimSimulator, ScaledWindowsMapPixelCentresAsResampling) {
  const FringeSimulationConfig c = MakeFringePreset("small", Vec3(12.0, -7.0, 705.0));
  for (double s : {0.25, 0.5, 2.0}) {
    const FringeSimulationConfig d = ScaleCameraWindows(c, s);
    EXPECT_EQ(d.cameras.left.width, static_cast<int>(std::lround(640 * s)));
    EXPECT_EQ(d.cameras.right.height, static_cast<int>(std::lround(512 * s)));
    for (const Vec3& x : {Vec3(12.0, -7.0, 705.0), Vec3(-20.0, 15.0, 690.0), Vec3(30.0, 25.0, 720.0)}) {
      for (int cam = 0; cam < 2; ++cam) {
        const Isometry3 view = cam == 0 ? Isometry3::Identity() : c.cameras.right_from_left;
        const CameraIntrinsics& a = cam == 0 ? c.cameras.left : c.cameras.right;
        const CameraIntrinsics& b = cam == 0 ? d.cameras.left : d.cameras.right;
        const Vec2 pa = ProjectPoint(a, view * x), pb = ProjectPoint(b, view * x);
        EXPECT_NEAR(pb.x(), (pa.x() + 0.5) * s - 0.5, 1e-9);
        EXPECT_NEAR(pb.y(), (pa.y() + 0.5) * s - 0.5, 1e-9);
      }
    }
  }
}

TEST(SimSimulator, SeedsReproduceImagesExactlyAcrossThreadCounts) {
  FringeSimulationConfig c = FastConfig();
  c.seed = 1234;
  const SimulatedCamera a = SimulateCamera(c, 1);
  SimulatedCamera b;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    b = SimulateCamera(c, 1);
  }
  ASSERT_EQ(a.images.size(), 3u);
  for (std::size_t i = 0; i < a.images.size(); ++i) EXPECT_TRUE(Identical(a.images[i], b.images[i])) << i;
  c.seed = 1235;
  const SimulatedCamera other = SimulateCamera(c, 1);
  EXPECT_FALSE(Identical(a.images[0], other.images[0]));
  // Same scene, different noise: the noiseless radiance is identical.
  EXPECT_TRUE(Identical(a.truth.radiance[0], other.truth.radiance[0]));
}

// Sensing a render again with another seed gives what a whole simulation with that seed gives,
// effects on the sensor (exposure, drift gains, camera blur) included.
TEST(SimSimulator, ResensedRenderIsTheSimulationWithThatSeed) {
  FringeSimulationConfig c = FastConfig();
  c.effects.Set("saturation", 0.5);
  c.effects.Set("intensity_drift", 0.05);
  c.effects.Set("camera_defocus", 0.7);
  c.seed = 11;
  const SimulatedCamera rendered = SimulateCamera(c, 1);
  c.seed = 12;
  const SimulatedCamera whole = SimulateCamera(c, 1);
  const SimulatedCamera resensed = ResenseCamera(c, rendered, 1);
  ASSERT_EQ(resensed.images.size(), whole.images.size());
  for (std::size_t i = 0; i < whole.images.size(); ++i) EXPECT_TRUE(Identical(resensed.images[i], whole.images[i])) << i;
  EXPECT_FALSE(Identical(resensed.images[0], rendered.images[0]));
}

TEST(SimSimulator, IntensityDriftAndGammaFollowTheirMagnitudes) {
  FringeSimulationConfig c = FastConfig();
  c.sensor.bits = 16;
  c.sensor.noise = false;
  const SimulatedCamera base = SimulateCamera(c, 0);
  c.effects.Set("intensity_drift", 0.1);
  const SimulatedCamera drift = SimulateCamera(c, 0);
  // Gain 1 + 0.1·k/(n − 1) on frame k: 1, 1.05, 1.1. 16-bit rounding: ±0.5 DN on > 2000 DN.
  for (int k = 0; k < 3; ++k) {
    cv::Mat a, b;
    base.images[k].convertTo(a, CV_64F);
    drift.images[k].convertTo(b, CV_64F);
    const cv::Mat mask = a > 2000.0;
    ASSERT_GT(cv::countNonZero(mask), 10000);
    cv::Mat ratio = b / a;
    double lo, hi;
    cv::minMaxLoc(ratio, &lo, &hi, nullptr, nullptr, mask);
    EXPECT_NEAR(lo, 1.0 + 0.05 * k, 1e-3) << k;
    EXPECT_NEAR(hi, 1.0 + 0.05 * k, 1e-3) << k;
  }
  // Gamma: with one ray per pixel and no ambient light, radiance = albedo·cos·P^γ. The linear
  // render gives albedo·cos (twice the mean of a 3-step set) and each P; γ = 2.2 must give
  // albedo·cos·P^2.2.
  c.supersampling = 1;  // single ray: P is one value per pixel
  c.effects = {};
  const SimulatedCamera lin1 = SimulateCamera(c, 0);
  c.effects.Set("projector_nonlinearity", 2.2);
  const SimulatedCamera gam1 = SimulateCamera(c, 0);
  // Recover P·albedo·cos from the three linear frames: A = mean = albedo·cos·0.5, so P_k = r_k/(2A).
  int checked = 0;
  for (int v = 100; v < 400; v += 37) {
    for (int u = 100; u < 540; u += 41) {
      if (lin1.truth.lit_fraction.at<float>(v, u) != 1.0f) continue;
      double a = 0;
      for (int k = 0; k < 3; ++k) a += lin1.truth.radiance[k].at<float>(v, u) / 3.0;
      const double shading = 2.0 * a;  // albedo·cos
      for (int k = 0; k < 3; ++k) {
        const double p = lin1.truth.radiance[k].at<float>(v, u) / shading;
        EXPECT_NEAR(gam1.truth.radiance[k].at<float>(v, u), shading * std::pow(p, 2.2), 2e-6) << u << "," << v;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(SimSimulator, PhaseShiftErrorShiftsEachStepByItsRecordedDraw) {
  // One ray per pixel, noiseless: the error-free 4-step radiance gives each pixel's shading S and
  // phase φ exactly; with phase_shift_error on, step k must read S·(0.5 + 0.5 cos(φ + 2πk/4 + ε_k))
  // with ε_k the draw RealiseEffects records for this seed.
  FringeSimulationConfig c = FastConfig();
  c.supersampling = 1;
  c.sequence = {PhaseShiftBlock(4, 64.0)};
  c.seed = 99;
  const SimulatedCamera clean = SimulateCamera(c, 0);
  c.effects.Set("phase_shift_error", 5.0);
  const SimulatedCamera shifted = SimulateCamera(c, 0);
  const EffectRealisation draws = RealiseEffects(c, ExpandSequence(c.sequence));
  double largest = 0.0;
  for (double e : draws.shift_errors_rad) largest = std::max(largest, std::abs(e));
  ASSERT_GT(largest, 0.02);  // the draws are not all ~0 (σ = 5° = 0.087 rad)
  const double two_pi = 6.283185307179586;
  int checked = 0;
  for (int v = 60; v < 460; v += 29) {
    for (int u = 60; u < 580; u += 31) {
      if (clean.truth.lit_fraction.at<float>(v, u) != 1.0f) continue;
      double r[4], s = 0, cc = 0;
      for (int k = 0; k < 4; ++k) {
        r[k] = clean.truth.radiance[k].at<float>(v, u);
        s += r[k] * std::sin(two_pi * k / 4);
        cc += r[k] * std::cos(two_pi * k / 4);
      }
      const double shading = (r[0] + r[1] + r[2] + r[3]) / 2.0;
      const double phi = std::atan2(-s, cc);
      for (int k = 0; k < 4; ++k) {
        const double expected = shading * (0.5 + 0.5 * std::cos(phi + two_pi * k / 4 + draws.shift_errors_rad[k]));
        EXPECT_NEAR(shifted.truth.radiance[k].at<float>(v, u), expected, 2e-6) << u << "," << v << " k " << k;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(SimSimulator, ProgressReportsRowsAndCancelsWithoutOutput) {
  FringeSimulationConfig c = FastConfig();
  std::size_t calls = 0, last_done = 0, total = 0;
  const SimulatedCamera done = SimulateCamera(c, 0, [&](const Progress& p) {
    ++calls;
    last_done = std::max(last_done, p.done);
    total = p.total;
    return true;
  });
  EXPECT_EQ(calls, 512u);  // one call per image row
  EXPECT_EQ(last_done, 512u);
  EXPECT_EQ(total, 512u);
  EXPECT_FALSE(done.truth.cancelled);
  const std::string out = (fs::temp_directory_path() / ("ramtk_sim_cancel_" + std::to_string(::getpid()))).string();
  fs::remove_all(out);
  const FringeSimulationSummary s = SimulateFringeSet(c, out, false, [](const Progress& p) { return p.done < 100; });
  EXPECT_TRUE(s.cancelled);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial-" + std::to_string(::getpid())));
}

TEST(SimSimulator, TwelveBitImagesAreWrittenAtSixteenBitFullScale) {
  FringeSimulationConfig c = FastConfig();
  c.supersampling = 1;
  c.sensor.bits = 12;
  c.effects.Set("saturation", 3.0);  // clip the bright fringes
  const std::string out = (fs::temp_directory_path() / ("ramtk_sim_12bit_" + std::to_string(::getpid()))).string();
  fs::remove_all(out);
  SimulateFringeSet(c, out);
  const cv::Mat written = cv::imread(out + "/left/00.png", cv::IMREAD_UNCHANGED);
  const SimulatedCamera sim = SimulateCamera(c, 0);  // same seed: the same 12-bit values
  ASSERT_EQ(written.type(), CV_16U);
  double lo, hi;
  cv::minMaxLoc(sim.images[0], &lo, &hi);
  EXPECT_EQ(hi, 4095.0);
  for (int v = 0; v < written.rows; v += 7)
    for (int u = 0; u < written.cols; u += 7) {
      const int q = sim.images[0].at<std::uint16_t>(v, u);
      ASSERT_EQ(written.at<std::uint16_t>(v, u), static_cast<int>(std::lround(q * 65535.0 / 4095.0))) << u << "," << v;
    }
  fs::remove_all(out);
}

// frame_format "bmp": the same samples as the rendered frames, in files the scan reads by rows
// (uncompressed 8-bit grey, identity palette), listed by the manifest; refused for a 12-bit sensor.
TEST(SimSimulator, BmpFramesHoldTheRenderedSamplesAndAreReadByRows) {
  FringeSimulationConfig c = FastConfig();
  c.supersampling = 1;
  c.frame_format = "bmp";
  const std::string out = (fs::temp_directory_path() / ("ramtk_sim_bmp_" + std::to_string(::getpid()))).string();
  fs::remove_all(out);
  SimulateFringeSet(c, out);
  const SimulatedCamera sim = SimulateCamera(c, 1);  // same seed: the same samples
  for (std::size_t i = 0; i < sim.images.size(); i += 5) {
    char name[32];
    std::snprintf(name, sizeof name, "/right/%02zu.bmp", i);
    const cv::Mat written = cv::imread(out + name, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(written.type(), CV_8UC1) << name;
    EXPECT_EQ(cv::norm(written, sim.images[i], cv::NORM_INF), 0.0) << name;
    image::FrameRows rows;
    std::string why;
    EXPECT_TRUE(rows.Open(out + name, &why)) << why;
  }
  std::ifstream manifest(out + "/manifest.json");
  const nlohmann::json m = nlohmann::json::parse(manifest);
  EXPECT_EQ(m["cameras"]["left"][0], "left/00.bmp");
  fs::remove_all(out);
  c.sensor.bits = 12;
  EXPECT_NE(c.Validate().find("frame_format"), std::string::npos) << c.Validate();
  c.sensor.bits = 8;
  c.frame_format = "tiff";
  EXPECT_NE(c.Validate().find("frame_format"), std::string::npos) << c.Validate();
}

// Mean |Δ projector x| between the two cameras' truth when left pixels are carried into the right
// image through the *written* calibration: left truth depth → 3-D point → right pixel, bilinear
// right truth there.
double StereoTruthDisagreement(const FringeSimulationConfig& c, int* used) {
  const SimulatedCamera left = SimulateCamera(c, 0), right = SimulateCamera(c, 1);
  const StereoCalibration calib = WrittenCalibration(c);
  double sum = 0.0;
  *used = 0;
  for (int v = 8; v < 504; v += 9) {
    for (int u = 8; u < 632; u += 9) {
      if (left.truth.lit_fraction.at<float>(v, u) != 1.0f) continue;
      const Vec3 ray = PixelRay(calib.left, Vec2(u, v));
      const Vec3 x_left = ray * (left.truth.depth.at<float>(v, u) / ray.z());
      const Vec2 p = ProjectPoint(calib.right, calib.right_from_left * x_left);
      const int u0 = static_cast<int>(std::floor(p.x())), v0 = static_cast<int>(std::floor(p.y()));
      if (u0 < 0 || v0 < 0 || u0 + 1 >= 640 || v0 + 1 >= 512) continue;
      bool clean = true;
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du)
          clean = clean && right.truth.lit_fraction.at<float>(v0 + dv, u0 + du) == 1.0f &&
                  right.truth.object_id.at<int>(v0 + dv, u0 + du) == left.truth.object_id.at<int>(v, u);
      if (!clean) continue;
      const double fu = p.x() - u0, fv = p.y() - v0;
      auto at = [&](int dv, int du) {
        return static_cast<double>(right.truth.projector_x.at<float>(v0 + dv, u0 + du));
      };
      const double interpolated =
          (1 - fv) * ((1 - fu) * at(0, 0) + fu * at(0, 1)) + fv * ((1 - fu) * at(1, 0) + fu * at(1, 1));
      sum += std::abs(interpolated - left.truth.projector_x.at<float>(v, u));
      ++*used;
    }
  }
  return sum / std::max(*used, 1);
}

TEST(SimSimulator, WrittenCalibrationMakesBothCamerasAgree) {
  // A surface point seen by both cameras is lit by one projector column: the written calibration
  // must carry each left pixel onto the right pixel that sees the same column. Bilinear
  // interpolation of a smooth map (~0.3 projector px per camera px) costs ~1e-3 px.
  FringeSimulationConfig c = FastConfig();
  c.supersampling = 1;
  c.sequence = {PhaseShiftBlock(3, 64.0)};
  int used = 0;
  const double modelled = StereoTruthDisagreement(c, &used);
  EXPECT_GT(used, 1500);
  EXPECT_LT(modelled, 5e-3);
  // With distortion that the calibration does not carry, the cameras disagree.
  c.effects.Set("lens_distortion_unmodelled", 0.5);
  const double unmodelled = StereoTruthDisagreement(c, &used);
  EXPECT_GT(unmodelled, 10 * modelled);
  RecordProperty("stereo_truth_disagreement_px", std::to_string(modelled));
  RecordProperty("stereo_truth_disagreement_unmodelled_px", std::to_string(unmodelled));
}

TEST(SimSimulator, SceneAroundTheRealSlmasterCalibration) {
  const std::string path = std::string(RAMTK_SHARED_DIR) + "/data/slmaster-binocular/caliInfo.yml";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  FringeSimulationConfig c = MakeFringeConfigForCalibration(ReadStereoCalibration(path));
  c.supersampling = 1;
  c.sequence = {PhaseShiftBlock(3, 64.0)};
  // The optical axes of caliInfo.yml come closest ~572 mm in front of the left camera (Rlr turns
  // the right camera by 20.05° about y; its centre −Rlrᵀ·Tlr is (197.7, 0.0, 30.5) mm, so the
  // axes meet where x = 0 on the right axis: z = 30.5 + 197.7 / tan 20.05° = 572.1 mm).
  const Vec3 ball = c.scene.spheres[0].centre_in_left;
  EXPECT_NEAR(ball.z(), 572.1, 0.5);
  for (int cam = 0; cam < 2; ++cam) {
    const SimulatedCamera sim = SimulateCamera(c, cam);
    const PinholeView view = RenderedCameraView(c, cam);
    const Vec2 px = ProjectPoint(view.intrinsics, view.view_from_left * ball);
    const int u = static_cast<int>(std::round(px.x())), v = static_cast<int>(std::round(px.y()));
    ASSERT_TRUE(u >= 0 && v >= 0 && u < 1280 && v < 1024) << cam;
    EXPECT_EQ(sim.truth.object_id.at<int>(v, u), 0) << cam;
    EXPECT_EQ(sim.truth.lit_fraction.at<float>(v, u), 1.0f) << cam;
  }
}

TEST(SimSimulator, HeterodyneFramesCarryTheirOwnFrequencies) {
  // Three 4-step sets at 70, 64 and 59 periods: each set's phase (one ray per pixel, exact
  // radiance) must be its own frequency's phase of the true projector column.
  FringeSimulationConfig c = FastConfig();
  c.supersampling = 1;
  c.sequence = {HeterodyneBlock(4, {70.0, 64.0, 59.0})};
  const SimulatedCamera sim = SimulateCamera(c, 0);
  ASSERT_EQ(sim.truth.radiance.size(), 12u);
  const double two_pi = 6.283185307179586;
  int checked = 0;
  for (int v = 20; v < 500; v += 23) {
    for (int u = 20; u < 620; u += 29) {
      if (sim.truth.lit_fraction.at<float>(v, u) != 1.0f) continue;
      const double x = sim.truth.projector_x.at<float>(v, u);
      for (int f = 0; f < 3; ++f) {
        double s = 0, cc = 0;
        for (int k = 0; k < 4; ++k) {
          const double r = sim.truth.radiance[4 * f + k].at<float>(v, u);
          s += r * std::sin(two_pi * k / 4);
          cc += r * std::cos(two_pi * k / 4);
        }
        const double cycles = std::vector<double>{70.0, 64.0, 59.0}[f];
        const double expected = two_pi * cycles * x / 912.0 - two_pi / 2;
        // float32 radiance and the float32 truth column (~3e-5 px × 2π·70/912): ~2e-5 rad.
        EXPECT_NEAR(std::remainder(std::atan2(-s, cc) - expected, two_pi), 0.0, 1e-4) << u << "," << v << " f" << f;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(SimSimulator, SmallPresetWindowsFollowTheBall) {
  // The rig stays aimed at (0, 0, 700); the 640×512 windows are cropped where the ball images, so
  // the ball centre lands within half a pixel of the window centre (319.5, 255.5) in both cameras.
  const Vec3 ball(60.0, -40.0, 720.0);
  const FringeSimulationConfig c = MakeFringePreset("small", ball);
  const FringeSimulationConfig thesis = MakeFringePreset("thesis", ball);
  EXPECT_LT((c.cameras.right_from_left.matrix() - thesis.cameras.right_from_left.matrix()).norm(), 1e-15);
  EXPECT_EQ(c.scene.spheres[0].centre_in_left, ball);
  for (int cam = 0; cam < 2; ++cam) {
    const PinholeView view = RenderedCameraView(c, cam);
    const Vec2 px = ProjectPoint(view.intrinsics, view.view_from_left * ball);
    EXPECT_NEAR(px.x(), 319.5, 0.5) << cam;
    EXPECT_NEAR(px.y(), 255.5, 0.5) << cam;
  }
  EXPECT_THROW(MakeFringePreset("small", Vec3(600.0, 0.0, 700.0)), InputError);
}

TEST(SimSimulator, UnknownEffectAndBadMagnitudeAreInputErrors) {
  FringeEffects e;
  EXPECT_THROW(e.Set("projector_gamma", 2.2), InputError);
  EXPECT_THROW(e.Set("defocus", -1.0), InputError);
  EXPECT_THROW(MakeFringePreset("huge"), InputError);
  try {
    e.Set("saturation", 0.0, "--effect saturation");
    ADD_FAILURE();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().field, "--effect saturation");
  }
}

TEST(SimSimulator, UnmodelledDistortionIsRenderedButNotWritten) {
  FringeSimulationConfig c = FastConfig();
  c.effects.Set("lens_distortion_unmodelled", 0.02);
  EXPECT_DOUBLE_EQ(RenderedCameraView(c, 0).intrinsics.distortion.k1, c.cameras.left.distortion.k1 + 0.02);
  EXPECT_DOUBLE_EQ(WrittenCalibration(c).left.distortion.k1, c.cameras.left.distortion.k1);
}

std::string TempDir(const std::string& name) {
  return (fs::temp_directory_path() / ("ramtk_sim_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(SimSimulator, WritesAReadableSetAndRefusesToOverwrite) {
  FringeSimulationConfig c = FastConfig();
  c.sequence.push_back(GrayCodeBlock(2, false));
  c.seed = 77;
  const std::string out = TempDir("set");
  fs::remove_all(out);
  const FringeSimulationSummary s = SimulateFringeSet(c, out + "/");  // a trailing slash names the same folder
  EXPECT_EQ(s.frames, 5);
  std::ifstream in(out + "/manifest.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  EXPECT_EQ(m["sequence"][0]["type"], "phase_shift");
  EXPECT_EQ(m["sequence"][0]["steps"], 3);
  EXPECT_EQ(m["sequence"][1]["type"], "gray_code");
  EXPECT_EQ(m["direction"], "vertical");
  EXPECT_EQ(m["sequence"][0]["phase_at_origin_deg"], -180.0);
  EXPECT_EQ(m["projector"]["width"], 912);
  EXPECT_EQ(m["simulation"]["seed"], 77);
  ASSERT_EQ(m["cameras"].size(), 2u);
  for (const auto& [name, images] : m["cameras"].items()) {
    ASSERT_EQ(images.size(), 5u) << name;
    for (const auto& f : images) {
      const cv::Mat img = cv::imread(out + "/" + f.get<std::string>(), cv::IMREAD_UNCHANGED);
      ASSERT_EQ(img.type(), CV_8U) << f;
      EXPECT_EQ(img.cols, 640);
      EXPECT_EQ(img.rows, 512);
    }
  }
  const StereoCalibration calib = ReadStereoCalibration(out + "/" + m["calibration"].get<std::string>());
  EXPECT_EQ(calib.left.fx, c.cameras.left.fx);
  EXPECT_EQ(calib.right.cx, c.cameras.right.cx);
  EXPECT_LT((calib.right_from_left.matrix() - c.cameras.right_from_left.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  std::ifstream tin(out + "/truth/truth.json");
  const nlohmann::json t = nlohmann::json::parse(tin);
  EXPECT_EQ(t["spheres"][0]["radius_mm"], 19.05);
  EXPECT_EQ(t["seed"], 77);
  const cv::Mat depth = cv::imread(out + "/truth/left_depth.tif", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_32F);
  // The ball's front pole is on the left optical axis: depth 700 − r at the ball-centre pixel.
  const CameraIntrinsics& k = c.cameras.left;
  EXPECT_NEAR(depth.at<float>(static_cast<int>(std::round(k.cy)), static_cast<int>(std::round(k.cx))), 700.0 - 19.05,
              0.01);

  // An existing non-empty folder is refused before any rendering, and left untouched.
  std::ofstream(out + "/keep.txt") << "user data";
  EXPECT_THROW(SimulateFringeSet(c, out), InputError);
  EXPECT_TRUE(fs::exists(out + "/keep.txt"));
  // A failure mid-way (invalid sequence) leaves no output and no temporary folder.
  const std::string out2 = TempDir("bad");
  fs::remove_all(out2);
  c.sequence[0].steps = 2;
  EXPECT_THROW(SimulateFringeSet(c, out2), InputError);
  EXPECT_FALSE(fs::exists(out2));
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_EQ(entry.path().string().find(out2 + ".partial"), std::string::npos);
  fs::remove_all(out);
}

}  // namespace
}  // namespace ramtk::vision
