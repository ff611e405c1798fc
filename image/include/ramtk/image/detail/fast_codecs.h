// The fast path of image_file.cpp: PNG through libpng, uncompressed BMP read here. Both give what
// OpenCV's imread(IMREAD_UNCHANGED) gives: 8/16-bit samples, 1 channel for grey, 3 (BGR) or 4
// (BGRA) for colour; 16-bit in host order.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ramtk::image::detail {

inline constexpr const char* kNotReadHere = "not read here";

// Closes an fopen'ed file when it goes out of scope.
struct FileCloser {
  std::FILE* f;
  ~FileCloser() {
    if (f) std::fclose(f);
  }
};

enum class FastFormat { kOther, kPng, kBmp };
// The format from a file's first bytes (at least 2; 8 for PNG).
FastFormat SniffFormat(const unsigned char* bytes, std::size_t n);

// Decodes the open file (positioned at its start) whose header size the caller has checked against
// the limits. The decoders check every size they derive from the file again. Returns an empty
// matrix with *error set when the file is damaged (the caller's error) or a variant not read here
// (BMP: RLE, bit fields, < 8 bits per pixel; PNG: 2 channels), whose message then contains
// kNotReadHere and which the caller hands to the OpenImageIO module.
cv::Mat ReadPng(std::FILE* file, std::string* error);
// The camera-frame case only (grey, 8/16 bit, not interlaced, no tRNS), inflated in one call with
// libdeflate (png_grey_fast.cpp); empty for any other or any not cleanly decodable file, which
// ReadPng then takes.
cv::Mat ReadGreyPngFast(std::FILE* file);
cv::Mat ReadBmp(std::FILE* file, std::string* error);

// An uncompressed BMP's layout, from its header and palette, every size checked against the
// file's length.
struct BmpLayout {
  long long width = 0, height = 0;
  long long stride = 0;     // bytes per stored row (rows are padded to 4 bytes)
  long long file_size = 0;  // bytes
  std::uint32_t pixel_offset = 0;
  int bpp = 0;                                   // 8, 24 or 32
  bool top_down = false;                         // rows stored top first (negative height)
  bool grey = true;                              // 8-bit with R = G = B in every palette entry
  bool identity = false;                         // grey with entry i = i: the stored bytes are the samples
  std::array<unsigned char, 256 * 3> palette{};  // B, G, R per entry, as stored
  // File offset of image row y (0 = top).
  long long RowOffset(long long y) const { return pixel_offset + (top_down ? y : height - 1 - y) * stride; }
};
// Reads the layout of the open file; false with *error set as ReadBmp (damaged, or a variant not
// read here).
bool ReadBmpLayout(std::FILE* file, BmpLayout* layout, std::string* error);
// Reverses the order of an image's rows in place (a bottom-up BMP read in one block).
void ReverseRows(cv::Mat* image);

// InputError naming `path` if a header's dimensions are empty or beyond kMaxImageSide /
// kMaxImagePixels (image_file.cpp).
void CheckDimensions(const std::string& path, long long width, long long height);
// InputError naming the file unless it exists and is a regular file (not a FIFO or a device,
// which would block or never end): every image reader calls it before opening.
void RequireImageFile(const std::string& path);

// PNG bytes of an 8/16-bit matrix with 1, 3 (BGR) or 4 (BGRA) channels; false with *error set.
// Deflate level 1 with run-length strategy, as OpenCV's default PNG writer.
bool EncodePng(const cv::Mat& image, std::vector<unsigned char>* bytes, std::string* error);
// PNG bytes of a palette picture: CV_8UC1 indices into up to 256 BGR colours; false with
// *error set (also for an index beyond the palette).
bool EncodeIndexedPng(const cv::Mat& index, const std::vector<cv::Vec3b>& palette_bgr,
                      std::vector<unsigned char>* bytes, std::string* error);

}  // namespace ramtk::image::detail
