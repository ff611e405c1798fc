// The cross-laser solver on simulated data: truth from the simulator, tolerances from the noise.
#include "ramtk/tcf/tcf_solver.h"

#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/tcf/simulator.h"

namespace ramtk::tcf {
namespace {

double AxisErrorDeg(const Vec3& a, const Vec3& b) {
  return RadToDeg(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
}

TcfSimulationOptions Noiseless() {
  TcfSimulationOptions o;
  o.repeatability_mm = 0.0;
  o.timing_jitter_s = 0.0;
  return o;
}

TEST(TcfSolver, NoiselessIdealDeviceIsExact) {
  const TcfSimulation sim = SimulateTcf(Noiseless());
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary s = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_LT((s.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 1e-4) << s.BriefReport();
  EXPECT_LT(AxisErrorDeg(s.solution.axis_in_flange, sim.truth.axis_in_flange), 1e-4);
  EXPECT_NEAR(s.blocking_radius_x_mm, 2.5, 1e-5);
  EXPECT_TRUE(s.converged);
  EXPECT_EQ(s.tip_events_unused, 0);
  EXPECT_LT(s.tip_rms_mm, 1e-4);
  EXPECT_LT(s.circle_rms_mm, 1e-5);
  // The 5-DOF frame equals the truth (no rotation about the axis in the truth).
  EXPECT_LT(RotationAngleBetween(s.solution.flange_from_tcp.linear(), sim.truth.flange_from_tcp.linear()), 1e-6);
}

TEST(TcfSolver, NoiselessWithModelledEffectsIsExact) {
  TcfSimulationOptions o = Noiseless();
  for (const char* e : {"beam_non_perpendicular", "beam_offset", "beam_width", "trigger_latency"})
    ASSERT_TRUE(o.effects.Enable(e));
  const TcfSimulation sim = SimulateTcf(o);
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary s = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_LT((s.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 1e-3) << s.BriefReport();
  EXPECT_LT(AxisErrorDeg(s.solution.axis_in_flange, sim.truth.axis_in_flange), 1e-3);
  EXPECT_NEAR(s.latency_s, o.effects.latency_s, 1e-6);
  EXPECT_NEAR(s.beam_height_difference_mm, o.effects.beam_offset_mm, 1e-3);
  EXPECT_NEAR(s.blocking_radius_x_mm, 2.5 + 0.5 * o.effects.beam_width_mm, 1e-5);
  EXPECT_NEAR(RadToDeg(s.beta_self_calibrated_rad), o.effects.beta_deg, 1e-4);
}

TEST(TcfSolver, RotationAboutTheToolAxisIsInvisible) {
  TcfSimulationOptions o = Noiseless();
  ASSERT_TRUE(o.effects.Enable("tool_axis_rotation"));
  const TcfSimulation sim = SimulateTcf(o);
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary s = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_LT((s.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 1e-4);
  // The frames differ by exactly the spin about the tool's Z.
  const Mat3 diff = s.solution.flange_from_tcp.linear().transpose() * sim.truth.flange_from_tcp.linear();
  EXPECT_LT((diff - RotZ(DegToRad(o.effects.tool_axis_rotation_deg))).norm(), 1e-6);
}

TEST(TcfSolver, EulerAnglesReproduceTheAxis) {
  for (const Vec3& a : {Vec3(0.1, -0.05, 1.0), Vec3(-0.2, 0.3, 0.9), Vec3(0.0, 0.0, 1.0), Vec3(0.05, 0.0, 1.0)}) {
    double psi, theta;
    EulerFromAxis(a, &psi, &theta);
    EXPECT_LT((FiveDofRotation(psi, theta).col(2) - a.normalized()).norm(), 1e-12);
    // The printed eq. (4-13) applied to the printed eq. (4-12) vector, which is −x, −y of the
    // flange-frame axis, gives the same frame: the two sign slips cancel.
    double psi_t, theta_t;
    ThesisEulerFromAxis(Vec3(-a.x(), -a.y(), a.z()), &psi_t, &theta_t);
    if (std::hypot(a.x(), a.y()) > 0) {
      EXPECT_LT((FiveDofRotation(psi_t, theta_t).col(2) - a.normalized()).norm(), 1e-12);
    }
  }
}

TEST(TcfSolver, NonAlternatingEventsAreRejected) {
  const TcfSimulation sim = SimulateTcf(Noiseless());
  std::vector<BeamEvent> ev = sim.events;
  ev.erase(ev.begin() + 1);
  for (std::size_t i = 0; i < ev.size(); ++i) ev[i].line = static_cast<int>(i) + 2;
  try {
    SolveTcf(ev, sim.motion, sim.calibrated_sensor, {}, "log.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("do not alternate"), std::string::npos) << e.what();
    EXPECT_EQ(e.where().file, "log.csv");
    EXPECT_GT(e.where().line, 0);
  }
}

TEST(TcfSolver, ToolAxisBeyondRangeIsRejected) {
  TcfSimulationOptions o = Noiseless();
  o.tool_theta_deg = 12.0;
  o.circle_radius_mm = 16.0;
  const TcfSimulation sim = SimulateTcf(o);
  TcfSolverOptions opt;
  opt.max_axis_tilt_deg = 10.0;
  try {
    SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt, "log.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond the range"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ramtk::tcf

namespace ramtk::tcf {
namespace {

TEST(TcfSolver, BetaSelfCalibrationRecoversFromAWrongCalibratedBeta) {
  TcfSimulationOptions o = Noiseless();
  ASSERT_TRUE(o.effects.Enable("beam_non_perpendicular"));
  TcfSimulation sim = SimulateTcf(o);
  sim.calibrated_sensor.beta_rad = DegToRad(90.0);  // calibration lost β
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary wrong = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  opt.self_calibrate_beta = true;
  const TcfSummary fixed = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_NEAR(RadToDeg(fixed.beta_used_rad), o.effects.beta_deg, 1e-4);
  EXPECT_LT((fixed.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 1e-3);
  // Without it the centre is off by about d_x / tan β (a few hundredths of a mm for this tool).
  EXPECT_GT((wrong.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 0.02);
}

// Issue 15: a β measured from the circle phases that disagrees with the sensor file is reported
// (not silently dropped); a file that agrees gives no warning. Default noise (jitter 20 µs,
// repeatability 0.03 mm) and the default uncertainty options.
TEST(TcfSolver, WarnsWhenTheCirclePhasesContradictTheFilesBeta) {
  TcfSimulationOptions o;
  ASSERT_TRUE(o.effects.Enable("beam_non_perpendicular"));
  o.seed = 4;
  TcfSimulation sim = SimulateTcf(o);
  const TcfSummary agree = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, TcfSolverOptions{});
  EXPECT_FALSE(agree.beta_disagrees);
  EXPECT_TRUE(agree.warnings.empty());
  // The phase estimate is within 3σ of the truth, and σ is the size the timing noise implies
  // (ω·σ_t/√K = π rad/s · 0.1 ms / √3 ≈ 0.01°), not orders of magnitude off.
  EXPECT_NEAR(RadToDeg(agree.beta_self_calibrated_rad), o.effects.beta_deg,
              3 * RadToDeg(agree.beta_self_calibrated_sigma_rad));
  EXPECT_GT(RadToDeg(agree.beta_self_calibrated_sigma_rad), 0.003);
  EXPECT_LT(RadToDeg(agree.beta_self_calibrated_sigma_rad), 0.05);
  sim.calibrated_sensor.beta_rad = DegToRad(90.0);  // the file lost β (thesis value 92.15°)
  const TcfSummary lost = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, TcfSolverOptions{});
  EXPECT_TRUE(lost.beta_disagrees);
  ASSERT_EQ(lost.warnings.size(), 1u);
  EXPECT_NE(lost.warnings[0].find("--self-calibrate-beta"), std::string::npos);
}

TEST(TcfSolver, SpeedScaleIsNotTakenForLatency) {
  TcfSimulationOptions o = Noiseless();
  ASSERT_TRUE(o.effects.Enable("speed_variation"));
  ASSERT_TRUE(o.effects.Enable("trigger_latency"));
  o.effects.speed_ripple = 0.0;  // a pure scale error is modelled exactly
  const TcfSimulation sim = SimulateTcf(o);
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary s = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_NEAR(s.speed_scale, 1.0 + o.effects.speed_scale_error, 1e-6);
  EXPECT_NEAR(s.latency_s, o.effects.latency_s, 1e-5);
  EXPECT_LT((s.solution.tcp_in_flange - sim.truth.tcp_in_flange).norm(), 1e-3) << s.BriefReport();
}

}  // namespace
}  // namespace ramtk::tcf

namespace ramtk::tcf {
namespace {

// The thesis's measured tool frames, eqs. (5-5) and (5-6), have the 5-DOF form of eq. (4-10):
// ψ, θ from their Z column rebuild the whole printed rotation to its 4 decimals.
TEST(TcfSolver, ThesisToolFramesHaveTheFiveDofForm) {
  const double eq55[3][3] = {{1.0000, -0.0000, -0.0016}, {-0.0000, 1.0000, -0.0012}, {0.0016, 0.0012, 1.0000}};
  const double eq56[3][3] = {{0.9963, 0.0051, 0.0857}, {0.0051, 0.9929, -0.1187}, {-0.0857, 0.1187, 0.9892}};
  for (const auto* m : {eq55, eq56}) {
    const Vec3 z(m[0][2], m[1][2], m[2][2]);
    double psi, theta;
    EulerFromAxis(z, &psi, &theta);
    const Mat3 r = FiveDofRotation(psi, theta);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(r(i, j), m[i][j], 1.5e-4) << i << "," << j;
      }
    }
  }
  // Eq. (5-6): the shimmed tool is tilted by θ = 8.4° towards ψ = 35.8°.
  double psi, theta;
  EulerFromAxis(Vec3(0.0857, -0.1187, 0.9892), &psi, &theta);
  EXPECT_NEAR(RadToDeg(psi), 35.83, 0.05);
  EXPECT_NEAR(RadToDeg(theta), 8.43, 0.05);
}

}  // namespace
}  // namespace ramtk::tcf

namespace ramtk::tcf {
namespace {

TEST(TcfSolver, ReceiverGlitchesAreDropped) {
  const TcfSimulation sim = SimulateTcf(Noiseless());
  TcfSolverOptions opt;
  opt.timing_sigma_s = 0;
  opt.repeatability_sigma_mm = 0;
  const TcfSummary clean = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, opt);
  // A 0.3 ms blocked/clear chatter on the x beam in the middle of the first circle.
  std::vector<BeamEvent> ev = sim.events;
  const double t = sim.motion.circles[0].start_time_s + 0.05;
  ev.push_back({t, Beam::kX, BeamState::kBlocked, 0});
  ev.push_back({t + 3e-4, Beam::kX, BeamState::kClear, 0});
  std::sort(ev.begin(), ev.end(), [](const BeamEvent& a, const BeamEvent& b) { return a.time_s < b.time_s; });
  const TcfSummary filtered = SolveTcf(ev, sim.motion, sim.calibrated_sensor, opt);
  EXPECT_EQ(filtered.glitches_removed, 1);
  EXPECT_LT((filtered.solution.tcp_in_flange - clean.solution.tcp_in_flange).norm(), 1e-12);
  // Without the filter the glitch is taken for a crossing and the circle is misread.
  opt.min_blocked_duration_s = 0.0;
  bool differs = true;
  try {
    const TcfSummary raw = SolveTcf(ev, sim.motion, sim.calibrated_sensor, opt);
    differs = (raw.solution.tcp_in_flange - clean.solution.tcp_in_flange).norm() > 0.01;
  } catch (const InputError&) {
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace ramtk::tcf
