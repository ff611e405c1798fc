// The projector-nonlinearity correction is applied only when its ripple is significant against
// its own leave-one-band-out scatter (NonlinearityOptions::min_ripple_t2). Truth here is what
// the simulator rendered: a linear projector (no ripple to remove) on the campaign twin's small
// 12-step balls, where the old correction fitted the ball's shape and pushed the apex up to 27 µm
// deep; and a projector gamma on a 4-step set, whose ripple must still be removed.
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/vision/sim/fringe_simulator.h"
#include "scan_sim.h"

namespace ramtk::vision {
namespace {

// The campaign twin's camera windows: the small preset around a ball, resampled by `scale`.
FringeSimulationConfig SmallBall(const Vec3& ball_in_left, double scale, std::uint64_t seed) {
  FringeSimulationConfig c = ScaleCameraWindows(MakeFringePreset("small", ball_in_left), scale);
  c.supersampling = 1;
  c.seed = seed;
  return c;
}

// Linear projector, 12 steps, balls 64 and 128 px across at several positions and noise draws:
// there is no ripple, so the correction must not be applied. Under the null hypothesis the
// test's false-alarm rate is 0.1 %; over these 24 decodes one is already unlikely (2.4 %).
TEST(NonlinearityGate, NoCorrectionOnSmallBallsWithALinearProjector) {
  int applied = 0, decodes = 0;
  double largest_t2 = 0;
  for (double scale : {0.25, 0.5}) {
    for (int k = 0; k < 6; ++k) {
      const Vec3 ball(-30.0 + 12.0 * k, 20.0 - 8.0 * k, 690.0 + 5.0 * k);
      const FringeSimulationConfig c = SmallBall(ball, scale, 100 + k);
      for (int cam = 0; cam < 2; ++cam) {
        const DecodedCamera d = testing::DecodeSimulated(c, SimulateCamera(c, cam));
        const NonlinearityEstimate& nl = d.summary.nonlinearity;
        applied += nl.applied;
        ++decodes;
        largest_t2 = std::max(largest_t2, nl.ripple_t2);
        EXPECT_FALSE(nl.applied) << "scale " << scale << " ball " << k << " camera " << cam << ": " << nl.BriefReport();
      }
    }
  }
  RecordProperty("largest_t2", std::to_string(largest_t2));
  EXPECT_EQ(applied, 0) << "of " << decodes;
}

// A projector gamma of 2.2 on a 4-step set of the same small ball: a real ripple (RippleOfGamma)
// that the gate must let through.
TEST(NonlinearityGate, GammaRippleOnASmallBallIsStillCorrected) {
  FringeSimulationConfig c = SmallBall(Vec3(0, 0, 700), 0.5, 7);
  c.sequence = {PhaseShiftBlock(4, 64.0), GrayCodeBlock(7, true)};
  c.effects.projector_nonlinearity = 2.2;
  const DecodedCamera d = testing::DecodeSimulated(c, SimulateCamera(c, 0));
  const NonlinearityEstimate& nl = d.summary.nonlinearity;
  EXPECT_TRUE(nl.applied) << nl.BriefReport();
  EXPECT_GT(nl.ripple_t2, 25.2) << nl.BriefReport();
}

// The test's first-order fit (FirstOrderRippleGate) only decides: a significant ripple is then
// fitted with every order from the start. The same gamma set decoded without the test
// (min_ripple_t2 = 0, every order fitted and applied) gives the same T², coefficients and
// coordinates. "The same" up to rounding: the fit's sums are a parallel reduction whose grouping
// varies from run to run, so coefficients agree to 1e-12 rad (of ~1e-4..1e-1) and coordinates
// to 1e-5 projector px (float rounding is ~3e-5 px at 500 px; the match sigma ~0.02 px).
TEST(NonlinearityGate, ASignificantRippleGetsTheSameFitAsWithoutTheTest) {
  FringeSimulationConfig c = SmallBall(Vec3(0, 0, 700), 0.5, 7);
  c.sequence = {PhaseShiftBlock(4, 64.0), GrayCodeBlock(7, true)};
  c.effects.projector_nonlinearity = 2.2;
  const SimulatedCamera sim = SimulateCamera(c, 0);
  DecodeOptions untested;
  untested.nonlinearity.min_ripple_t2 = 0;
  const DecodedCamera gated = testing::DecodeSimulated(c, sim);
  const DecodedCamera full = testing::DecodeSimulated(c, sim, untested);
  const NonlinearityEstimate &g = gated.summary.nonlinearity, &f = full.summary.nonlinearity;
  ASSERT_TRUE(g.applied) << g.BriefReport();
  ASSERT_TRUE(f.applied) << f.BriefReport();
  EXPECT_NEAR(g.ripple_t2, f.ripple_t2, 1e-9 * f.ripple_t2);  // the all-order fit's first pass
  EXPECT_GT(g.ripple_t2, 25.2);
  for (std::size_t k = 0; k < g.sin_rad.size(); ++k) {
    EXPECT_NEAR(g.sin_rad[k], f.sin_rad[k], 1e-12) << "order " << k + 1;
    EXPECT_NEAR(g.cos_rad[k], f.cos_rad[k], 1e-12) << "order " << k + 1;
  }
  ASSERT_EQ(gated.coordinate.size(), full.coordinate.size());
  long differ = 0, valid = 0;
  for (int y = 0; y < gated.coordinate.rows; ++y)
    for (int x = 0; x < gated.coordinate.cols; ++x) {
      const float a = gated.coordinate.at<float>(y, x), b = full.coordinate.at<float>(y, x);
      if (std::isnan(a) && std::isnan(b)) continue;
      ++valid;
      differ += !(std::abs(a - b) <= 1e-5f);
    }
  EXPECT_GT(valid, 1000);
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace ramtk::vision
