// The robot model YAML; a model that parses is also run through forward kinematics.
#include "fuzz_common.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const auto model = ramtk::kinematics::ParseRobotModel(ramtk::fuzz::Text(data, size), "fuzz.yaml");
    (void)ramtk::kinematics::BaseFromFlange(model, ramtk::kinematics::JointVector::Zero());
    (void)ramtk::kinematics::RobotModelToYaml(model);
  });
}
