// The fringe image set manifest (JSON).
#include "fuzz_common.h"
#include "ramtk/vision/fringe/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const auto m = ramtk::vision::ParseFringeManifest(ramtk::fuzz::Text(data, size), "/fuzz/manifest.json");
    (void)m.ImageCount();
    (void)m.InputFiles();
    (void)ramtk::vision::FringeManifestToJson(m);
  });
}
