// The scan pipeline against the simulator's truth (small preset), a scene without the ball, bad
// calibrations, and the real SLMaster capture (skipped when ../shared is absent).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <unordered_map>

#include "ramtk/core/error.h"
#include "ramtk/vision/stereo/cloud_noise.h"
#include "ramtk/vision/scan/scan.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

using testing::SimulateAndDecode;

TEST(ScanPipeline, BallCentreAndRadiusAgainstTheSimulatorTruth) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.seed = 3;
  const auto s = SimulateAndDecode(c);
  const ScanResult r = ScanDecoded(WrittenCalibration(c), s.left, s.right, s.period, ScanOptions{});
  ASSERT_EQ(r.summary.termination, Termination::kSuccess) << r.summary.BriefReport();
  ASSERT_EQ(r.summary.spheres.spheres.size(), 1u);
  const SphereResult& ball = r.summary.spheres.spheres[0];
  const Vec3 err = ball.centre_mm - c.scene.spheres[0].centre_in_left;
  const double radius_err = ball.radius_mm - c.scene.spheres[0].radius;
  RecordProperty("report", r.summary.BriefReport());
  RecordProperty("centre_error_um", std::to_string(1000 * err.norm()));
  RecordProperty("radius_error_um", std::to_string(1000 * radius_err));
  std::cout << r.summary.BriefReport() << "\ncentre error " << 1000 * err.transpose() << " um, radius error "
            << 1000 * radius_err << " um\n";
  // Issue 4's targets: 5 um. The fit leaves out the points seen beyond 60 deg (their depth is
  // biased by the noise, docs/scan.md); at this pose what remains is a -1.1 um bias along z and
  // a 1.4 um scatter (the sweep, 50 seeds; predicted 1.45 um): 5 um is the bias plus 2.8 sigma.
  // Without the viewing-angle cut this pose's bias is -3.0 um along z.
  EXPECT_LT(err.norm(), 0.005);
  EXPECT_LT(std::abs(radius_err), 0.005);
  EXPECT_GT(ball.num_grazing, 3000);
  EXPECT_GT(ball.correlation_factor, 1.0);  // neighbouring pixels' noise is positively correlated
  EXPECT_GT(ball.num_points, 25000);
  EXPECT_NEAR(ball.variance_factor, 1.0, 0.5);  // the points' sigma explains their scatter
}

// The same pose with the fringes' phase origin moved off the code edges (issue 16: wraps mid code
// cell). Over 30 seeds per origin (2026-11-24, `ramtk simulate fringe --seed S --phase-at-origin O`
// then `ramtk scan --truth`) the centre's z error is -0.89 +- 0.24 um at -180 deg and
// -0.80 +- 0.29 um at 0 deg, scatter 1.3-1.6 um against the predicted 1.45: no dependence on the
// origin, the common -0.85 um being the view-angle bias above. Same 5 um gate (bias + 2.8 sigma).
class ScanPhaseOrigin : public ::testing::TestWithParam<double> {};

TEST_P(ScanPhaseOrigin, BallCentreDoesNotDependOnWhereThePhaseWraps) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.seed = 3;
  for (auto& b : c.sequence) b.phase_at_origin_rad = GetParam() * 3.14159265358979323846 / 180.0;
  const auto s = SimulateAndDecode(c);
  const ScanResult r = ScanDecoded(WrittenCalibration(c), s.left, s.right, s.period, ScanOptions{});
  ASSERT_EQ(r.summary.spheres.spheres.size(), 1u) << r.summary.BriefReport();
  const SphereResult& ball = r.summary.spheres.spheres[0];
  const Vec3 err = ball.centre_mm - c.scene.spheres[0].centre_in_left;
  RecordProperty("centre_error_um", std::to_string(1000 * err.norm()));
  EXPECT_LT(err.norm(), 0.005) << 1000 * err.transpose() << " um";
  EXPECT_LT(std::abs(ball.radius_mm - c.scene.spheres[0].radius), 0.005);
  EXPECT_NEAR(ball.variance_factor, 1.0, 0.5);
}

INSTANTIATE_TEST_SUITE_P(Origins, ScanPhaseOrigin, ::testing::Values(0.0, 90.0),
                         [](const ::testing::TestParamInfo<double>& i) {
                           return "deg" + std::to_string(static_cast<int>(i.param));
                         });

TEST(ScanPipeline, NoBallGivesNoSphereFoundNotACentre) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.scene.spheres.clear();  // the backdrop alone
  c.supersampling = 1;
  const auto s = SimulateAndDecode(c);
  const ScanResult r = ScanDecoded(WrittenCalibration(c), s.left, s.right, s.period, ScanOptions{});
  EXPECT_EQ(r.summary.termination, Termination::kNoResult);
  EXPECT_TRUE(r.summary.spheres.spheres.empty());
  EXPECT_FALSE(r.summary.spheres.no_sphere_reason.empty());
  EXPECT_GT(r.cloud.size(), 50000u);  // the plane itself is reconstructed
}

TEST(ScanPipeline, CalibrationOfAnotherImageSizeIsRejectedNamingTheField) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.supersampling = 1;
  const auto s = SimulateAndDecode(c);
  StereoCalibration wrong = WrittenCalibration(c);
  wrong.right.width = 1280;
  wrong.source_path = "calib.yml";  // the errors name the calibration's file
  try {
    ScanDecoded(wrong, s.left, s.right, s.period, ScanOptions{});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "calib.yml");
    EXPECT_EQ(e.where().field, "image_size");
    EXPECT_NE(std::string(e.what()).find("right calibration is 1280x512 but the right images are 640x512"),
              std::string::npos)
        << e.what();
  }
}

