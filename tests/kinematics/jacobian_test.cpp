// The analytic parameter Jacobian (thesis eq. 3-6) against central finite differences of the
// forward kinematics, and the joint Jacobian against Orocos KDL.
#include "ramtk/kinematics/jacobian.h"

#include <gtest/gtest.h>

#include <random>

#include "kdl_peer.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using testing::LoadShippedRobot;
using testing::PerturbedModel;

// Central-difference steps. Lengths enter FK linearly, so their difference has no truncation
// error; for angles h = 1e-6 rad gives truncation ~h²·|f'''| ≈ 1e-12·3000 mm and rounding
// ~eps·|f|/h ≈ 2e-16·3000/1e-6 ≈ 6e-7 mm per rad, i.e. relative errors ~1e-9 of columns whose
// size is ~10³ mm/rad. The required relative error is 1e-6 (the figure).
constexpr double kLengthStep = 1e-3;
constexpr double kAngleStep = 1e-6;
constexpr double kRelTol = 1e-6;

double Step(int k) { return IsAngleParam(k) ? kAngleStep : kLengthStep; }

RobotModel WithParam(const RobotModel& m, int k, double delta) {
  RobotModel out = m;
  ParamVector p = m.Params();
  p[k] += delta;
  out.SetParams(p);
  return out;
}

// Relative error of a column: |analytic − numeric| / max(|numeric|, 1), where 1 is one unit
// (mm per mm or mm per rad) so that columns that are zero by geometry are held to 1e-6 absolute.
double ColumnError(const Eigen::VectorXd& analytic, const Eigen::VectorXd& numeric) {
  return (analytic - numeric).norm() / std::max(numeric.norm(), 1.0);
}

struct Case {
  RobotModel model;
  JointVector q;
};

std::vector<Case> RandomCases(int count, unsigned seed) {
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  const RobotModel bx = LoadShippedRobot("kawasaki_bx200l.yaml");
  const RobotModel ur = LoadShippedRobot("ur10.yaml");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  std::vector<Case> cases;
  for (int n = 0; n < count; ++n) {
    Case c;
    // Cycle through nominal robots and drifted ones with every parameter non-zero (β on all
    // joints), so each of the 30 formulas is exercised away from special values.
    switch (n % 4) {
      case 0: c.model = kr; break;
      case 1: c.model = PerturbedModel(kr, seed + n, 3.0, DegToRad(2.0), true); break;
      case 2: c.model = PerturbedModel(bx, seed + n, 3.0, DegToRad(2.0), true); break;
      default: c.model = PerturbedModel(ur, seed + n, 3.0, DegToRad(2.0), true); break;
    }
    for (int i = 0; i < kNumJoints; ++i) c.q[i] = u(rng);
    cases.push_back(c);
  }
  return cases;
}

