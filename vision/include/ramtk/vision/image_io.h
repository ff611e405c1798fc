#pragma once
// Image input/output through OpenImageIO. Camera images are loaded as single-channel CV_32F
// matrices in digital numbers (DN) of their native depth (0..255 for 8 bit, 0..65535 for 16
// bit). Every error names the file. Outputs are written to a temporary file and renamed.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ramtk::vision {

// Limits checked against an image header before any pixel is allocated (InputError naming the
// file beyond them): 4× the side of the largest machine-vision sensors, 268 Mpx.
inline constexpr int kMaxImageSide = 32768;
inline constexpr long long kMaxImagePixels = 1LL << 28;

// An ordered stack of camera frames of one size and one bit depth.
struct ImageStack {
  std::vector<cv::Mat> frames;     // CV_32FC1, DN (native loading: CV_8UC1 / CV_16UC1 for grey files)
  std::vector<std::string> files;  // source file of each frame
  int bits_per_sample = 8;         // 8 or 16
  double full_scale = 255.0;       // 2^bits - 1
};

// Loads one 8- or 16-bit image (multi-channel images are averaged to grey). InputError naming
// the file if it is missing, unreadable or of another pixel type.
cv::Mat LoadImageDn(const std::string& path, int* bits_per_sample);

// Loads one single-channel 8- or 16-bit image as it is stored (CV_8UC1 / CV_16UC1, no copy into
// float); other images go through LoadImageDn (CV_32F). Same errors as LoadImageDn.
cv::Mat LoadImageNative(const std::string& path, int* bits_per_sample);

// Loads all files (`native`: with LoadImageNative, else LoadImageDn); InputError naming the first file whose size or bit depth differs from the
// first one, and naming the set if every image is dark (brightest sample < dark_fraction of
// full scale).
ImageStack LoadImageStack(const std::vector<std::string>& paths, double dark_fraction = 0.02, bool native = false);

// Writes a CV_32FC1 / CV_8UC1 / CV_8UC3 / CV_16UC1 matrix; the format follows the extension
// (.tif/.tiff/.exr/.png). Written to "<path>.tmp<ext>" and renamed, so a failure leaves nothing.
void WriteImage(const std::string& path, const cv::Mat& image);

}  // namespace ramtk::vision
