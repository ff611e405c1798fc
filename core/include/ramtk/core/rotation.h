#pragma once
// Rotations and rigid transforms. Conventions (see docs/conventions.md):
//  * A transform named target_from_source maps coordinates in `source` into `target`:
//      x_in_target = target_from_source * x_in_source.
//  * Elementary rotations RotX/RotY/RotZ are active, right-handed (thesis eqs. 2-8..2-10); their
//    columns are the rotated frame's axes expressed in the original frame.
//  * Successive rotations about the *new* axes multiply on the right (thesis eq. 2-15,
//    R_right = Rκ·Rφ·Rω). KUKA's A,B,C are exactly that: R = RotZ(A)·RotY(B)·RotX(C).
//  * The Euler form of thesis eq. (4-3) is Z-X-Z about new axes: R = RotZ(A)·RotX(B)·RotZ(C).
// All angles here are radians.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ramtk {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Isometry3 = Eigen::Isometry3d;

Mat3 RotX(double angle);
Mat3 RotY(double angle);
Mat3 RotZ(double angle);

// KUKA A,B,C (= thesis κ, φ, ω of eq. 2-15): R = RotZ(a)·RotY(b)·RotX(c).
struct KukaAbc {
  double a = 0.0;  // about Z
  double b = 0.0;  // about the new Y
  double c = 0.0;  // about the newest X
};
Mat3 RotationFromKukaAbc(const KukaAbc& abc);
// Inverse of RotationFromKukaAbc with b in [-pi/2, pi/2]. At the singularity |b| = pi/2 only
// a - c (b > 0) or a + c (b < 0) is defined; c is then set to 0.
KukaAbc KukaAbcFromRotation(const Mat3& rotation);

// Euler Z-X-Z of thesis eq. (4-3): R = RotZ(a)·RotX(b)·RotZ(c).
struct EulerZxz {
  double a = 0.0;
  double b = 0.0;
  double c = 0.0;
};
Mat3 RotationFromEulerZxz(const EulerZxz& zxz);
// Inverse of RotationFromEulerZxz with b in [0, pi]; at b = 0 or pi, c is set to 0.
EulerZxz EulerZxzFromRotation(const Mat3& rotation);

// Angle (radians, in [0, pi]) of the relative rotation a^T·b.
double RotationAngleBetween(const Mat3& a, const Mat3& b);

// Rotation vector (axis * angle) of R, log map of SO(3).
Vec3 LogSO3(const Mat3& rotation);
// The rotation of a rotation vector (axis * angle), exp map of SO(3); the inverse of LogSO3.
Mat3 ExpSO3(const Vec3& rotation_vector);

// Largest deviation of R^T R from identity, and |det R - 1|: how far R is from a rotation.
double OrthonormalityError(const Mat3& rotation);

// The rotation nearest to m in the Frobenius norm (U·diag(1, 1, det(U Vᵀ))·Vᵀ of m's SVD): never a
// reflection, also when det m < 0. Of a sum of rotations, their chordal mean.
Mat3 NearestRotation(const Mat3& m);

// The cross-product matrix [v]×, so that Skew(v)·w = v × w.
Mat3 Skew(const Vec3& v);

}  // namespace ramtk
