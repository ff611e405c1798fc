#include "pose_print.h"

#include <cstdio>

#include "ramtk/core/units.h"

namespace ramtk::tools {

std::string FormatPose(const std::string& title, const Isometry3& pose) {
  const Vec3 t = pose.translation();
  const Mat3 r = pose.linear();
  const KukaAbc abc = KukaAbcFromRotation(r);
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "%s\n"
                "  position (mm)        x %12.4f   y %12.4f   z %12.4f\n"
                "  rotation             [%9.6f %9.6f %9.6f]\n"
                "                       [%9.6f %9.6f %9.6f]\n"
                "                       [%9.6f %9.6f %9.6f]\n"
                "  KUKA A,B,C (deg)     A %12.4f   B %12.4f   C %12.4f\n",
                title.c_str(), t.x(), t.y(), t.z(), r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0),
                r(2, 1), r(2, 2), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  return buf;
}

}  // namespace ramtk::tools
