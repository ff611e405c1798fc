// Rotations: identities (Sophus-style), thesis conventions, and Eigen's AngleAxis as a peer.
#include "ramtk/core/rotation.h"

#include <gtest/gtest.h>

#include <random>

#include "ramtk/core/units.h"

namespace ramtk {
namespace {

constexpr double kEps = 1e-14;

Mat3 AxisAngle(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

TEST(Rotation, ElementaryRotationsMatchAngleAxisPeer) {
  for (double angle : {-3.0, -1.2, 0.0, 0.3, 1.5707963267948966, 2.9}) {
    EXPECT_TRUE(RotX(angle).isApprox(AxisAngle(Vec3::UnitX(), angle), kEps)) << angle;
    EXPECT_TRUE(RotY(angle).isApprox(AxisAngle(Vec3::UnitY(), angle), kEps)) << angle;
    EXPECT_TRUE(RotZ(angle).isApprox(AxisAngle(Vec3::UnitZ(), angle), kEps)) << angle;
  }
}

TEST(Rotation, ThesisEq28RotZMapsNewAxesIntoOld) {
  // Eq. (2-7): X = x cos κ − y sin κ, Y = x sin κ + y cos κ. A quarter turn sends x to Y.
  const Mat3 r = RotZ(DegToRad(90.0));
  EXPECT_NEAR((r * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, kEps);
  EXPECT_NEAR((r * Vec3::UnitY() + Vec3::UnitX()).norm(), 0.0, kEps);
  // Eq. (2-9): rotation about Y by +90° sends z to X.
  EXPECT_NEAR((RotY(DegToRad(90.0)) * Vec3::UnitZ() - Vec3::UnitX()).norm(), 0.0, kEps);
}

TEST(Rotation, GroupIdentities) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int i = 0; i < 100; ++i) {
    const double a = u(rng), b = u(rng);
    EXPECT_TRUE((RotZ(a) * RotZ(b)).isApprox(RotZ(a + b), kEps));
    EXPECT_TRUE((RotX(a) * RotX(-a)).isApprox(Mat3::Identity(), kEps));
    EXPECT_LT(OrthonormalityError(RotY(a) * RotX(b)), 1e-15);
  }
}

TEST(Rotation, KukaAbcIsSuccessiveRotationAboutNewAxes) {
  // Thesis eq. (2-15): rotating about Z, then the new y, then the newest x gives Rκ·Rφ·Rω.
  // Build the same rotation by turning the frame's own axes one after another with AngleAxis.
  const KukaAbc abc{DegToRad(30.0), DegToRad(-20.0), DegToRad(50.0)};
  Mat3 frame = AxisAngle(Vec3::UnitZ(), abc.a);
  frame = AxisAngle(frame.col(1), abc.b) * frame;  // about the new y, expressed in the old frame
  frame = AxisAngle(frame.col(0), abc.c) * frame;  // about the newest x
  EXPECT_TRUE(RotationFromKukaAbc(abc).isApprox(frame, kEps));
}

TEST(Rotation, KukaAbcRoundTrip) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ua(-kPi, kPi), ub(-kPi / 2, kPi / 2);
  for (int i = 0; i < 1000; ++i) {
    const KukaAbc abc{ua(rng), ub(rng), ua(rng)};
    const KukaAbc back = KukaAbcFromRotation(RotationFromKukaAbc(abc));
    EXPECT_NEAR(back.a, abc.a, 1e-9);
    EXPECT_NEAR(back.b, abc.b, 1e-9);
    EXPECT_NEAR(back.c, abc.c, 1e-9);
  }
}

TEST(Rotation, KukaAbcGimbalLockReproducesRotation) {
  for (double b : {kPi / 2, -kPi / 2}) {
    const Mat3 r = RotationFromKukaAbc({0.4, b, -0.7});
    const KukaAbc back = KukaAbcFromRotation(r);
    EXPECT_EQ(back.c, 0.0);
    EXPECT_TRUE(RotationFromKukaAbc(back).isApprox(r, 1e-12));
  }
}

TEST(Rotation, EulerZxzMatchesThesisEq43Entries) {
  // Entries of eq. (4-3) typed from the thesis.
  const double A = 0.3, B = 1.1, C = -0.8;
  const double cA = std::cos(A), sA = std::sin(A), cB = std::cos(B), sB = std::sin(B), cC = std::cos(C),
               sC = std::sin(C);
  Mat3 expected;
  expected << cA * cC - sA * cB * sC, -cA * sC - sA * cB * cC, sA * sB,  //
      sA * cC + cA * cB * sC, -sA * sC + cA * cB * cC, -cA * sB,         //
      sB * sC, sB * cC, cB;
  EXPECT_TRUE(RotationFromEulerZxz({A, B, C}).isApprox(expected, kEps));
}

TEST(Rotation, EulerZxzRoundTripAndSingularity) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> ua(-kPi, kPi), ub(0.01, kPi - 0.01);
  for (int i = 0; i < 1000; ++i) {
    const EulerZxz e{ua(rng), ub(rng), ua(rng)};
    const EulerZxz back = EulerZxzFromRotation(RotationFromEulerZxz(e));
    EXPECT_NEAR(back.a, e.a, 1e-9);
    EXPECT_NEAR(back.b, e.b, 1e-9);
    EXPECT_NEAR(back.c, e.c, 1e-9);
  }
  for (double b : {0.0, kPi}) {
    const Mat3 r = RotationFromEulerZxz({0.5, b, 0.2});
    EXPECT_TRUE(RotationFromEulerZxz(EulerZxzFromRotation(r)).isApprox(r, 1e-12));
  }
}

