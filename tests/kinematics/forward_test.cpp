// Forward kinematics against the thesis, hand-computed single-joint cases and Orocos KDL.
#include "ramtk/kinematics/forward.h"

#include <gtest/gtest.h>

#include <random>

#include "kdl_peer.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using testing::KdlBaseFromFlange;
using testing::LoadShippedRobot;
using testing::PerturbedModel;

JointVector Deg(double q1, double q2, double q3, double q4, double q5, double q6) {
  JointVector q;
  q << q1, q2, q3, q4, q5, q6;
  return q * kRadPerDeg;
}

// Doubles near 2000 mm carry ~4e-13 mm of rounding per operation; a 6-link product stays well
// inside this.
constexpr double kPosTolMm = 1e-9;
constexpr double kRotTol = 1e-12;

TEST(ForwardKinematics, Bx200lThesisPose) {
  // Thesis §2.2.2: controller joints (90,0,0,0,0,0); the nominal model (Table 2-1, joint 1
  // negated) gives (1675, 0, 1920) mm. The controller itself reports (1675.749, −0.650,
  // 1918.024): the real robot is not nominal, so that reading is not the model's truth.
  const RobotModel bx = LoadShippedRobot("kawasaki_bx200l.yaml");
  const Isometry3 t = BaseFromFlange(bx, Deg(90, 0, 0, 0, 0, 0));
  EXPECT_NEAR(t.translation().x(), 1675.0, kPosTolMm);
  EXPECT_NEAR(t.translation().y(), 0.0, kPosTolMm);
  EXPECT_NEAR(t.translation().z(), 1920.0, kPosTolMm);
  const Vec3 measured(1675.749, -0.650, 1918.024);
  EXPECT_NEAR((measured - t.translation()).norm(), std::sqrt(0.749 * 0.749 + 0.65 * 0.65 + 1.976 * 1.976), 1e-9);
}

TEST(ForwardKinematics, Bx200lJointOneIsNegated) {
  // Thesis: "joint 1 input +90°, but the robot turns −90° about Z0". At controller 0 the flange
  // therefore lies on +Y (rotate the (90,...) pose back by +90° about Z0).
  const RobotModel bx = LoadShippedRobot("kawasaki_bx200l.yaml");
  const Vec3 p90 = BaseFromFlange(bx, Deg(90, 0, 0, 0, 0, 0)).translation();
  const Vec3 p0 = BaseFromFlange(bx, Deg(0, 0, 0, 0, 0, 0)).translation();
  EXPECT_NEAR((p0 - RotZ(DegToRad(90.0)) * p90).norm(), 0.0, kPosTolMm);
  EXPECT_NEAR(p0.y(), 1675.0, kPosTolMm);
}

TEST(ForwardKinematics, Ur10ZeroPoseClosedForm) {
  // All DH angles zero: x = a2 + a3, y = −(d4 + d6), z = d1 − d5 (UR's published table).
  const RobotModel ur = LoadShippedRobot("ur10.yaml");
  const Vec3 p = BaseFromFlange(ur, Deg(0, 0, 0, 0, 0, 0)).translation();
  EXPECT_NEAR(p.x(), -612.0 - 572.3, kPosTolMm);
  EXPECT_NEAR(p.y(), -(163.941 + 92.2), kPosTolMm);
  EXPECT_NEAR(p.z(), 127.3 - 115.7, kPosTolMm);
}

TEST(ForwardKinematics, Kr150NominalPosesClosedForm) {
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  // Controller zero: arm stretched along +X0, wrist offset 41 mm up.
  const Vec3 p0 = BaseFromFlange(kr, Deg(0, 0, 0, 0, 0, 0)).translation();
  EXPECT_NEAR((p0 - Vec3(350 + 1350 + 1400 + 240, 0, 675 + 41)).norm(), 0.0, kPosTolMm);
  // KUKA home (0,−90,90,0,0,0): upper arm vertical, forearm horizontal.
  const Isometry3 home = BaseFromFlange(kr, Deg(0, -90, 90, 0, 0, 0));
  EXPECT_NEAR((home.translation() - Vec3(350 + 1400 + 240, 0, 675 + 1350 + 41)).norm(), 0.0, kPosTolMm);
  EXPECT_NEAR((home.linear().col(2) - Vec3::UnitX()).norm(), 0.0, kRotTol);  // flange Z forward
}

