// The cross-laser device log (CSV time_s,beam,state): docs/formats.md.
#include "fuzz_common.h"
#include "ramtk/tcf/device_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const auto events = ramtk::tcf::ParseDeviceLog(ramtk::fuzz::Text(data, size), "/fuzz/laser_log.csv");
    (void)ramtk::tcf::FormatDeviceLog(events);
  });
}
