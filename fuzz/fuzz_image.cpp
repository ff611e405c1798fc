// Camera frames as `ramtk scan` and `ramtk decode` load them: the PNG/BMP header check against
// the size limits, then OpenCV's decoders (the OpenImageIO module is not loaded here, so other
// formats must end in an InputError naming the file).
#include <cstdio>
#include <fstream>
#include <opencv2/core.hpp>
#include <unistd.h>

#include "fuzz_common.h"
#include "ramtk/vision/fringe/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/ramtk_fuzz_image_" + std::to_string(::getpid()) + ".png";
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  RAMTK_FUZZ_BODY({
    int bits = 0;
    const cv::Mat m = ramtk::vision::LoadImageNative(path, &bits);
    if (m.empty() || (bits != 8 && bits != 16) || m.channels() != 1) __builtin_trap();  // never a half answer
  });
}
