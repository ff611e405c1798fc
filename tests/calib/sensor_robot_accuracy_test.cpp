// Accuracy against simulator truth: the thesis method and the manifold estimator side by side over
// 5..20 poses, and the reported covariance against Monte-Carlo scatter.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sensor_robot_test_util.h"

namespace ramtk::calib {
namespace {

using testing::Errors;
using testing::ErrorsAgainstTruth;
using testing::Kr150;

// RMS over seeds of each error, for one pose count.
struct ErrorRms {
  double rotation_arcsec = 0, translation_um = 0, ball_um = 0;
  void Add(const Errors& e, int count) {
    rotation_arcsec += e.rotation_arcsec * e.rotation_arcsec / count;
    translation_um += e.translation_um * e.translation_um / count;
    ball_um += e.ball_um * e.ball_um / count;
  }
  void Finish() {
    rotation_arcsec = std::sqrt(rotation_arcsec);
    translation_um = std::sqrt(translation_um);
    ball_um = std::sqrt(ball_um);
  }
};

TEST(SensorRobotAccuracy, ManifoldAtLeastAsAccurateAsThesisFrom5To20Poses) {
  const kinematics::RobotModel model = Kr150();
  const int kSeeds = 20;
  std::printf(
      "poses | thesis: rot(arcsec) t(um) ball(um) | manifold: rot(arcsec) t(um) ball(um)   [RMS over %d seeds, "
      "centre noise 10 um, RP 0.05 mm]\n",
      kSeeds);
  for (int poses : {5, 7, 9, 12, 15, 20}) {
    ErrorRms thesis, ours;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      SensorRobotSimOptions o;
      o.num_poses = poses;
      o.seed = 100 + seed;
      o.noise_seed = seed;
      const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
      SensorRobotOptions mo;
      mo.checks.warn_condition_number = 1e3;  // 5-pose sets are legitimately weaker; keep the log quiet
      ThesisCalibrationOptions to;
      to.checks = mo.checks;
      thesis.Add(ErrorsAgainstTruth(CalibrateSensorRobotThesis(model, sim.observations, to), sim), kSeeds);
      ours.Add(ErrorsAgainstTruth(CalibrateSensorRobot(model, sim.observations, mo), sim), kSeeds);
    }
    thesis.Finish();
    ours.Finish();
    std::printf("%5d | %10.2f %8.1f %8.1f | %10.2f %8.1f %8.1f\n", poses, thesis.rotation_arcsec, thesis.translation_um,
                thesis.ball_um, ours.rotation_arcsec, ours.translation_um, ours.ball_um);
    EXPECT_LE(ours.rotation_arcsec, thesis.rotation_arcsec) << poses << " poses";
    EXPECT_LE(ours.translation_um, thesis.translation_um) << poses << " poses";
    EXPECT_LE(ours.ball_um, thesis.ball_um) << poses << " poses";
  }
}

void CheckCovarianceAgainstMonteCarlo(int poses) {
  const kinematics::RobotModel model = Kr150();
  const int kDraws = 60;
  SensorRobotSimOptions o;
  o.seed = 7;
  o.num_poses = poses;
  std::printf("%d poses, %d noise draws:\n", poses, kDraws);
  Eigen::Matrix<double, 9, 1> sum = Eigen::Matrix<double, 9, 1>::Zero(), sum2 = sum, reported = sum;
  for (int draw = 1; draw <= kDraws; ++draw) {
    o.noise_seed = 1000 + draw;
    const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
    SensorRobotOptions so;
    so.checks.warn_condition_number = 1e3;  // 5-pose sets are weaker by design
    const SensorRobotCalibration c = CalibrateSensorRobot(model, sim.observations, so);
    ASSERT_TRUE(c.has_covariance);
    Eigen::Matrix<double, 9, 1> x;
    // Rotation error as a left rotation vector in the sensor frame, like the covariance.
    x.head<3>() = LogSO3(c.sensor_from_base.linear() * sim.sensor_from_base.linear().transpose());
    x.segment<3>(3) = c.sensor_from_base.translation() - sim.sensor_from_base.translation();
    x.tail<3>() = c.ball_in_flange - sim.ball_in_flange;
    sum += x;
    sum2 += x.cwiseProduct(x);
    reported += c.covariance.diagonal();
  }
  const Eigen::Matrix<double, 9, 1> mean = sum / kDraws;
  const Eigen::Matrix<double, 9, 1> mc_std = ((sum2 - kDraws * mean.cwiseProduct(mean)) / (kDraws - 1)).cwiseSqrt();
  const Eigen::Matrix<double, 9, 1> rep_std = (reported / kDraws).cwiseSqrt();
  const char* names[9] = {"phi_x", "phi_y", "phi_z", "t_x", "t_y", "t_z", "ball_x", "ball_y", "ball_z"};
  for (int i = 0; i < 9; ++i) {
    const double scale = i < 3 ? kArcsecPerRad : 1000.0;
    std::printf("%-7s Monte-Carlo std %9.3f  reported std %9.3f  ratio %.3f  (%s)\n", names[i], mc_std[i] * scale,
                rep_std[i] * scale, mc_std[i] / rep_std[i], i < 3 ? "arcsec" : "um");
    EXPECT_NEAR(mc_std[i] / rep_std[i], 1.0, 0.3) << names[i] << ", " << poses << " poses";
  }
}

// The covariance the estimator reports must describe its real scatter: over 60 noise draws on
// one pose set, the standard deviation of each of the 9 unknowns against the mean reported one.
TEST(SensorRobotAccuracy, ReportedCovarianceMatchesMonteCarloScatter) {
  for (int poses : {5, 9, 20}) CheckCovarianceAgainstMonteCarlo(poses);
}

}  // namespace
}  // namespace ramtk::calib