// The real capture: the bust reconstructs densely, and the local surface-fit noise agrees with
// the noise the decoder's sigma predicts.
TEST(ScanPipeline, SlmasterBinocularReconstructs) {
  // The manifest with its paths pointed at RAMTK_SHARED_DIR.
  FringeManifest m;
  if (!testing::SlmasterManifest(&m)) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const std::string dir = std::string(RAMTK_TEST_OUTPUT_DIR) + "/slmaster_scan";
  std::filesystem::create_directories(dir);
  WriteFringeManifest(dir + "/manifest.json", m);
  ScanOptions o;
  o.fit_spheres = false;  // no ball in this capture (a bust)
  o.match.min_depth_mm = 300;
  o.match.max_depth_mm = 1500;
  const ScanResult r = ScanFringeSet(dir + "/manifest.json", o);
  const LocalFitNoise noise = MeasureLocalFitNoise(r.cloud, cv::Size(r.summary.width, r.summary.height), 7);
  std::cout << r.summary.match.BriefReport() << "\n"
            << r.summary.triangulation.BriefReport() << "\nlocal fit: " << noise.patches << " patches, median RMS "
            << noise.median_rms_mm * 1000 << " um, predicted " << noise.median_predicted_mm * 1000 << " um, ratio "
            << noise.ratio << "\n";
  RecordProperty("points", std::to_string(r.cloud.size()));
  RecordProperty("local_fit_rms_um", std::to_string(noise.median_rms_mm * 1000));
  RecordProperty("local_fit_predicted_um", std::to_string(noise.median_predicted_mm * 1000));
  // The decoder finds ~410k valid left pixels (31 %); most of them must match.
  EXPECT_GT(r.summary.match.matched, 0.8 * r.summary.match.left_valid);
  // The bust stands 510..680 mm in front of the cameras (SLMaster's working distance).
  EXPECT_GT(r.summary.triangulation.depth_min_mm, 450);
  EXPECT_LT(r.summary.triangulation.depth_max_mm, 750);
  // Noise: the predicted point sigma is honest. sigma_I is the random part of the sinusoid-fit
  // residual (neighbouring pixels along the fringe, DecodeOptions::noise_from_neighbours): on
  // this capture the whole residual (6.9 DN) is ~99 % projector harmonics, which made sigma 7x
  // too large before (ratio 0.13, docs/scan.md). Issue 16's bound: predicted / observed local
  // quadratic-patch noise within 0.7..1.4 (7 000 patches: the observed median is itself precise to
  // ~1 %; the band is for the quadratic patches' model error, not for sampling).
  EXPECT_GT(noise.patches, 2000);
  EXPECT_GT(1.0 / noise.ratio, 0.7);
  EXPECT_LT(1.0 / noise.ratio, 1.4);

  // The phase filter (DecodeOptions::coordinate_filter) on real data. Its output is a projection
  // of the raw coordinates, so raw − filtered has variance σ_raw² − σ_filtered² for pixel-independent
  // noise. The filter also removes part of this capture's pixel-scale ripple, which its σ
  // conservatively keeps whole, so the observed differences may exceed that (they are ~2× here);
  // they must not fall short of it, which would mean the filter claims more noise removed than
  // it removes. (7 000+ independent patches' worth of points: the RMS is precise to ~1 %.)
  ScanOptions filtered_options = o;
  filtered_options.decode.coordinate_filter.radius_px = 2;
  const ScanResult f = ScanFringeSet(dir + "/manifest.json", filtered_options);
  std::unordered_map<long, std::size_t> raw_index;
  for (std::size_t i = 0; i < r.cloud.size(); ++i)
    raw_index[static_cast<long>(r.cloud.left_pixels[i].y()) * r.summary.width +
              static_cast<long>(r.cloud.left_pixels[i].x())] = i;
  double sum_norm_sq = 0, sum_raw_sigma = 0, sum_filtered_sigma = 0;
  long n = 0;
  for (std::size_t i = 0; i < f.cloud.size(); ++i) {
    const auto it = raw_index.find(static_cast<long>(f.cloud.left_pixels[i].y()) * f.summary.width +
                                   static_cast<long>(f.cloud.left_pixels[i].x()));
    if (it == raw_index.end()) continue;
    const double s_raw = r.cloud.sigma_mm[it->second], s_f = f.cloud.sigma_mm[i];
    if (!(s_raw > s_f)) continue;
    const double d = (f.cloud.points_in_left[i] - r.cloud.points_in_left[it->second]).cast<double>().norm();
    if (!std::isfinite(d) || d > 1.0) continue;  // a different crossing, not noise
    sum_norm_sq += d * d / (s_raw * s_raw - s_f * s_f);
    sum_raw_sigma += s_raw, sum_filtered_sigma += s_f;
    ++n;
  }
  const double normalised = std::sqrt(sum_norm_sq / std::max<long>(n, 1));
  std::cout << "phase filter R=2: " << f.summary.match.BriefReport() << "\n"
            << n << " common points, mean sigma " << 1000 * sum_raw_sigma / n << " -> " << 1000 * sum_filtered_sigma / n
            << " um, RMS((raw - filtered) / sqrt(sigma_raw^2 - sigma_filtered^2)) " << normalised << "\n";
  RecordProperty("phase_filter_points", std::to_string(f.cloud.size()));
  RecordProperty("phase_filter_difference_over_sigma", std::to_string(normalised));
  EXPECT_GT(n, 300000);
  EXPECT_GT(f.summary.match.matched, 0.999 * r.summary.match.matched);
  EXPECT_LT(sum_filtered_sigma, sum_raw_sigma);
  EXPECT_GT(normalised, 0.9);
}

}  // namespace
}  // namespace ramtk::vision
