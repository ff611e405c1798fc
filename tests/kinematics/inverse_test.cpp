// Inverse kinematics: FK -> IK -> FK round trips, IK under a modified parameter set (the
// compensator's use), and unreachable targets.
#include "ramtk/kinematics/inverse.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "kdl_peer.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using testing::LoadShippedRobot;
using testing::PerturbedModel;

// The requirement for a round trip.
constexpr double kPosTolMm = 1e-6;
constexpr double kRotTolDeg = 1e-6;

// Inverse condition number of the joint Jacobian with rotation rows in mm (× 1000 mm).
double InverseCondition(const RobotModel& robot, const JointVector& q) {
  JointJacobian j = ComputeJointJacobian(robot, q);
  j.bottomRows<3>() *= 1000.0;
  const Eigen::JacobiSVD<JointJacobian> svd(j);
  return svd.singularValues()[5] / svd.singularValues()[0];
}

// Random joints over ±180°, seeds within ±15° per joint. Poses at or next to a singularity
// (inverse condition < 0.02 at the truth or the seed: stretched elbow, aligned wrist) are
// redrawn: from such seeds a local solver may legitimately stall on the singular set.
void RoundTrips(const RobotModel& robot, unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-kPi, kPi), near(-DegToRad(15.0), DegToRad(15.0));
  int converged = 0;
  for (int n = 0; n < count; ++n) {
    JointVector truth, seed_q;
    do {
      for (int i = 0; i < kNumJoints; ++i) truth[i] = u(rng);
      seed_q = truth;
      for (int i = 0; i < kNumJoints; ++i) seed_q[i] += near(rng);
    } while (InverseCondition(robot, truth) < 0.02 || InverseCondition(robot, seed_q) < 0.02);
    const Isometry3 target = BaseFromFlange(robot, truth);
    const InverseKinematicsSummary s = SolveInverseKinematics(robot, target, seed_q);
    ASSERT_TRUE(s.Converged()) << robot.name << " case " << n << ": " << s.BriefReport();
    const Isometry3 reached = BaseFromFlange(robot, s.q_controller);
    EXPECT_LT((reached.translation() - target.translation()).norm(), kPosTolMm);
    EXPECT_LT(RadToDeg(RotationAngleBetween(reached.linear(), target.linear())), kRotTolDeg);
    converged += s.Converged();
  }
  EXPECT_EQ(converged, count);
}

TEST(InverseKinematics, RoundTripKr150) { RoundTrips(LoadShippedRobot("kuka_kr150_r3100.yaml"), 1, 300); }
TEST(InverseKinematics, RoundTripBx200l) { RoundTrips(LoadShippedRobot("kawasaki_bx200l.yaml"), 2, 300); }
TEST(InverseKinematics, RoundTripUr10) { RoundTrips(LoadShippedRobot("ur10.yaml"), 3, 300); }

TEST(InverseKinematics, CompensatesUnderAModifiedParameterSet) {
  // The compensator's question: the robot drifted (its parameters changed); which joints put the
  // flange back on the taught pose? Taught with the nominal model, solved with the drifted one.
  const RobotModel nominal = LoadShippedRobot("kuka_kr150_r3100.yaml");
  const RobotModel drifted = PerturbedModel(nominal, 9, 0.3, DegToRad(0.02));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int n = 0; n < 50; ++n) {
    JointVector taught;
    taught << u(rng), -1.2 + 0.3 * u(rng), 1.4 + 0.3 * u(rng), u(rng), 0.8 + 0.2 * u(rng), u(rng);
    const Isometry3 target = BaseFromFlange(nominal, taught);
    const double drift_mm = (BaseFromFlange(drifted, taught).translation() - target.translation()).norm();
    ASSERT_GT(drift_mm, 0.01);  // the drift is real
    const InverseKinematicsSummary s = SolveInverseKinematics(drifted, target, taught);
    ASSERT_TRUE(s.Converged()) << s.BriefReport();
    const Isometry3 reached = BaseFromFlange(drifted, s.q_controller);
    EXPECT_LT((reached.translation() - target.translation()).norm(), kPosTolMm);
    EXPECT_LT(RadToDeg(RotationAngleBetween(reached.linear(), target.linear())), kRotTolDeg);
    // Small drifts need small corrections (0.3 mm / 0.02° drifts: well under a degree).
    EXPECT_LT((s.q_controller - taught).cwiseAbs().maxCoeff(), DegToRad(1.0));
  }
}

TEST(InverseKinematics, UnreachableTargetIsReportedNotConverged) {
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  JointVector seed;
  seed << 0, -kPi / 2, kPi / 2, 0, 0.3, 0;
  // 10 m away: beyond the 3.3 m reach.
  Isometry3 far = Isometry3::Identity();
  far.translation() = Vec3(10000, 0, 500);
  const InverseKinematicsSummary s = SolveInverseKinematics(kr, far, seed);
  EXPECT_FALSE(s.Converged());
  EXPECT_EQ(s.termination, Termination::kNoResult) << s.BriefReport();
  // The closest reachable point is at least 10000 − (max reach ≈ 3.4 m) away.
  EXPECT_GT(s.final_position_error_mm, 10000.0 - 3500.0);
  // Inside the base column: a point the arm cannot fold onto with this orientation.
  Isometry3 inside = Isometry3::Identity();
  inside.translation() = Vec3(0, 0, -2000);
  const InverseKinematicsSummary s2 = SolveInverseKinematics(kr, inside, seed);
  EXPECT_FALSE(s2.Converged()) << s2.BriefReport();
}

TEST(InverseKinematics, OptionsValidation) {
  InverseKinematicsOptions o;
  EXPECT_EQ(o.Validate(), "");
  o.max_iterations = 0;
  EXPECT_NE(o.Validate(), "");
  o = {};
  o.reach_position_tolerance_mm = 1e-12;
  EXPECT_NE(o.Validate(), "");
}

}  // namespace
}  // namespace ramtk::kinematics
