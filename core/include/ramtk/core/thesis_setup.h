#pragma once
// The source thesis's measured set-up, written once: the fixed sensor's pose in the
// robot base, eq. (5-1), its printed 4-decimal rotation projected onto SO(3), and the ball centre
// in the flange frame, eq. (5-2). Simulators of several modules default to them.
#include "ramtk/core/rotation.h"

namespace ramtk {

// sensor_from_base of eq. (5-1): translation in mm, rotation the nearest rotation to the printed
// matrix (which is orthonormal only to ~1e-4).
Isometry3 ThesisSensorFromBase();

// ball_in_flange of eq. (5-2), mm.
Vec3 ThesisBallInFlange();

}  // namespace ramtk
