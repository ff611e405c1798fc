// The stereo calibration file (OpenCV FileStorage YAML/JSON, either layout: `ramtk calib cameras`
// or SLMaster's caliInfo.yml), read and written back.
#include <unistd.h>

#include <cstdio>

#include "fuzz_common.h"
#include "ramtk/camera/stereo_calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const auto c = ramtk::camera::ParseStereoCalibration(ramtk::fuzz::Text(data, size), "/fuzz/calibration.yml");
    // What a file that parses must also survive: a round trip through the writer.
    static const std::string out = "/tmp/ramtk_fuzz_calib_" + std::to_string(::getpid()) + ".yml";
    ramtk::camera::WriteStereoCalibration(out, c);
    (void)ramtk::camera::ReadStereoCalibration(out);
    std::remove(out.c_str());
  });
}