namespace ramtk::calib {
namespace {

// One pose with a 1 mm blunder (a mis-fitted sphere): the robust loss keeps the estimate near
// the clean one, plain least squares does not, and the pose is listed as an outlier.
TEST(SensorRobotAccuracy, RobustLossResistsABlunderAndNamesIt) {
  const kinematics::RobotModel model = testing::Kr150();
  SensorRobotSimOptions o;
  o.num_poses = 12;
  SensorRobotSimulation sim = SimulateSensorRobot(model, o);
  const SensorRobotCalibration clean = CalibrateSensorRobot(model, sim.observations);
  sim.observations[7].ball_in_sensor += Vec3(0.6, -0.5, 0.6);
  SensorRobotOptions plain, cauchy;
  plain.loss = RobustLoss::kNone;
  cauchy.loss = RobustLoss::kCauchy;
  cauchy.loss_scale_mm = 0.05;
  SensorRobotSummary s_plain, s_huber, s_cauchy;
  const SensorRobotCalibration a = CalibrateSensorRobot(model, sim.observations, plain, &s_plain);
  const SensorRobotCalibration h = CalibrateSensorRobot(model, sim.observations, {}, &s_huber);
  const SensorRobotCalibration c = CalibrateSensorRobot(model, sim.observations, cauchy, &s_cauchy);
  const auto e_clean = testing::ErrorsAgainstTruth(clean, sim);
  for (auto* p : {&a, &h, &c}) {
    const auto e = testing::ErrorsAgainstTruth(*p, sim);
    std::printf("blunder: rot %.2f arcsec, t %.1f um, ball %.1f um (clean data: %.2f, %.1f, %.1f)\n", e.rotation_arcsec,
                e.translation_um, e.ball_um, e_clean.rotation_arcsec, e_clean.translation_um, e_clean.ball_um);
  }
  // Distance from the clean-data estimate (sensor translation: the most sensitive unknown).
  auto moved = [&](const SensorRobotCalibration& x) {
    return (x.sensor_from_base.translation() - clean.sensor_from_base.translation()).norm();
  };
  EXPECT_LT(moved(h), 0.5 * moved(a));
  EXPECT_LT(moved(c), 0.5 * moved(h));
  // Cauchy: back to within 20 µm of the clean-data ball offset.
  EXPECT_LT((c.ball_in_flange - clean.ball_in_flange).norm(), 0.020);
  for (const SensorRobotSummary* s : {&s_plain, &s_huber, &s_cauchy}) {
    ASSERT_EQ(s->outliers.size(), 1u) << s->BriefReport();
    EXPECT_EQ(s->outliers[0], 7);
  }
}

}  // namespace
}  // namespace ramtk::calib

namespace ramtk::calib {
namespace {

// The thesis gives no value for the penalty factor M of eq. (3-18). Small M leaves R_s visibly
// non-orthonormal and biases t_s (which is averaged through R_s, eq. 3-19). The default options
// (whatever M they hold) must make the penalty exact to 1e-6 and fit t_s better than M = 1e2.
TEST(SensorRobotAccuracy, ThesisPenaltyFactorSweep) {
  const kinematics::RobotModel model = testing::Kr150();
  const int kSeeds = 20;
  double t_small_m = 0.0, t_default = 0.0, orth_default = 0.0;
  for (double m : {1e2, 1e4, 1e6, 0.0}) {  // 0: the default options, untouched
    double rot2 = 0.0, t2 = 0.0, ball2 = 0.0, orth = 0.0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      SensorRobotSimOptions o;
      o.seed = 100 + seed;
      o.noise_seed = seed;
      const SensorRobotSimulation sim = SimulateSensorRobot(model, o);
      ThesisCalibrationOptions to;
      if (m > 0.0) to.penalty_factor = m;
      const SensorRobotCalibration c = CalibrateSensorRobotThesis(model, sim.observations, to);
      const testing::Errors e = testing::ErrorsAgainstTruth(c, sim);
      rot2 += e.rotation_arcsec * e.rotation_arcsec / kSeeds;
      t2 += e.translation_um * e.translation_um / kSeeds;
      ball2 += e.ball_um * e.ball_um / kSeeds;
      orth = std::max(orth, c.orthonormality_error);
    }
    std::printf("M %.0e: rotation %.2f arcsec, t %.1f um, ball %.1f um, worst orthonormality error %.2e\n", m,
                std::sqrt(rot2), std::sqrt(t2), std::sqrt(ball2), orth);  // M 0 = the default
    if (m == 1e2) t_small_m = std::sqrt(t2);
    if (m == 0.0) t_default = std::sqrt(t2), orth_default = orth;
  }
  EXPECT_LT(orth_default, 1e-6);
  EXPECT_LT(t_default, t_small_m);
}

}  // namespace
}  // namespace ramtk::calib