TEST(ParamJacobian, PointJacobianMatchesCentralDifferences) {
  const Vec3 ball_in_flange(12.0, -25.0, 160.0);  // an eq. 5-2-like ball offset
  double worst = 0.0;
  for (const Case& c : RandomCases(40, 100)) {
    const PointParamJacobian jac = ComputePointParamJacobian(c.model, c.q, ball_in_flange);
    for (int k = 0; k < kNumParams; ++k) {
      const double h = Step(k);
      const Vec3 plus = BaseFromFlange(WithParam(c.model, k, h), c.q) * ball_in_flange;
      const Vec3 minus = BaseFromFlange(WithParam(c.model, k, -h), c.q) * ball_in_flange;
      const Vec3 numeric = (plus - minus) / (2 * h);
      const double err = ColumnError(jac.col(k), numeric);
      worst = std::max(worst, err);
      ASSERT_LT(err, kRelTol) << ParamName(k) << " of " << c.model.name;
    }
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(ParamJacobian, FlangeDifferentialsMatchCentralDifferencesOfTheMatrix) {
  for (const Case& c : RandomCases(12, 200)) {
    const std::array<Mat4, kNumParams> d = FlangeDifferentials(c.model, c.q);
    for (int k = 0; k < kNumParams; ++k) {
      const double h = Step(k);
      const Mat4 numeric = (BaseFromFlange(WithParam(c.model, k, h), c.q).matrix() -
                            BaseFromFlange(WithParam(c.model, k, -h), c.q).matrix()) /
                           (2 * h);
      const double err = (d[k] - numeric).norm() / std::max(numeric.norm(), 1.0);
      ASSERT_LT(err, kRelTol) << ParamName(k);
      EXPECT_EQ(d[k].row(3).norm(), 0.0);  // thesis: the fourth row of A_qi (and dT) is zero
    }
  }
}

TEST(ParamJacobian, LinkDifferentialIsInverseTimesDerivative) {
  // A_qi = (T_i^{i-1})^{-1} · ∂T_i^{i-1}/∂q_i, with ∂T by central differences of LinkTransform.
  const LinkParams l{210.0, 0.3, 640.0, -1.4, 0.02};
  const double theta_in = -0.9;
  for (int kind = 0; kind < 5; ++kind) {
    const ParamKind pk = static_cast<ParamKind>(kind);
    const double h = (pk == ParamKind::kD || pk == ParamKind::kA) ? kLengthStep : kAngleStep;
    auto shifted = [&](double delta) {
      LinkParams s = l;
      switch (pk) {
        case ParamKind::kD: s.d += delta; break;
        case ParamKind::kTheta: s.theta0 += delta; break;
        case ParamKind::kA: s.a += delta; break;
        case ParamKind::kAlpha: s.alpha += delta; break;
        case ParamKind::kBeta: s.beta += delta; break;
      }
      return LinkTransform(s, theta_in).matrix();
    };
    const Mat4 numeric = LinkTransform(l, theta_in).inverse().matrix() * (shifted(h) - shifted(-h)) / (2 * h);
    EXPECT_LT((LinkDifferential(l, theta_in, pk) - numeric).norm(), 1e-7) << kind;
  }
}

TEST(ParamJacobian, PoseJacobianMatchesCentralDifferences) {
  for (const Case& c : RandomCases(12, 300)) {
    const PoseParamJacobian jac = ComputePoseParamJacobian(c.model, c.q);
    for (int k = 0; k < kNumParams; ++k) {
      const double h = Step(k);
      const Isometry3 plus = BaseFromFlange(WithParam(c.model, k, h), c.q);
      const Isometry3 minus = BaseFromFlange(WithParam(c.model, k, -h), c.q);
      Eigen::Matrix<double, 6, 1> numeric;
      numeric.head<3>() = (plus.translation() - minus.translation()) / (2 * h);
      numeric.tail<3>() = LogSO3(plus.linear() * minus.linear().transpose()) / (2 * h);
      ASSERT_LT(ColumnError(jac.col(k).head<3>(), numeric.head<3>()), kRelTol) << ParamName(k);
      // Angular rows are rad per unit (≤ 1); hold them to 1e-6 absolute.
      ASSERT_LT((jac.col(k).tail<3>() - numeric.tail<3>()).norm(), kRelTol) << ParamName(k);
    }
  }
}

TEST(JointJacobian, MatchesKdlPeerAndThetaColumns) {
  for (const Case& c : RandomCases(40, 400)) {
    const JointJacobian ours = ComputeJointJacobian(c.model, c.q);
    const Eigen::Matrix<double, 6, 6> peer = testing::KdlJointJacobian(c.model, c.q);
    ASSERT_LT((ours - peer).norm() / peer.norm(), 1e-12) << c.model.name;
    // ∂/∂q_i = sign_i · ∂/∂θ_i.
    const PoseParamJacobian pj = ComputePoseParamJacobian(c.model, c.q);
    for (int i = 0; i < kNumJoints; ++i) {
      ASSERT_LT((ours.col(i) - c.model.mapping[i].sign * pj.col(ParamIndex(ParamKind::kTheta, i))).norm(), 1e-9);
    }
  }
}

TEST(ParamJacobian, StructuralZerosOfTheKr150) {
  // Thesis eq. (3-6): β1, d2, β3..β6 are fixed at zero; 24 parameters remain.
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  const std::vector<int> free = kr.FreeParams();
  EXPECT_EQ(free.size(), 24u);
  for (const char* name : {"beta1", "d2", "beta3", "beta4", "beta5", "beta6"}) {
    EXPECT_TRUE(kr.structural_zero[ParamIndexFromName(name)]) << name;
  }
  EXPECT_FALSE(kr.structural_zero[ParamIndexFromName("beta2")]);
  // β2 tilts Z2 about Y2 and swings everything beyond joint 2 (lever ~ 1.5 m): its column is
  // far from zero, so it is identifiable where d2 would not be.
  const PointParamJacobian j = ComputePointParamJacobian(kr, JointVector::Constant(0.3), Vec3(0, 0, 100));
  EXPECT_GT(j.col(ParamIndexFromName("beta2")).norm(), 100.0);
}

}  // namespace
}  // namespace ramtk::kinematics
