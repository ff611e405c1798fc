// Independent cross-laser device log generator (issue 15): a ball-nosed tool on the flange circles
// and plunges through two crossing line beams; the receiver logs every blocked/clear change.
// See README.md for the physics.
#pragma once

#include "common.h"

#include <Eigen/Geometry>

namespace indep {

// Shortest distance between the infinite line p + s·d (d unit) and the segment [a, b].
double LineSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b);

// KUKA A, B, C (deg) of a rotation R = RotZ(A)·RotY(B)·RotX(C).
Eigen::Vector3d KukaAbcDeg(const Eigen::Matrix3d& r);

void GenerateLaser(const GenOptions& options);

}  // namespace indep
