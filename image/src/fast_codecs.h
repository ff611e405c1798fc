// The fast path of image_file.cpp: PNG through libpng, uncompressed BMP read here. Both give what
// OpenCV's imread(IMREAD_UNCHANGED) gives: 8/16-bit samples, 1 channel for grey, 3 (BGR) or 4
// (BGRA) for colour; 16-bit in host order.
#pragma once

#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ramtk::image::detail {

inline constexpr const char* kNotReadHere = "not read here";

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

// PNG bytes of an 8/16-bit matrix with 1, 3 (BGR) or 4 (BGRA) channels; false with *error set.
// Deflate level 1 with run-length strategy, as OpenCV's default PNG writer.
bool EncodePng(const cv::Mat& image, std::vector<unsigned char>* bytes, std::string* error);

}  // namespace ramtk::image::detail
