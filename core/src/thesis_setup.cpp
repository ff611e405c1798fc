#include "ramtk/core/thesis_setup.h"

namespace ramtk {

Isometry3 ThesisSensorFromBase() {
  Mat3 r;  // eq. (5-1) as printed, 4 decimals
  r << 0.9003, -0.1695, -0.4009, -0.1695, 0.7117, -0.6817, 0.4009, 0.6817, 0.6120;
  Isometry3 t = Isometry3::Identity();
  t.linear() = NearestRotation(r);
  t.translation() = Vec3(2037.2109, -1761.8217, 343.7652);
  return t;
}

Vec3 ThesisBallInFlange() { return Vec3(43.0823, -5.6419, 306.7015); }

}  // namespace ramtk