TEST(Rotation, LogAndAngleBetween) {
  const Vec3 axis = Vec3(1, -2, 0.5).normalized();
  const Mat3 r = AxisAngle(axis, 0.7);
  EXPECT_NEAR((LogSO3(r) - 0.7 * axis).norm(), 0.0, 1e-14);
  EXPECT_NEAR(RotationAngleBetween(RotX(0.2), RotX(0.5)), 0.3, 1e-14);
  EXPECT_NEAR(LogSO3(Mat3::Identity()).norm(), 0.0, 0.0);
}

TEST(Rotation, OrthonormalityErrorDetectsNonRotation) {
  Mat3 r = RotZ(0.3);
  r(0, 0) += 1e-3;
  EXPECT_GT(OrthonormalityError(r), 5e-4);
  Mat3 reflection = Mat3::Identity();
  reflection(2, 2) = -1;
  EXPECT_NEAR(OrthonormalityError(reflection), 2.0, 1e-15);
}

// NearestRotation (one implementation for the four places that had their own, one without the
// reflection guard): a rotation is its own nearest; a rotation times a small symmetric stretch
// comes back to the rotation (the polar factor, to first order exactly); a reflection gives a
// proper rotation; the result minimises the Frobenius distance against random rotations.
TEST(Rotation, NearestRotationIsThePolarFactorAndNeverAReflection) {
  const Mat3 r = RotZ(0.3) * RotY(-1.1) * RotX(2.0);
  EXPECT_LT((NearestRotation(r) - r).norm(), 1e-14);
  Mat3 s = Mat3::Identity();
  s(0, 1) = s(1, 0) = 1e-3;
  s(2, 2) = 1.002;
  EXPECT_LT((NearestRotation(r * s) - r).norm(), 1e-12);
  Mat3 flip = Mat3::Identity();
  flip(2, 2) = -1;
  const Mat3 n = NearestRotation(r * flip);
  EXPECT_NEAR(n.determinant(), 1.0, 1e-12);
  EXPECT_LT(OrthonormalityError(n), 1e-12);
  const Mat3 m = r * s + 0.05 * Mat3::Random();
  const Mat3 best = NearestRotation(m);
  for (int i = 0; i < 200; ++i) {
    const Mat3 other = best * RotX(0.01 * Vec3::Random()[0]) * RotY(0.01 * Vec3::Random()[1]);
    EXPECT_LE((best - m).norm(), (other - m).norm() + 1e-12);
  }
}

TEST(Rotation, SkewIsTheCrossProduct) {
  const Vec3 v(0.3, -1.2, 2.5), w(-0.7, 0.4, 1.1);
  EXPECT_LT((Skew(v) * w - v.cross(w)).norm(), 1e-15);
  EXPECT_LT((Skew(v) + Skew(v).transpose()).norm(), 1e-15);
}

}  // namespace
// The exp map against Rodrigues' formula written out, and as the inverse of the log map.
TEST(Rotation, ExpSO3IsRodriguesAndInvertsLogSO3) {
  const Vec3 w(0.3, -1.1, 0.4);
  const double t = w.norm();
  const Mat3 k = Skew(w / t);
  const Mat3 rodrigues = Mat3::Identity() + std::sin(t) * k + (1.0 - std::cos(t)) * k * k;
  EXPECT_LT((ExpSO3(w) - rodrigues).norm(), 1e-14);
  EXPECT_LT((LogSO3(ExpSO3(w)) - w).norm(), 1e-13);
  EXPECT_EQ(ExpSO3(Vec3::Zero()), Mat3::Identity());
}

}  // namespace ramtk
