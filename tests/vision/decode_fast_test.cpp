// The fused decode path (default) against the reference path (DecodeOptions::reference_path, the
// pre-issue-13 implementation) on simulated sets: phase within 1e-4 rad, the same mask and
// matches, ball centres within 0.1 um (issue 13). Neither path produced the data: the stereo set
// comes from the fringe simulator, the single-camera sets from the analytic synthesiser.
#include <gtest/gtest.h>

#include <iostream>

#include <cmath>

#include "decode_synth.h"
#include "ramtk/vision/decode.h"
#include "ramtk/vision/scan.h"
#include "scan_sim.h"

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
      d.wrapped = std::max(
          d.wrapped, std::abs(std::remainder(a.wrapped.at<float>(y, x) - b.wrapped.at<float>(y, x), 2 * CV_PI)));
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
  DecodeOptions ref_opt;
  ref_opt.reference_path = true;
  const DecodedCamera lr = testing::DecodeSimulated(c, left, ref_opt), rr = testing::DecodeSimulated(c, right, ref_opt);
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
  ASSERT_EQ(sf.summary.spheres.spheres.size(), 1u) << sf.summary.BriefReport() << "\n" << sf.summary.match.BriefReport();
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
    DecodeOptions ref_opt;
    ref_opt.reference_path = true;
    const DecodedCamera ref = DecodeFrames(m, as16, 65535.0, ref_opt, "cam");
    const DecodedCamera fast = DecodeFrames(m, as16, 65535.0, DecodeOptions{}, "cam");
    ExpectSameDecode(fast, ref, (std::to_string(m.sequence[0].steps) + "-step " +
                                 (m.sequence[0].type == BlockType::kHeterodyne ? "heterodyne" : "gray")).c_str());
  }
}

}  // namespace
}  // namespace ramtk::vision
