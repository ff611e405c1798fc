// The robot measurement CSV (ball / monitoring files, thesis thermal experiment, `ramtk measure`).
#include "fuzz_common.h"
#include "ramtk/kinematics/measurements_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const auto set = ramtk::kinematics::ParseRobotMeasurements(ramtk::fuzz::Text(data, size), "fuzz.csv");
    if (ramtk::kinematics::HasCentreCovariance(set, "fuzz.csv"))
      for (const auto& row : set.rows) (void)ramtk::kinematics::CentreCovariance(row, "fuzz.csv");
  });
}
