// The fringe diagnosis against hidden effects rendered by the vision simulator: the named cause must
// be the hidden one ("none" for clean sets and for effects the ideal intensity model cannot see),
// and an extension must remove at least half of the excess on held-out tiles. Parameter estimates
// are checked against the simulator's truth and closed forms.
#include "ramtk/diagnose/fringe/fringe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include "ramtk/core/error.h"
#include "ramtk/diagnose/fringe/fringe_hidden.h"
#include "ramtk/vision/decode/nonlinearity.h"

namespace ramtk::diagnose {
namespace {

Diagnosis DiagnoseSet(const HiddenFringeSet& set, const std::string& out = "") {
  DiagnoseOptions o;
  o.seed = set.draw.seed;
  o.output_folder = out;
  return DiagnoseFringeFrames(set.manifest, set.frames, set.full_scale, o, "draw");
}

// The issue-15 rule: a named cause is right if it is the truth, or `ambiguous` with the truth in a
// look-alike set of at most two.
bool NamesOrAmbiguousWith(const Diagnosis& d, const std::string& effect) {
  if (d.cause == effect) return true;
  return d.cause == kAmbiguous && d.look_alikes.size() <= 2 &&
         std::find(d.look_alikes.begin(), d.look_alikes.end(), effect) != d.look_alikes.end();
}

// A candidate's own fit (its parameters whether or not it was the one named).
const CandidateFit& Candidate(const Diagnosis& d, const std::string& effect) {
  for (const CandidateFit& c : d.candidates)
    if (c.effect == effect) return c;
  throw std::runtime_error("no candidate " + effect);
}

// Fixed seeds: the first two draws of every effect from seed 1 on, and the first three clean ones.
std::vector<std::uint64_t> Seeds() {
  std::map<std::string, int> taken;
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t s = 1; s < 400; ++s) {
    const HiddenFringeDraw d = DrawHiddenFringeEffect(s);
    if (taken[d.effect] < (d.effect == "none" ? 3 : 2)) ++taken[d.effect], seeds.push_back(s);
  }
  return seeds;
}

class FringeHiddenDraw : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(FringeHiddenDraw, NamesTheHiddenCause) {
  const HiddenFringeSet set = SimulateHiddenFringe(DrawHiddenFringeEffect(GetParam()));
  const Diagnosis d = DiagnoseSet(set);
  SCOPED_TRACE(set.draw.effect + " " + std::to_string(set.draw.magnitude) + ": " + d.cause);
  EXPECT_TRUE(NamesOrAmbiguousWith(d, set.draw.expected));
  // The noise floor of 8-bit simulated images (shot noise of 10000 e- full well, quantisation)
  // is about 1.2 DN; the data-driven estimate must land there.
  EXPECT_GT(d.noise_floor_rms, 0.9);
  EXPECT_LT(d.noise_floor_rms, 1.8);
  if (set.draw.expected != "none") {
    EXPECT_GE(d.excess_removed, 0.5);
    EXPECT_LT(d.rms_after, d.rms_before);
  } else {
    EXPECT_LT(d.residual_rms, 1.1 * d.noise_floor_rms);  // clean: white at the floor
  }
}

INSTANTIATE_TEST_SUITE_P(Draws, FringeHiddenDraw, ::testing::ValuesIn(Seeds()));

// Clean sets with only read + photon shot noise at camera gains 1, 4 and 16 (full well 10000,
// 2500, 625 e−): the variance grows with intensity, up to ~80 DN² at the bright end for gain 16,
// and the dark end (no black offset) clips noisy samples at 0.
// The diagnosis must say "none", and the noise-level function must recover the simulator's shot
// term b = 255/full well DN per electron (the per-pixel fit's loss of degrees of freedom and the
// Gray frames' extra variance scale it by less than ±15 %, the renderer's 2×2 supersampling does
// not touch the noise).
class FringeShotNoise : public ::testing::TestWithParam<std::tuple<double, std::uint64_t>> {};

TEST_P(FringeShotNoise, PhotonNoiseAloneIsNone) {
  HiddenFringeDraw draw;
  draw.camera_gain = std::get<0>(GetParam());
  draw.seed = std::get<1>(GetParam());
  const HiddenFringeSet set = SimulateHiddenFringe(draw);
  const Diagnosis d = DiagnoseSet(set);
  SCOPED_TRACE("gain " + std::to_string(draw.camera_gain));
  EXPECT_EQ(d.cause, "none");
  const double b_true = 255.0 / (10000.0 / draw.camera_gain);
  ASSERT_TRUE(d.noise_model.count("b_DN"));
  EXPECT_NEAR(d.noise_model.at("b_DN"), b_true, 0.15 * b_true + 3 * d.noise_model_sigmas.at("b_DN"));
  EXPECT_EQ(d.noise_model.at("c"), 0.0);  // Poisson–Gaussian: no I² term claimed
}

INSTANTIATE_TEST_SUITE_P(Gains, FringeShotNoise,
                         ::testing::Values(std::make_tuple(1.0, 501ull), std::make_tuple(4.0, 502ull),
                                           std::make_tuple(16.0, 503ull)));

TEST(FringeDiagnosis, SeedListCoversEveryEffect) {
  std::set<std::string> effects;
  for (std::uint64_t s : Seeds()) effects.insert(DrawHiddenFringeEffect(s).effect);
  const std::vector<std::string> drawn = DrawnFringeEffects();
  std::set<std::string> expected(drawn.begin(), drawn.end());
  expected.insert("none");
  EXPECT_EQ(effects, expected);
}

TEST(FringeDiagnosis, HarmonicsOfAProjectorGammaMatchTheClosedForm) {
  HiddenFringeDraw draw;
  draw.seed = 7, draw.effect = draw.expected = "projector_nonlinearity", draw.magnitude = 1.8;
  const Diagnosis d = DiagnoseSet(SimulateHiddenFringe(draw));
  ASSERT_EQ(d.cause, "projector_nonlinearity");
  // B2/B1 of (0.5 + 0.5 cos)^1.8; the noise gives sigmas of ~1e-4, the 2x2 supersampling and the
  // box footprint a few 1e-3.
  EXPECT_NEAR(d.parameters.at("B2/B1"), vision::SecondHarmonicOfGamma(1.8), 0.01);
}

TEST(FringeDiagnosis, PhaseStepErrorsMatchTheRenderedOnes) {
  HiddenFringeDraw draw;
  draw.seed = 11, draw.effect = draw.expected = "phase_shift_error", draw.magnitude = 3.0;
  const HiddenFringeSet set = SimulateHiddenFringe(draw);
  const Diagnosis d = DiagnoseSet(set);
  ASSERT_EQ(d.cause, "phase_shift_error");
  // A common shift of all steps is absorbed by the per-pixel phase: compare about the mean.
  const int n = 12;
  const double mean_truth = std::accumulate(set.shift_errors_deg.begin(), set.shift_errors_deg.begin() + n, 0.0) / n;
  double mean_est = 0;
  for (int k = 0; k < n; ++k)
    mean_est += d.parameters.at("step_" + std::string(k < 10 ? "0" : "") + std::to_string(k) + "_error_deg") / n;
  for (int k = 0; k < n; ++k) {
    const std::string key = "step_" + std::string(k < 10 ? "0" : "") + std::to_string(k) + "_error_deg";
    EXPECT_NEAR(d.parameters.at(key) - mean_est, set.shift_errors_deg[k] - mean_truth, 0.25) << key;
  }
}

TEST(FringeDiagnosis, CameraDefocusSigmaMatchesTheRenderedBlur) {
  HiddenFringeDraw draw;
  draw.seed = 13, draw.effect = draw.expected = "camera_defocus", draw.magnitude = 1.5;
  const Diagnosis d = DiagnoseSet(SimulateHiddenFringe(draw), std::string(RAMTK_TEST_OUTPUT_DIR) + "/fringe_defocus");
  // At 1.5 camera px on this view the edges spread by ~0.4 projector px, hardly varying across the
  // ball: the projector's blur is a look-alike, and `ambiguous` with both is an allowed verdict.
  ASSERT_TRUE(NamesOrAmbiguousWith(d, "camera_defocus")) << d.cause;
  EXPECT_NEAR(Candidate(d, "camera_defocus").parameters.at("blur_sigma_px"), 1.5, 0.3);
  ASSERT_EQ(d.pictures.size(), 4u);
  for (const Picture& p : d.pictures)
    EXPECT_TRUE(std::filesystem::exists(std::string(RAMTK_TEST_OUTPUT_DIR) + "/fringe_defocus/" + p.file)) << p.file;
}

TEST(FringeDiagnosis, ProjectorDefocusIsNamedApartFromCameraBlurWithItsSigma) {
  // A projector blur of 1.0 projector px (~1.9 camera px on this view): the code edges spread by
  // the same width in projector px everywhere, unlike a camera blur whose width in projector px
  // follows the foreshortening across the ball. Same 0.3 px tolerance as the camera blur.
  HiddenFringeDraw draw;
  draw.seed = 19, draw.effect = draw.expected = "defocus", draw.magnitude = 1.0;
  const Diagnosis d = DiagnoseSet(SimulateHiddenFringe(draw));
  ASSERT_TRUE(NamesOrAmbiguousWith(d, "defocus")) << d.cause;
  EXPECT_NEAR(Candidate(d, "defocus").parameters.at("blur_sigma_projector_px"), 1.0, 0.3);
  EXPECT_GE(d.excess_removed, 0.5);
}

TEST(FringeDiagnosis, SoftKneeIsNamedWithTheRenderedKnee) {
  // The simulator's knee is the algebraic soft clip at 30 % of full scale; the candidate's grid
  // steps 0.05 in the knee, so the estimate must land within one step.
  HiddenFringeDraw draw;
  draw.seed = 17, draw.effect = draw.expected = "soft_knee_response", draw.magnitude = 0.3;
  const Diagnosis d = DiagnoseSet(SimulateHiddenFringe(draw));
  ASSERT_TRUE(NamesOrAmbiguousWith(d, "soft_knee_response")) << d.cause;
  EXPECT_NEAR(Candidate(d, "soft_knee_response").parameters.at("knee_fraction"), 0.3, 0.05 + 1e-9);
  EXPECT_EQ(Candidate(d, "soft_knee_response").parameters.at("knee_shape_algebraic"), 1.0);
  EXPECT_GE(d.excess_removed, 0.5);
}

TEST(FringeDiagnosis, RejectsASequenceWithoutGrayCode) {
  HiddenFringeSet set = SimulateHiddenFringe(DrawHiddenFringeEffect(1));
  set.manifest.sequence.pop_back();
  set.frames.resize(12);
  EXPECT_THROW(DiagnoseSet(set), InputError);
}

}  // namespace
}  // namespace ramtk::diagnose
