// Baselines: closed-form (noiseless) cases against the simulated truth.
#include "ramtk/tcf/baselines.h"

#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/core/units.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::tcf {
namespace {

Isometry3 Tool() {
  Isometry3 t = Isometry3::Identity();
  t.linear() = FiveDofRotation(DegToRad(30.0), DegToRad(3.0));
  t.translation() = Vec3(3.0, -2.0, 150.5);
  return t;
}

TEST(Baselines, FourAndSevenPointAreExactWithoutNoise) {
  TouchUpSimulationOptions o;
  o.repeatability_mm = 0.0;
  o.touch_sigma_mm = 0.0;
  o.align_sigma_deg = 0.0;
  const BaselineResult four = SimulateFourPoint(Tool(), o);
  EXPECT_LT((four.tcp_in_flange - Tool().translation()).norm(), 1e-8);
  EXPECT_LT(four.residual_rms_mm, 1e-8);
  const BaselineResult seven = SimulateSevenPoint(Tool(), o);
  EXPECT_LT((seven.axis_in_flange - Tool().linear().col(2)).norm(), 1e-9);
}

TEST(Baselines, SevenPointAxisErrorIsTheOperatorsAlignment) {
  TouchUpSimulationOptions o;
  o.repeatability_mm = 0.0;
  o.touch_sigma_mm = 0.0;
  o.align_sigma_deg = 0.5;
  double ss = 0.0;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    o.seed = 100 + i;
    const BaselineResult r = SimulateSevenPoint(Tool(), o);
    const double a = std::acos(std::clamp(r.axis_in_flange.dot(Tool().linear().col(2)), -1.0, 1.0));
    ss += a * a;
  }
  // Tilt of Z from two of three Gaussian components: RMS = sqrt(2)·σ (±15 % for 200 samples).
  EXPECT_NEAR(RadToDeg(std::sqrt(ss / n)), std::sqrt(2.0) * 0.5, 0.15 * std::sqrt(2.0) * 0.5);
}

TEST(Baselines, ParallelLaserIsExactWithoutNoiseAndWidth) {
  ParallelLaserSimulationOptions o;
  o.repeatability_mm = 0.0;
  o.timing_jitter_s = 0.0;
  const BaselineResult r = SimulateParallelLaser(Tool(), o);
  EXPECT_LT((r.axis_in_flange - Tool().linear().col(2)).norm(), 1e-6);
  // Eq. (4-7) puts the apex on the beam line; with the 3° tilted ball-nosed tip (not re-oriented,
  // see baselines.h) the ball touches first, r (1 − cos θ) = 2.5 · 0.00137 = 0.0034 mm higher.
  const double bias = 2.5 * (1.0 - std::cos(DegToRad(3.0)));
  EXPECT_NEAR((r.tcp_in_flange - Tool().translation()).norm(), bias, 0.5 * bias);
}

}  // namespace
}  // namespace ramtk::tcf
