// Covariance weighting of the sensor-to-robot calibration: centre noise that varies across the
// field (larger at the edge and along the line of sight), weighted vs unweighted, against the
// simulator's truth over noise seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/calib/sensor_robot_io.h"
#include "sensor_robot_test_util.h"

namespace ramtk::calib {
namespace {

// σ grows from 2 µm at the field centre to 20 µm at its edge; depth σ is 3× the lateral one.
Mat3 FieldCovariance(const Vec3& ball_in_sensor, const SensorRobotSimOptions& o) {
  const double r = (ball_in_sensor - o.volume_center_in_sensor).norm() / (std::sqrt(3.0) * o.volume_half_size_mm);
  const double s = 0.002 * (1.0 + 9.0 * r * r);
  return Vec3(s * s, s * s, 9.0 * s * s).asDiagonal();
}

TEST(SensorRobotWeighting, CovarianceWeightingBeatsUnweightedWhenNoiseVariesAcrossTheField) {
  const kinematics::RobotModel model = testing::Kr150();
  SensorRobotSimOptions o;
  o.num_poses = 15;
  o.center_noise_mm = 0.0;
  o.repeatability_mm = 0.0;
  o.seed = 3;
  double sum_w[3] = {0, 0, 0}, sum_u[3] = {0, 0, 0};
  const int seeds = 30;
  for (int seed = 1; seed <= seeds; ++seed) {
    SensorRobotSimulation sim = SimulateSensorRobot(model, o);  // noise-free
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n01;
    for (std::size_t i = 0; i < sim.observations.size(); ++i) {
      BallObservation& b = sim.observations[i];
      b.covariance_mm2 = FieldCovariance(sim.true_ball_in_sensor[i], o);
      b.has_covariance = true;
      const Vec3 z(n01(rng), n01(rng), n01(rng));
      b.ball_in_sensor = sim.true_ball_in_sensor[i] + b.covariance_mm2.llt().matrixL() * z;
    }
    SensorRobotOptions weighted, plain;
    plain.use_covariance = false;
    SensorRobotSummary sw, su;
    const auto cw = CalibrateSensorRobot(model, sim.observations, weighted, &sw);
    const auto cu = CalibrateSensorRobot(model, sim.observations, plain, &su);
    EXPECT_TRUE(sw.weighted);
    EXPECT_FALSE(su.weighted);
    EXPECT_NE(sw.BriefReport().find("weighted by its covariance"), std::string::npos);
    const testing::Errors ew = testing::ErrorsAgainstTruth(cw, sim), eu = testing::ErrorsAgainstTruth(cu, sim);
    sum_w[0] += ew.rotation_arcsec * ew.rotation_arcsec;
    sum_w[1] += ew.translation_um * ew.translation_um;
    sum_w[2] += ew.ball_um * ew.ball_um;
    sum_u[0] += eu.rotation_arcsec * eu.rotation_arcsec;
    sum_u[1] += eu.translation_um * eu.translation_um;
    sum_u[2] += eu.ball_um * eu.ball_um;
  }
  // Generalised least squares is the best linear unbiased estimator: with σ varying 10× across
  // X
  for (int k = 0; k < 3; ++k) {
    const double rms_w = std::sqrt(sum_w[k] / seeds), rms_u = std::sqrt(sum_u[k] / seeds);
    ::testing::Test::RecordProperty("gain_" + std::to_string(k), std::to_string(rms_u / rms_w));
    EXPECT_LT(rms_w * 1.3, rms_u) << "quantity " << k << ": weighted " << rms_w << ", unweighted " << rms_u;
  }
}

TEST(SensorRobotWeighting, ReadsTheCovarianceColumns) {
  const kinematics::RobotModel model = testing::Kr150();
  SensorRobotSimOptions o;
  o.center_noise_mm = 0.0;
  o.repeatability_mm = 0.0;
  SensorRobotSimulation sim = SimulateSensorRobot(model, o);
  kinematics::RobotMeasurementSet set = MeasurementsFromObservations(sim.observations);
  kinematics::AddCentreCovarianceColumns(&set);
  for (std::size_t i = 0; i < set.rows.size(); ++i) {
    kinematics::SetCentreCovariance(FieldCovariance(sim.true_ball_in_sensor[i], o), &set.rows[i]);
  }
  const auto obs = BallObservationsFromMeasurements(set, "ball.csv");
  ASSERT_TRUE(obs[3].has_covariance);
  EXPECT_NEAR(obs[3].covariance_mm2(2, 2), FieldCovariance(sim.true_ball_in_sensor[3], o)(2, 2), 1e-18);
}

}  // namespace
}  // namespace ramtk::calib