TEST(ForwardKinematics, SingleJointRotationsClosedForm) {
  // Turning one joint moves the flange rigidly about that joint's axis (a line known from the
  // pose before the turn). Axis of joint 1 = Z0 through the origin; joint 2 of the KR150 = +Y0
  // through (350, 0, 675); joint 6 = the flange's own Z.
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  const RobotModel ur = LoadShippedRobot("ur10.yaml");
  const Isometry3 kr0 = BaseFromFlange(kr, Deg(0, 0, 0, 0, 0, 0));
  const Isometry3 ur0 = BaseFromFlange(ur, Deg(0, 0, 0, 0, 0, 0));
  for (double deg : {-170.0, -35.0, 12.5, 90.0}) {
    const double phi = DegToRad(deg);
    // UR10 joint 1 (sign +1) and KR150 joint 1 (sign −1).
    const Isometry3 ur1 = BaseFromFlange(ur, Deg(deg, 0, 0, 0, 0, 0));
    EXPECT_NEAR((ur1.translation() - RotZ(phi) * ur0.translation()).norm(), 0.0, kPosTolMm) << deg;
    EXPECT_NEAR(RotationAngleBetween(ur1.linear(), RotZ(phi) * ur0.linear()), 0.0, kRotTol) << deg;
    const Isometry3 kr1 = BaseFromFlange(kr, Deg(deg, 0, 0, 0, 0, 0));
    EXPECT_NEAR((kr1.translation() - RotZ(-phi) * kr0.translation()).norm(), 0.0, kPosTolMm) << deg;
    // KR150 joint 2: rotation about +Y0 through (350, 0, 675); positive lowers the arm.
    const Vec3 pivot(350, 0, 675);
    const Isometry3 kr2 = BaseFromFlange(kr, Deg(0, deg, 0, 0, 0, 0));
    EXPECT_NEAR((kr2.translation() - (pivot + RotY(phi) * (kr0.translation() - pivot))).norm(), 0.0, kPosTolMm);
    // Joint 6: position fixed, orientation turns about the flange Z.
    const Isometry3 kr6 = BaseFromFlange(kr, Deg(0, 0, 0, 0, 0, deg));
    EXPECT_NEAR((kr6.translation() - kr0.translation()).norm(), 0.0, kPosTolMm);
    EXPECT_NEAR(RotationAngleBetween(kr6.linear(), kr0.linear() * RotZ(phi)), 0.0, kRotTol);
  }
  EXPECT_LT(BaseFromFlange(kr, Deg(0, 10, 0, 0, 0, 0)).translation().z(), kr0.translation().z());
}

TEST(ForwardKinematics, MatchesKdlPeerOnRandomConfigurations) {
  std::vector<RobotModel> robots = {LoadShippedRobot("kawasaki_bx200l.yaml"), LoadShippedRobot("ur10.yaml"),
                                    LoadShippedRobot("kuka_kr150_r3100.yaml")};
  // A drifted KR150 with every parameter (β on all joints too) away from nominal.
  robots.push_back(PerturbedModel(robots[2], 3, 2.0, DegToRad(0.5), /*all_params=*/true));
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (const RobotModel& robot : robots) {
    for (int n = 0; n < 200; ++n) {
      JointVector q;
      for (int i = 0; i < kNumJoints; ++i) q[i] = u(rng);
      const Isometry3 ours = BaseFromFlange(robot, q);
      const Isometry3 peer = KdlBaseFromFlange(robot, q);
      ASSERT_NEAR((ours.translation() - peer.translation()).norm(), 0.0, kPosTolMm) << robot.name;
      ASSERT_NEAR(RotationAngleBetween(ours.linear(), peer.linear()), 0.0, kRotTol) << robot.name;
    }
  }
}

TEST(ForwardKinematics, ChainFramesEndAtTheFlange) {
  const RobotModel kr = PerturbedModel(LoadShippedRobot("kuka_kr150_r3100.yaml"), 5, 1.0, 0.01, true);
  const JointVector q = Deg(10, -70, 80, 30, 45, -60);
  const ChainFrames f = ComputeChainFrames(kr, q);
  EXPECT_TRUE(f.base_from_link[kNumJoints].isApprox(BaseFromFlange(kr, q), 1e-14));
  const JointVector theta_in = kr.ModelFromController(q);
  for (int i = 1; i <= kNumJoints; ++i) {
    EXPECT_TRUE(f.link_from_previous[i].isApprox(LinkTransform(kr.links[i - 1], theta_in[i - 1]), 1e-15));
  }
}

TEST(ForwardKinematics, LinkTransformIsThesisEq218Product) {
  // Trans(Z,d)·Rot(Z,θ)·Trans(X,a)·Rot(X,α)·Rot(Y,β) multiplied out factor by factor.
  const LinkParams l{123.0, 0.4, -56.0, -1.2, 0.03};
  const double theta_in = 0.7;
  Isometry3 expected = Isometry3::Identity();
  expected *= Eigen::Translation3d(0, 0, l.d);
  expected *= Eigen::AngleAxisd(l.theta0 + theta_in, Vec3::UnitZ());
  expected *= Eigen::Translation3d(l.a, 0, 0);
  expected *= Eigen::AngleAxisd(l.alpha, Vec3::UnitX());
  expected *= Eigen::AngleAxisd(l.beta, Vec3::UnitY());
  EXPECT_TRUE(LinkTransform(l, theta_in).isApprox(expected, 1e-15));
}

TEST(ForwardKinematics, ControllerMappingRoundTrip) {
  RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  kr.mapping[3] = {-1.0, DegToRad(12.0)};
  const JointVector q = Deg(1, 2, 3, 4, 5, 6);
  const JointVector t = kr.ModelFromController(q);
  EXPECT_NEAR(t[0], -q[0], 1e-16);
  EXPECT_NEAR(t[3], -q[3] + DegToRad(12.0), 1e-16);
  EXPECT_TRUE(kr.ControllerFromModel(t).isApprox(q, 1e-15));
}

}  // namespace
}  // namespace ramtk::kinematics
