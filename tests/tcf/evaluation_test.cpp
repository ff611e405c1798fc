// Accuracy against the simulator's truth over fixed seeds. Tolerances from the noise: at 0.03 mm
// repeatability (1σ per axis per segment) the solver's own first-order prediction is ~0.045 mm.
#include "ramtk/tcf/evaluation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ramtk::tcf {
namespace {

const MethodAccuracy& Row(const std::vector<MethodAccuracy>& rows, TcfMethod m) {
  for (const MethodAccuracy& r : rows)
    if (r.method == m) return r;
  throw std::runtime_error("missing row");
}

TEST(Evaluation, CrossLaserMeetsTheTargetAtRepeatability003) {
  EvaluationOptions o;
  o.runs = 30;
  o.simulation.repeatability_mm = 0.03;
  o.methods = {TcfMethod::kCrossLaser, TcfMethod::kParallelLaser, TcfMethod::kFourPoint};
  const auto rows = EvaluateMethods(o);
  const MethodAccuracy& x = Row(rows, TcfMethod::kCrossLaser);
  EXPECT_EQ(x.failures, 0);
  EXPECT_LE(x.tcp_rms_mm, 0.05) << FormatAccuracyTable(rows);
  // The propagated 1σ agrees with the observed RMS (30 runs: ±25 %).
  EXPECT_NEAR(x.tcp_rms_mm / x.predicted_tcp_sigma_mm, 1.0, 0.25);
  // The touch-up 4-point method (operator 0.1 mm by eye) is far worse.
  EXPECT_GT(Row(rows, TcfMethod::kFourPoint).tcp_rms_mm, 5 * x.tcp_rms_mm);
}

TEST(Evaluation, SelfCalibrationRemovesLatencyAndBeamOffset) {
  EvaluationOptions o;
  o.runs = 20;
  o.simulation.effects.Enable("trigger_latency");
  o.simulation.effects.Enable("beam_offset");
  o.methods = {TcfMethod::kCrossLaser, TcfMethod::kCrossLaserNoSelfCalibration};
  const auto rows = EvaluateMethods(o);
  const double with = Row(rows, TcfMethod::kCrossLaser).tcp_rms_mm;
  const double without = Row(rows, TcfMethod::kCrossLaserNoSelfCalibration).tcp_rms_mm;
  EXPECT_LE(with, 0.05) << FormatAccuracyTable(rows);
  // Without: latency 8 ms × (20 − 40 mm/s)/2 and half the 0.4 mm offset add ≈ 0.08 mm of bias.
  EXPECT_GT(without, 1.5 * with) << FormatAccuracyTable(rows);
}

TEST(Evaluation, ObliqueCorrectionMattersForAnOffsetTool) {
  EvaluationOptions o;
  o.runs = 10;
  o.simulation.repeatability_mm = 0.0;
  o.simulation.timing_jitter_s = 0.0;
  o.simulation.effects.Enable("beam_non_perpendicular");
  o.methods = {TcfMethod::kThesisCorrected, TcfMethod::kThesisUncorrected};
  const auto rows = EvaluateMethods(o);
  // Noiseless: the uncorrected centre is off by d_x / tan β ≈ 2 mm · 0.0375 along X_s.
  EXPECT_GT(Row(rows, TcfMethod::kThesisUncorrected).axis_rms_deg,
            1.5 * Row(rows, TcfMethod::kThesisCorrected).axis_rms_deg + 0.01)
      << FormatAccuracyTable(rows);
}

}  // namespace
}  // namespace ramtk::tcf

namespace ramtk::tcf {
namespace {

TEST(Evaluation, PredictedUncertaintyFollowsTimingNoise) {
  EvaluationOptions o;
  o.runs = 30;
  o.simulation.repeatability_mm = 0.005;
  o.simulation.timing_jitter_s = 5e-4;
  o.methods = {TcfMethod::kCrossLaser};
  const auto rows = EvaluateMethods(o);
  EXPECT_NEAR(rows[0].tcp_rms_mm / rows[0].predicted_tcp_sigma_mm, 1.0, 0.3) << FormatAccuracyTable(rows);
}

}  // namespace
}  // namespace ramtk::tcf
