// Sensor-to-robot calibration: noise-free closed cases, simulator properties, diagnostics.
#include <gtest/gtest.h>

#include "ramtk/kinematics/forward.h"
#include "sensor_robot_test_util.h"

namespace ramtk::calib {
namespace {

using testing::ErrorsAgainstTruth;
using testing::Kr150;

TEST(SensorRobotSim, ThesisTruthAndMeasurementVolume) {
  const kinematics::RobotModel model = Kr150();
  SensorRobotSimOptions o;
  const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
  ASSERT_EQ(sim.observations.size(), 9u);
  // Eq. (5-1) is printed with 4 decimals: its polar projection moves entries by < 2e-4.
  const Mat3 printed =
      (Mat3() << 0.9003, -0.1695, -0.4009, -0.1695, 0.7117, -0.6817, 0.4009, 0.6817, 0.6120).finished();
  EXPECT_LT((sim.sensor_from_base.linear() - printed).cwiseAbs().maxCoeff(), 2e-4);
  EXPECT_LT(OrthonormalityError(sim.sensor_from_base.linear()), 1e-12);
  EXPECT_NEAR(sim.sensor_from_base.translation().norm(), 2715.22, 0.01);  // |t| of eq. (5-1)
  for (std::size_t i = 0; i < sim.observations.size(); ++i) {
    // Noise-free centre is exactly eq. (3-1) of the stored joints, and inside the volume box.
    const Vec3 p =
        PredictBallInSensor(model, sim.sensor_from_base, sim.ball_in_flange, sim.observations[i].q_controller);
    EXPECT_LT((p - sim.true_ball_in_sensor[i]).norm(), 1e-9);
    const Vec3 rel =
        (sim.sensor_from_base.inverse() * p) - (sim.sensor_from_base.inverse() * o.volume_center_in_sensor);
    EXPECT_LE(rel.cwiseAbs().maxCoeff(), o.volume_half_size_mm + 1e-6);
    // Noise: centre 10 µm + repeatability 0.05/3.6 mm per axis → |noise| well under 0.15 mm.
    EXPECT_LT((sim.observations[i].ball_in_sensor - p).norm(), 0.15);
  }
  // Same seeds, same data.
  const SensorRobotSimulation again = SimulateSensorRobot(model, o);
  EXPECT_EQ(again.observations[4].ball_in_sensor, sim.observations[4].ball_in_sensor);
}

TEST(SensorRobot, NoiseFreeDataGiveTruthForAllEstimators) {
  const kinematics::RobotModel model = Kr150();
  SensorRobotSimOptions o;
  o.center_noise_mm = 0.0;
  o.repeatability_mm = 0.0;
  const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
  SensorRobotSummary s;
  const SensorRobotCalibration lin = SolveSensorRobotLinear(model, sim.observations);
  const SensorRobotCalibration ours = CalibrateSensorRobot(model, sim.observations, {}, &s);
  ThesisCalibrationOptions to;
  const SensorRobotCalibration thesis = CalibrateSensorRobotThesis(model, sim.observations, to);
  for (const SensorRobotCalibration* c : {&lin, &ours, &thesis}) {
    const auto e = ErrorsAgainstTruth(*c, sim);
    // Exact data: only rounding (1e-9 of 3 m) is left.
    EXPECT_LT(e.rotation_arcsec, 1e-4);
    EXPECT_LT(e.translation_um, 1e-3);
    EXPECT_LT(e.ball_um, 1e-3);
    EXPECT_LT(c->rms_mm, 1e-6);
  }
  EXPECT_EQ(s.termination, Termination::kSuccess);
  std::printf("%s\n", s.BriefReport().c_str());
  EXPECT_TRUE(s.warnings.empty()) << s.BriefReport();
}

TEST(SensorRobot, ResidualsAreMeasuredMinusPredicted) {
  const kinematics::RobotModel model = Kr150();
  const SensorRobotSimulation sim = SimulateSensorRobot(model, {});
  SensorRobotSummary s;
  const SensorRobotCalibration c = CalibrateSensorRobot(model, sim.observations, {}, &s);
  ASSERT_EQ(c.residuals_mm.size(), sim.observations.size());
  double sum2 = 0.0;
  for (std::size_t i = 0; i < c.residuals_mm.size(); ++i) {
    const Vec3 pred =
        PredictBallInSensor(model, c.sensor_from_base, c.ball_in_flange, sim.observations[i].q_controller);
    EXPECT_LT((sim.observations[i].ball_in_sensor - pred - c.residuals_mm[i]).norm(), 1e-12);
    sum2 += c.residuals_mm[i].squaredNorm();
  }
  EXPECT_NEAR(c.rms_mm, std::sqrt(sum2 / 9.0), 1e-12);
  // Per-axis noise σ = sqrt(0.010² + (0.05/3.6)²) = 0.0171 mm; the residual RMS of the 3-D vector
  // is σ·sqrt(3·(27−9)/27) ≈ 0.024 mm. Loose bounds for 9 poses.
  EXPECT_GT(c.rms_mm, 0.008);
  EXPECT_LT(c.rms_mm, 0.05);
  EXPECT_NE(s.BriefReport().find("manifold: converged"), std::string::npos) << s.BriefReport();
}

}  // namespace
}  // namespace ramtk::calib
