// Simulator: reproducibility, the thermal model against its closed form, measurement geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/thermal/identify.h"
#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using testing::Kr150;
using testing::Thesis;

TEST(ThermalSimulator, SameSeedSameData) {
  ThermalSimOptions o = ThesisPreset(7);
  o.cycles = 5;
  const ThermalSimResult a = SimulateThermal(Kr150(), o);
  const ThermalSimResult b = SimulateThermal(Kr150(), o);
  EXPECT_EQ(kinematics::FormatRobotMeasurements(a.ball), kinematics::FormatRobotMeasurements(b.ball));
  EXPECT_EQ(kinematics::FormatRobotMeasurements(a.monitoring), kinematics::FormatRobotMeasurements(b.monitoring));
  o.seed = 8;
  const ThermalSimResult c = SimulateThermal(Kr150(), o);
  EXPECT_NE(kinematics::FormatRobotMeasurements(a.ball), kinematics::FormatRobotMeasurements(c.ball));
}

// Constant duty from cold: housing ΔT = G(1 − e^{−t/τ}); structure (first-order lag τs behind it)
// S = G[1 − (τ e^{−t/τ} − τs e^{−t/τs})/(τ − τs)]. ΔX = Σ per_kelvin · S.
TEST(ThermalSimulator, DriftFollowsTheClosedFormOfTwoFirstOrderStages) {
  const ThermalSimOptions o = ThesisPreset(1);
  const double ts = o.structure_tau_s;
  for (double t : {600.0, 1800.0, 3600.0, 6000.0}) {
    Eigen::Matrix<double, 6, 1> housing;
    const kinematics::ParamVector x = TrueDriftAt(o, t, &housing);
    kinematics::ParamVector expected = kinematics::ParamVector::Zero();
    for (const HeatSource& h : o.sources) {
      const double tau = h.tau_heat_s;
      EXPECT_NEAR(housing[h.joint] - o.ambient_c, h.gain_k * (1 - std::exp(-t / tau)), 1e-3 * h.gain_k);
      const double s = h.gain_k * (1 - (tau * std::exp(-t / tau) - ts * std::exp(-t / ts)) / (tau - ts));
      for (const ParamDrift& d : o.drifts) expected[d.param] += d.per_kelvin[h.joint] * s;
    }
    for (int p = 0; p < kinematics::kNumParams; ++p) {
      EXPECT_NEAR(x[p], expected[p], 1e-3 * std::abs(expected[p]) + 1e-12) << kinematics::ParamName(p) << " t=" << t;
    }
  }
}

TEST(ThermalSimulator, ThesisPresetGeometryAndMagnitudes) {
  const auto& e = Thesis(1);
  EXPECT_EQ(e.experiment.ball.NumCycles(), 90);
  EXPECT_EQ(e.experiment.ball.NumPoses(), 20);
  EXPECT_EQ(e.experiment.monitoring.NumPoses(), 34);
  EXPECT_NEAR(e.sim.cycle_time_s.back() + e.options.cycle_period_s, 3 * 3600.0, 1.0);
  // Sensor about 2 m from the base; ball poses 700 ± 75 mm in front of it (field of view).
  EXPECT_NEAR(e.sim.setup.sensor_from_base.inverse().translation().norm(), 2000.0, 300.0);
  for (const auto& row : e.sim.ball.rows) {
    EXPECT_NEAR(row.position_mm.z(), 700.0, 76.0);
    EXPECT_LT(std::abs(row.position_mm.x()), 201.0);
  }
  // Thesis §1: up to ~0.5 mm at the TCP after hours of fast motion.
  double largest = 0.0;
  for (int c = 0; c < 90; ++c) {
    for (int i = 0; i < 20; ++i) {
      largest = std::max(
          largest, (e.experiment.ball.cycles[c].position_mm[i] - e.experiment.ball.cycles[0].position_mm[i]).norm());
    }
  }
  EXPECT_GT(largest, 0.3);
  EXPECT_LT(largest, 0.8);
  // Monitoring readings are the car-body points seen from the tool sensor at working distance.
  for (const auto& row : e.sim.monitoring.rows) EXPECT_NEAR(row.position_mm.z(), 300.0, 1.0);
}

TEST(ThermalSimulator, NoiseFreeBallReadingsAreTheWarmForwardKinematics) {
  ThermalSimOptions o = ThesisPreset(3);
  o.cycles = 3;
  o.sensor_noise_mm = o.tool_sensor_noise_mm = o.repeatability_mm = 0.0;
  const ThermalSimResult r = SimulateThermal(Kr150(), o);
  for (const auto& row : r.ball.rows) {
    const kinematics::ParamVector dx = TrueDriftAt(o, row.time_s);
    kinematics::RobotModel warm = Kr150();
    warm.SetParams(Kr150().Params() + dx);
    const Vec3 expected =
        o.setup.sensor_from_base * (kinematics::BaseFromFlange(warm, row.q_controller) * o.setup.ball_in_flange);
    EXPECT_LT((row.position_mm - expected).norm(), 1e-6);
  }
}

TEST(ThermalSimulator, TruthCsvNamesTheDriftingSet) {
  const auto& e = Thesis(1);
  const std::string csv = TruthTrajectoriesCsv(e.sim);
  EXPECT_NE(csv.find("# drifting parameters (truth): d4,d6,a1,a2,a3,alpha3,alpha4,beta2"), std::string::npos);
  EXPECT_NE(csv.find("cycle,time_s,temp_j1"), std::string::npos);
}

TEST(ThermalSimulator, InvalidOptionsAreInputErrors) {
  ThermalSimOptions o = ThesisPreset(1);
  o.cycles = 1;
  EXPECT_THROW(SimulateThermal(Kr150(), o), InputError);
  o = ThesisPreset(1);
  o.drifts[0].per_kelvin.resize(3);
  EXPECT_THROW(SimulateThermal(Kr150(), o), InputError);
}

}  // namespace
}  // namespace ramtk::thermal
