// The OpenImageIO half of image_file.cpp, built as a plugin (a shared module, `ramtk_oiio_backend`)
// and loaded with dlopen the first time a format the PNG/BMP fast path does not take is read or
// written (TIFF, EXR, JPEG, PGM, ..., float images). Linking OpenImageIO into every program costs
// 117 shared libraries and ~0.14 s at each start (docs/performance.md); PNG and BMP camera frames,
// the common case, never load it. The interface is plain C++ without exceptions: errors come back
// as text, so no exception crosses the module boundary.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace ramtk::image::detail {

struct OiioBackend {
  int version = 1;
  // Reads an 8/16-bit image converted to single-channel CV_32F DN (colour averaged, alpha ignored),
  // after checking the header against the limits. Returns false with *error set.
  bool (*load_dn)(const std::string& path, int max_side, long long max_pixels, cv::Mat* out, int* bits,
                  std::string* error) = nullptr;
  // Reads a single-channel 8/16-bit image as stored (CV_8UC1 / CV_16UC1); *converted = true when
  // the file is not such an image and it was read as load_dn does instead.
  bool (*load_native)(const std::string& path, int max_side, long long max_pixels, cv::Mat* out, int* bits,
                      std::string* error) = nullptr;
  // Writes the matrix (CV_8U/16U/32F, 1 or 3 channels BGR) to exactly `path` (format from the
  // extension; float with zip compression).
  bool (*write)(const std::string& path, const cv::Mat& image, std::string* error) = nullptr;
};

}  // namespace ramtk::image::detail

// The plugin's one exported symbol.
extern "C" const ramtk::image::detail::OiioBackend* ramtk_oiio_backend();
