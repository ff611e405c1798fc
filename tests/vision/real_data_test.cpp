// The real SLMaster binocular capture (shared/data/slmaster-binocular): 12-step phase shift with
// 64 periods and a 7-image complementary Gray code, 1280x1024 BMP. Skipped if absent.
#include <gtest/gtest.h>

#include <filesystem>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {
namespace {

class SlmasterBinocular : public ::testing::TestWithParam<std::string> {};

bool SlmasterPresent() {
  return std::filesystem::exists(std::string(RAMTK_SHARED_DIR) + "/data/slmaster-binocular/L/0.bmp");
}

FringeManifest SlmasterManifest() {
  FringeManifest m = ReadFringeManifest(std::string(RAMTK_DATASETS_DIR) + "/vision/slmaster_binocular.json");
  // The manifest expects the checkout beside shared/; follow RAMTK_SHARED_DIR if it lives elsewhere.
  const std::string rel = "../../../shared";
  for (auto& [name, files] : m.cameras)
    for (std::string& f : files)
      if (!std::filesystem::exists(m.Resolve(f)) && f.rfind(rel, 0) == 0) f = RAMTK_SHARED_DIR + f.substr(rel.size());
  return m;
}

TEST_P(SlmasterBinocular, DecodesWithSmoothCoordinates) {
  if (!SlmasterPresent()) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const std::string camera = GetParam();
  const FringeManifest m = SlmasterManifest();
  const DecodedCamera d = DecodeCamera(m, camera, DecodeOptions{});
  const DecodeSummary& s = d.summary;
  std::cout << s.BriefReport() << "\n";
  RecordProperty("valid_fraction", std::to_string(s.valid_fraction));
  RecordProperty("fit_residual_rms_dn", std::to_string(s.fit_residual_rms_dn));
  RecordProperty("phase_residual_rms_rad", std::to_string(s.phase_residual_rms_rad));
  WriteDecodedCamera(std::string(RAMTK_TEST_OUTPUT_DIR) + "/slmaster", camera, d);

  // The bust fills about a third of the frame; the black background is masked as dark.
  EXPECT_GT(s.valid_fraction, 0.25);
  EXPECT_LT(s.valid_fraction, 0.45);
  EXPECT_EQ(s.saturated, 0);
  // The Gray code must agree with the phase (our layout = SLMaster's): only pixels near code
  // edges need their order corrected.
  EXPECT_LT(s.edge_corrections, 0.05 * s.valid_pixels);
  // No period jumps: horizontally adjacent valid pixels with clearly visible fringes (B at least
  // 2 % of full scale) differ by far less than a period, except at occlusion edges of the bust.
  // The weaker pixels the sigma rule admits lie on the dark limbs and shadow borders, where the
  // surface turns away and the coordinate changes fast: their jumps are counted apart, and their
  // share is bounded (docs/scan.md, "Density on dark, low-modulation surfaces").
  const float strong = static_cast<float>(0.02 * 255);
  long pairs = 0, jumps = 0, weak_pairs = 0, weak_jumps = 0;
  double sum_dx = 0;
  for (int y = 0; y < d.mask.rows; ++y)
    for (int x = 1; x < d.mask.cols; ++x) {
      if (!d.mask.at<uchar>(y, x) || !d.mask.at<uchar>(y, x - 1)) continue;
      const double du = d.coordinate.at<float>(y, x) - d.coordinate.at<float>(y, x - 1);
      const bool weak = d.modulation.at<float>(y, x) < strong || d.modulation.at<float>(y, x - 1) < strong;
      ++(weak ? weak_pairs : pairs);
      sum_dx += du;
      if (std::abs(du) > s.period_px / 2) ++(weak ? weak_jumps : jumps);
    }
  std::cout << camera << ": " << jumps << " jumps > P/2 in " << pairs << " adjacent pairs, mean du/dx "
            << sum_dx / pairs << " projector px per camera px; weak pixels: " << weak_jumps << " in " << weak_pairs
            << " pairs\n";
  EXPECT_LT(jumps, 0.002 * pairs);
  EXPECT_LT(weak_pairs, 0.01 * pairs);
  EXPECT_LT(weak_jumps, 0.25 * weak_pairs);
  EXPECT_GT(sum_dx / pairs, 0.0);  // vertical fringes: the projector column grows left to right
  // A 12-step fit of a good camera: residual well below the modulation.
  EXPECT_LT(s.phase_residual_rms_rad, 0.1);
}

// The projector-nonlinearity fit on a quarter of each band's rows (NonlinearityOptions::
// row_subsample: the default on this capture's ~400 k valid pixels per camera) on real data,
// against the fit on every row (forced): the same decision (no significant ripple on this
// capture), the same coordinates, and first-order coefficients within 5 sigma of the quarter's
// noise, sigma_hp / sqrt(pixels / 2).
TEST_P(SlmasterBinocular, RippleFitOnAQuarterOfTheRowsAgreesWithEveryRow) {
  if (!SlmasterPresent()) GTEST_SKIP() << "shared/data/slmaster-binocular not present";
  const FringeManifest m = SlmasterManifest();
  DecodeOptions every_row, quarter;
  every_row.nonlinearity.row_subsample = 1;
  quarter.nonlinearity.row_subsample_min_pixels = 1000;
  const DecodedCamera a = DecodeCamera(m, GetParam(), every_row), b = DecodeCamera(m, GetParam(), quarter);
  const NonlinearityEstimate &ea = a.summary.nonlinearity, &eb = b.summary.nonlinearity;
  std::cout << "every row: " << ea.BriefReport() << "\nquarter:   " << eb.BriefReport() << "\n";
  ASSERT_EQ(ea.row_subsample, 1);
  ASSERT_EQ(eb.row_subsample, 4);
  EXPECT_EQ(ea.applied, eb.applied);
  EXPECT_FALSE(eb.applied);
  long differ = 0;  // not applied: the coordinates are the same, pixel for pixel
  for (int y = 0; y < a.mask.rows; ++y)
    for (int x = 0; x < a.mask.cols; ++x) {
      const bool va = a.mask.at<uchar>(y, x) != 0, vb = b.mask.at<uchar>(y, x) != 0;
      differ += va != vb || (va && a.coordinate.at<float>(y, x) != b.coordinate.at<float>(y, x));
    }
  EXPECT_EQ(differ, 0);
  const double sigma = eb.residual_rms_before_rad / std::sqrt(eb.pixels_used / 2.0);
  EXPECT_NEAR(eb.sin_rad[0], ea.sin_rad[0], 5 * sigma);
  EXPECT_NEAR(eb.cos_rad[0], ea.cos_rad[0], 5 * sigma);
}

INSTANTIATE_TEST_SUITE_P(BothCameras, SlmasterBinocular, ::testing::Values("left", "right"));

}  // namespace
}  // namespace ramtk::vision
