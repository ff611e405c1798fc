#pragma once
// Stacks of camera frames. Frames are loaded as single-channel CV_32F matrices in digital numbers
// (DN) of their native depth (0..255 for 8 bit, 0..65535 for 16 bit), or as stored (native).
// Every error names the file.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/image/image_file.h"

namespace ramtk::vision {

// Single image files (limits, loaders, the atomic writer) live in ramtk::image; the names are
// available here too.
using image::kMaxImagePixels;
using image::kMaxImageSide;
using image::LoadImageDn;
using image::LoadImageNative;
using image::WriteImage;

// An ordered stack of camera frames of one size and one bit depth.
struct ImageStack {
  std::vector<cv::Mat> frames;     // CV_32FC1, DN (native loading: CV_8UC1 / CV_16UC1 for grey files)
  std::vector<std::string> files;  // source file of each frame
  int bits_per_sample = 8;         // 8 or 16
  double full_scale = 255.0;       // 2^bits - 1
};

// Loads all files (`native`: with LoadImageNative, else LoadImageDn); InputError naming the first file whose size or bit depth differs from the
// first one, and naming the set if every image is dark (brightest sample < dark_fraction of
// full scale).
ImageStack LoadImageStack(const std::vector<std::string>& paths, double dark_fraction = 0.02, bool native = false);

}  // namespace ramtk::vision
