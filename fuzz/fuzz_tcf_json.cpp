// The laser device's JSON inputs: programmed motion (motion.json) and sensor frame (sensor.json).
// The first byte picks the reader so one corpus grows both.
#include "fuzz_common.h"
#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool motion = data[0] & 1;
  RAMTK_FUZZ_BODY({
    const std::string text = ramtk::fuzz::Text(data + 1, size - 1);
    if (motion) {
      const auto m = ramtk::tcf::ProgrammedMotionFromJson(text, "/fuzz/motion.json");
      (void)ramtk::tcf::ProgrammedMotionToJson(m);
    } else {
      const auto s = ramtk::tcf::SensorFrameFromJson(text, "/fuzz/sensor.json");
      (void)ramtk::tcf::SensorFrameToJson(s);
    }
  });
}
