#pragma once
// Image files: reading camera frames and board views, writing pictures. PNG (libpng) and
// uncompressed BMP (read here) are the fast path; every other format (TIFF, EXR, JPEG, PGM, ...)
// and float images go through an OpenImageIO module loaded on first use. Nothing here links
// OpenCV's imgcodecs, whose dependencies (GDAL, GDCM, ...) cost ~0.15 s at every program start
// (docs/performance.md). Every error is an InputError naming the file.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ramtk::image {

// Limits checked against an image header before any pixel is allocated (InputError naming the
// file beyond them): 4× the side of the largest machine-vision sensors, 268 Mpx.
inline constexpr int kMaxImageSide = 32768;
inline constexpr long long kMaxImagePixels = 1LL << 28;

// Loads one 8- or 16-bit image as single-channel CV_32F digital numbers (colour averaged, alpha
// ignored, values rounded to 1/16 DN). InputError naming the file if it is missing, unreadable or
// of another pixel type.
cv::Mat LoadImageDn(const std::string& path, int* bits_per_sample);

// Loads one single-channel 8- or 16-bit image as it is stored (CV_8UC1 / CV_16UC1, no copy into
// float); other images go through LoadImageDn (CV_32F). Same errors as LoadImageDn.
cv::Mat LoadImageNative(const std::string& path, int* bits_per_sample);

// Loads one image as 8-bit grey (CV_8UC1), as board detection wants it: colour converted with the
// ITU-R BT.601 luma weights (cv::COLOR_BGR2GRAY), 16-bit samples scaled by 255/65535.
cv::Mat LoadImageGrey8(const std::string& path);

// Writes a CV_32FC1 / CV_8UC1 / CV_8UC3 (BGR) / CV_16UC1 matrix; the format follows the
// extension (.png here; .tif/.tiff/.exr and others through the OpenImageIO module). Written to
// "<stem>.tmp<ext>" beside the target and renamed, so a failure leaves nothing.
void WriteImage(const std::string& path, const cv::Mat& image);

// PNG file bytes of an 8/16-bit matrix with 1, 3 (BGR) or 4 (BGRA) channels; InputError naming
// `what` if the matrix cannot be encoded.
std::vector<unsigned char> EncodePng(const cv::Mat& image, const std::string& what = "picture");

// PNG file bytes of a palette picture: a CV_8UC1 matrix of indices into `palette_bgr` (1 to 256
// colours, BGR). A third the bytes of the BGR picture to compress (false-colour previews).
// InputError naming `what` for an empty palette, more than 256 colours or an index beyond it.
std::vector<unsigned char> EncodeIndexedPng(const cv::Mat& index, const std::vector<cv::Vec3b>& palette_bgr,
                                            const std::string& what = "picture");

}  // namespace ramtk::image
