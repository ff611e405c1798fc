#pragma once
// Geometry shared by the laser-device simulator, solver and diagnosis, written once.
#include "ramtk/core/rotation.h"

namespace ramtk::tcf {

// Shortest distance from the line through p with unit direction d to the ray {c + μ·e : μ ≥ 0}
// (e unit): the tool's axis seen from a laser beam. Parallel line and ray give the distance from
// c to the line.
double LineToRayDistance(const Vec3& p, const Vec3& d, const Vec3& c, const Vec3& e);

}  // namespace ramtk::tcf
