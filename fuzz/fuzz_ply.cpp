// Point clouds (PLY, ASCII and binary little-endian): the reader takes a path, so each input is
// written to a scratch file first.
#include <unistd.h>

#include <fstream>

#include "fuzz_common.h"
#include "ramtk/vision/stereo/point_cloud.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/ramtk-fuzz-" + std::to_string(::getpid()) + ".ply";
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  RAMTK_FUZZ_BODY({
    const auto cloud = ramtk::vision::ReadPly(path);
    cloud.Check(path);
    (void)ramtk::vision::PlyBytes(cloud);
  });
}
