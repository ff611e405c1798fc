// Uses the installed ramtk: FK of the installed BX200L model at the thesis pose.
#include <cmath>
#include <cstdio>

#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  using namespace ramtk::kinematics;
  const RobotModel bx = ReadRobotModel(argv[1]);
  JointVector q = JointVector::Zero();
  q[0] = ramtk::DegToRad(90.0);
  const ramtk::Vec3 p = BaseFromFlange(bx, q).translation();
  std::printf("%.4f %.4f %.4f\n", p.x(), p.y(), p.z());
  return std::abs(p.x() - 1675.0) < 1e-9 && std::abs(p.z() - 1920.0) < 1e-9 ? 0 : 1;
}
