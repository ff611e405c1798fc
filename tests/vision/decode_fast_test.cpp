// The fused decode path (default) against the reference decode (the test hook
// detail::DecodeTestHooks::reference_path, decode_reference.cpp) on simulated sets: phase within
// 1e-4 rad, the same mask and matches, ball centres within 0.1 um. Neither path produced the data:
// the stereo set comes from the fringe simulator, the single-camera sets from the analytic
// synthesiser.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "decode_synth.h"
#include "ramtk/core/error.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/scan/scan.h"
#include "scan_sim.h"
#include "test_hooks_scope.h"

namespace ramtk::vision {
namespace {

constexpr double kPhaseTol = 1e-4;  // rad (issue 13)

struct Diff {
  long mask_differs = 0, valid = 0;
  double wrapped = 0, coordinate_rad = 0, sigma_rel = 0;
};

// Largest differences over the pixels valid in both.
Diff Compare(const DecodedCamera& a, const DecodedCamera& b) {
  Diff d;
  const double to_rad = 2 * CV_PI / a.summary.period_px;
  for (int y = 0; y < a.mask.rows; ++y)
    for (int x = 0; x < a.mask.cols; ++x) {
      const bool va = a.mask.at<uchar>(y, x) != 0, vb = b.mask.at<uchar>(y, x) != 0;
      if (va != vb) ++d.mask_differs;
      if (!va || !vb) continue;
      ++d.valid;
      d.wrapped = std::max(d.wrapped,
                           std::abs(std::remainder(a.wrapped.at<float>(y, x) - b.wrapped.at<float>(y, x), 2 * CV_PI)));
      d.coordinate_rad =
          std::max(d.coordinate_rad, to_rad * std::abs(a.coordinate.at<float>(y, x) - b.coordinate.at<float>(y, x)));
      const double sa = a.sigma_coordinate.at<float>(y, x), sb = b.sigma_coordinate.at<float>(y, x);
      d.sigma_rel = std::max(d.sigma_rel, std::abs(sa - sb) / sb);
    }
  return d;
}

void ExpectSameDecode(const DecodedCamera& fast, const DecodedCamera& ref, const char* what) {
  const Diff d = Compare(fast, ref);
  SCOPED_TRACE(what);
  EXPECT_GT(d.valid, 1000);
  EXPECT_EQ(d.mask_differs, 0);
  EXPECT_LT(d.wrapped, kPhaseTol);
  EXPECT_LT(d.coordinate_rad, kPhaseTol);
  // sigma_I is the fit residual RMS over all valid pixels: float vs double sums, ~1e-6.
  EXPECT_LT(d.sigma_rel, 1e-4);
  EXPECT_EQ(fast.summary.valid_pixels, ref.summary.valid_pixels);
  EXPECT_EQ(fast.summary.low_modulation, ref.summary.low_modulation);
  EXPECT_EQ(fast.summary.saturated, ref.summary.saturated);
  EXPECT_EQ(fast.summary.unwrap_rejected, ref.summary.unwrap_rejected);
  EXPECT_NEAR(fast.summary.sigma_intensity_dn, ref.summary.sigma_intensity_dn, 1e-4 * ref.summary.sigma_intensity_dn);
  EXPECT_NEAR(fast.summary.median_modulation_dn, ref.summary.median_modulation_dn,
              1e-6 * ref.summary.median_modulation_dn);
  EXPECT_NEAR(fast.summary.median_sigma_phase_rad, ref.summary.median_sigma_phase_rad,
              1e-4 * ref.summary.median_sigma_phase_rad);
  const NonlinearityEstimate &nf = fast.summary.nonlinearity, &nr = ref.summary.nonlinearity;
  EXPECT_EQ(nf.applied, nr.applied);
  EXPECT_EQ(nf.window_px, nr.window_px);
  EXPECT_EQ(nf.pixels_used, nr.pixels_used);
  ASSERT_EQ(nf.sin_rad.size(), nr.sin_rad.size());
  for (std::size_t i = 0; i < nf.sin_rad.size(); ++i) {
    EXPECT_NEAR(nf.sin_rad[i], nr.sin_rad[i], 1e-6);
    EXPECT_NEAR(nf.cos_rad[i], nr.cos_rad[i], 1e-6);
  }
}

// The small preset with a 4-step + 7-bit complementary Gray sequence (8-bit) and a projector
// gamma, so the nonlinearity correction is active; the fast path reads the 8-bit frames as
// rendered, the reference path float copies.
TEST(DecodeFast, StereoSetSameDecodeMatchesAndCentreAsTheReferencePath) {
  FringeSimulationConfig c = MakeFringePreset("small");
  c.seed = 11;
  c.sequence = {PhaseShiftBlock(4, 64.0), GrayCodeBlock(7, true)};
  c.effects.projector_nonlinearity = 1.3;
  c.supersampling = 1;  // speed; the comparison does not need the antialiased edges
  const SimulatedCamera left = SimulateCamera(c, 0), right = SimulateCamera(c, 1);
  const DecodeOptions ref_opt;
  const DecodedCamera lr = testing::WithReferenceDecode(true, [&] { return testing::DecodeSimulated(c, left, ref_opt); });
  const DecodedCamera rr = testing::WithReferenceDecode(true, [&] { return testing::DecodeSimulated(c, right, ref_opt); });
  const FringeManifest m = testing::ManifestForConfig(c);
  const double fs = (1 << c.sensor.bits) - 1.0;
  ASSERT_EQ(left.images[0].depth(), CV_8U);
  const DecodedCamera lf = DecodeFrames(m, left.images, fs, DecodeOptions{});
  const DecodedCamera rf = DecodeFrames(m, right.images, fs, DecodeOptions{});
  ExpectSameDecode(lf, lr, "left");
  ExpectSameDecode(rf, rr, "right");
  EXPECT_TRUE(lf.summary.nonlinearity.applied) << lf.summary.BriefReport();
  std::cout << "left: " << lf.summary.nonlinearity.BriefReport() << "\n";
  EXPECT_GT(std::abs(lr.summary.nonlinearity.sin_rad[0]), 1e-3) << lr.summary.BriefReport();  // a ripple to remove

  const StereoCalibration calib = WrittenCalibration(c);
  const ScanResult sf = ScanDecoded(calib, lf, rf, lf.summary.period_px, ScanOptions{});
  const ScanResult sr = ScanDecoded(calib, lr, rr, lr.summary.period_px, ScanOptions{});
  EXPECT_EQ(sf.summary.match.matched, sr.summary.match.matched);
  EXPECT_EQ(sf.summary.triangulation.points, sr.summary.triangulation.points);
  ASSERT_EQ(sf.summary.spheres.spheres.size(), 1u) << sf.summary.BriefReport() << "\n"
                                                   << sf.summary.match.BriefReport();
  ASSERT_EQ(sr.summary.spheres.spheres.size(), 1u) << sr.summary.BriefReport();
  const Vec3 dc = sf.summary.spheres.spheres[0].centre_mm - sr.summary.spheres.spheres[0].centre_mm;
  EXPECT_LT(dc.norm(), 1e-4) << "centre moved by " << 1000 * dc.norm() << " um";
}

// 16-bit samples: the SLMaster sequence (12-step + complementary Gray), a plain Gray code and a
// three-frequency heterodyne set, on the analytic synthesiser's frames with a projector gamma.
TEST(DecodeFast, SixteenBitGrayAndHeterodyneSetsAsTheReferencePath) {
  testing::SynthOptions o;
  o.gamma = 2.0;
  o.noise_dn = 1.0;
  const std::vector<FringeManifest> sets = {testing::GrayManifest(12, 64, true), testing::GrayManifest(4, 32, false),
                                            testing::HeterodyneManifest(5, {64, 59, 55})};
  for (const FringeManifest& m : sets) {
    const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
    const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
    std::vector<cv::Mat> as16(frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) frames[i].convertTo(as16[i], CV_16U, 257.0);  // 8 -> 16 bit
    // The nonlinearity fit on every row, and on a quarter of each band's rows (what a
    // frame of >= 400 k valid pixels gets by default; here forced by a low pixel floor).
    for (const long floor : {500000L, 1000L}) {
      DecodeOptions fast_opt;
      fast_opt.nonlinearity.row_subsample_min_pixels = floor;
      const DecodedCamera ref =
          testing::WithReferenceDecode(true, [&] { return DecodeFrames(m, as16, 65535.0, fast_opt, "cam"); });
      const DecodedCamera fast = DecodeFrames(m, as16, 65535.0, fast_opt, "cam");
      EXPECT_EQ(fast.summary.nonlinearity.row_subsample, floor == 1000 ? 4 : 1);
      ExpectSameDecode(fast, ref,
                       (std::to_string(m.sequence[0].steps) + "-step " +
                        (m.sequence[0].type == BlockType::kHeterodyne ? "heterodyne" : "gray") + ", rows 1/" +
                        std::to_string(fast.summary.nonlinearity.row_subsample))
                           .c_str());
    }
  }
}

// 8-bit frames whose width is not a multiple of eight: the fused decode sums eight pixels at once
// over the frames (OpenCV universal intrinsics) and the last columns one by one. Both against
// the reference path, on a 12-step Gray set and a 4-step complementary one.
TEST(DecodeFast, EightBitFramesOfAnOddWidthAsTheReferencePath) {
  testing::SynthOptions o;
  o.width = 403;
  o.gamma = 2.0;
  o.noise_dn = 1.0;
  for (const FringeManifest& m : {testing::GrayManifest(12, 64, true), testing::GrayManifest(4, 32, false)}) {
    const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
    std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
    for (cv::Mat& f : frames) f.convertTo(f, CV_8U);  // rounded, as an 8-bit camera gives them
    const DecodedCamera ref =
        testing::WithReferenceDecode(true, [&] { return DecodeFrames(m, frames, 255.0, DecodeOptions{}, "cam"); });
    const DecodedCamera fast = DecodeFrames(m, frames, 255.0, DecodeOptions{}, "cam");
    ExpectSameDecode(fast, ref, (std::to_string(m.sequence[0].steps) + "-step, 403 px wide").c_str());
    // The last three columns (the one-by-one tail) hold valid pixels too.
    EXPECT_GT(cv::countNonZero(fast.mask.colRange(400, 403)), 100);
  }
}

// The ripple fitted on a quarter of the rows (NonlinearityOptions::row_subsample) against the
// fit on every row, for a 4-step set with projector gamma 2.2 (a first-order ripple of ~0.1
// rad): the coefficients agree within their noise, sigma_hp / sqrt(pixels / 2) for a sine basis
// of variance 1/2 (5 sigma of the subsample's fit), and the test still finds the ripple.
TEST(DecodeFast, RippleFromAQuarterOfTheRowsAgreesWithEveryRow) {
  testing::SynthOptions o;
  o.gamma = 2.2;
  o.noise_dn = 1.0;
  o.blur_px = 0.3;
  const FringeManifest m = testing::GrayManifest(4, 32, true);
  const cv::Mat truth = testing::TruthCoordinate(o, m.Extent());
  const std::vector<cv::Mat> frames = testing::SynthesizeFrames(m, truth, o);
  NonlinearityEstimate est[2];
  for (int i = 0; i < 2; ++i) {
    DecodeOptions opt;
    opt.nonlinearity.row_subsample_min_pixels = i == 0 ? 0 : 1000;
    opt.nonlinearity.row_subsample = i == 0 ? 1 : 4;
    est[i] = DecodeFrames(m, frames, 255.0, opt, "cam").summary.nonlinearity;
    EXPECT_TRUE(est[i].applied) << est[i].BriefReport();
    EXPECT_GT(est[i].ripple_t2, 25.2) << est[i].BriefReport();
  }
  EXPECT_EQ(est[0].row_subsample, 1);
  EXPECT_EQ(est[1].row_subsample, 4);
  // A quarter of each band's rows, rounded up: at most one row more per band (16 bands, 300 rows).
  const double fraction = static_cast<double>(est[1].pixels_used) / est[0].pixels_used;
  EXPECT_GT(fraction, 0.24);
  EXPECT_LT(fraction, 0.26 + 16.0 / o.height);
  const double sigma = est[1].residual_rms_before_rad / std::sqrt(est[1].pixels_used / 2.0);
  EXPECT_GT(std::abs(est[0].sin_rad[0]), 20 * sigma) << est[0].BriefReport();  // a ripple well above the noise
  // Against the synthesiser's truth: the quarter's ripple converts back to the projector's
  // gamma 2.2 as closely as the every-row fit does in Gamma.* (N = 4: within 0.2).
  EXPECT_NEAR(est[1].equivalent_gamma, o.gamma, 0.2) << est[1].BriefReport();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(est[1].sin_rad[k], est[0].sin_rad[k], 5 * sigma) << "order " << k + 1;
    EXPECT_NEAR(est[1].cos_rad[k], est[0].cos_rad[k], 5 * sigma) << "order " << k + 1;
    std::cout << "order " << k + 1 << ": every row (" << est[0].sin_rad[k] << ", " << est[0].cos_rad[k]
              << ") rad, a quarter (" << est[1].sin_rad[k] << ", " << est[1].cos_rad[k] << "), sigma " << sigma << "\n";
  }
}

// The decode's own check for a dark set (frames given in memory, not through the loader, which
// has its own): all frames dark is an error naming the camera; dark phase-shift frames beside a
// bright Gray-code frame are not (the set is decoded, every pixel masked as dark), on both paths.
TEST(DecodeFast, DarkSetIsAnErrorOnlyWhenEveryFrameIsDark) {
  const FringeManifest m = testing::GrayManifest(12, 64, true);
  const std::size_t count = static_cast<std::size_t>(m.sequence[0].steps) + m.sequence[1].ImageCount();
  std::vector<cv::Mat> dark(count, cv::Mat(24, 40, CV_8U, cv::Scalar(2)));
  for (const bool reference : {false, true}) {
    const detail::ScopedDecodeTestHooks scope(testing::ReferenceDecodeHooks(reference));
    DecodeOptions o;
    try {
      (void)DecodeFrames(m, dark, 255.0, o, "cam");
      ADD_FAILURE() << "an all-dark set decoded (reference path " << reference << ")";
    } catch (const ramtk::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("all images are dark"), std::string::npos) << e.what();
    }
    std::vector<cv::Mat> gray_bright = dark;
    gray_bright.back() = cv::Mat(24, 40, CV_8U, cv::Scalar(200));
    const DecodedCamera d = DecodeFrames(m, gray_bright, 255.0, o, "cam");
    EXPECT_EQ(d.summary.valid_pixels, 0);
    EXPECT_EQ(d.summary.dark, 24 * 40);
  }
}

}  // namespace
}  // namespace ramtk::vision
