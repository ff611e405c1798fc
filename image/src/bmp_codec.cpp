// Uncompressed Windows bitmaps: 8-bit palette, 24-bit BGR and 32-bit BGRX rows, bottom-up or
// top-down. That is what cameras and their SDKs write; RLE, bit-field and < 8-bit files are left to
// the OpenImageIO module. Every offset and size read from the file is checked against the file's
// length before it is used.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "ramtk/image/detail/fast_codecs.h"

namespace ramtk::image::detail {
namespace {

std::uint32_t Le32(const unsigned char* b) {
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}
std::uint16_t Le16(const unsigned char* b) { return static_cast<std::uint16_t>(b[0] | (b[1] << 8)); }

bool ReadAt(std::FILE* file, long long offset, void* out, std::size_t n) {
  if (std::fseek(file, static_cast<long>(offset), SEEK_SET) != 0) return false;
  return std::fread(out, 1, n, file) == n;
}

}  // namespace

FastFormat SniffFormat(const unsigned char* b, std::size_t n) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 8 && std::memcmp(b, kPng, 8) == 0) return FastFormat::kPng;
  if (n >= 2 && b[0] == 'B' && b[1] == 'M') return FastFormat::kBmp;
  return FastFormat::kOther;
}

bool ReadBmpLayout(std::FILE* file, BmpLayout* layout, std::string* error) {
  BmpLayout& l = *layout;
  if (std::fseek(file, 0, SEEK_END) != 0) {
    *error = "cannot seek in BMP";
    return false;
  }
  l.file_size = std::ftell(file);
  unsigned char h[54] = {};
  if (l.file_size < 26 || !ReadAt(file, 0, h, static_cast<std::size_t>(std::min<long long>(54, l.file_size)))) {
    *error = "BMP header truncated";
    return false;
  }
  l.pixel_offset = Le32(h + 10);
  const std::uint32_t dib_size = Le32(h + 14);
  std::uint32_t compression = 0, colours_used = 0;
  int palette_entry = 4;
  if (dib_size == 12) {  // BITMAPCOREHEADER
    l.width = Le16(h + 18);
    l.height = static_cast<std::int16_t>(Le16(h + 20));
    l.bpp = Le16(h + 24);
    palette_entry = 3;
  } else if (dib_size >= 40 && l.file_size >= 54) {
    l.width = static_cast<std::int32_t>(Le32(h + 18));
    l.height = static_cast<std::int32_t>(Le32(h + 22));
    l.bpp = Le16(h + 28);
    compression = Le32(h + 30);
    colours_used = Le32(h + 46);
  } else {
    *error = "BMP header of " + std::to_string(dib_size) + " bytes not read here";
    return false;
  }
  if (compression != 0 || (l.bpp != 8 && l.bpp != 24 && l.bpp != 32)) {
    *error = "BMP with " + std::to_string(l.bpp) + " bits per pixel and compression " + std::to_string(compression) +
             " not read here";
    return false;
  }
  l.top_down = l.height < 0;
  if (l.top_down) l.height = -l.height;
  if (l.width <= 0 || l.height <= 0) {
    *error = "BMP has no pixels";
    return false;
  }
  l.stride = ((l.width * l.bpp + 31) / 32) * 4;
  if (l.pixel_offset < 14 + dib_size || static_cast<long long>(l.pixel_offset) + l.stride * l.height > l.file_size) {
    *error = "BMP pixel data truncated (" + std::to_string(l.file_size) + " bytes for " + std::to_string(l.width) +
             "x" + std::to_string(l.height) + " at " + std::to_string(l.bpp) + " bits)";
    return false;
  }
  // Palette: grey when every entry has equal R, G and B (the rows then map through a table into one
  // channel, as OpenCV reads such files), BGR otherwise.
  l.grey = true;
  if (l.bpp == 8) {
    const long long palette_at = 14 + dib_size;
    long long entries = colours_used == 0 ? 256 : std::min<long long>(colours_used, 256);
    entries = std::min<long long>(entries, (l.pixel_offset - palette_at) / palette_entry);
    std::vector<unsigned char> raw(static_cast<std::size_t>(std::max<long long>(entries, 0) * palette_entry));
    if (!raw.empty() && !ReadAt(file, palette_at, raw.data(), raw.size())) {
      *error = "BMP palette truncated";
      return false;
    }
    for (long long i = 0; i < entries; ++i)
      for (int c = 0; c < 3; ++c)
        l.palette[static_cast<std::size_t>(i * 3 + c)] = raw[static_cast<std::size_t>(i * palette_entry + c)];
    for (int i = 0; i < 256 && l.grey; ++i)
      l.grey = l.palette[i * 3] == l.palette[i * 3 + 1] && l.palette[i * 3] == l.palette[i * 3 + 2];
  }
  l.identity = l.bpp == 8 && l.grey;
  for (int i = 0; i < 256 && l.identity; ++i) l.identity = l.palette[static_cast<std::size_t>(i) * 3] == i;
  return true;
}

void ReverseRows(cv::Mat* image) {
  const std::size_t bytes = image->cols * image->elemSize();
  std::vector<unsigned char> tmp(bytes);
  for (int r = 0; r < image->rows / 2; ++r) {
    unsigned char* a = image->ptr<unsigned char>(r);
    unsigned char* b = image->ptr<unsigned char>(image->rows - 1 - r);
    std::memcpy(tmp.data(), a, bytes);
    std::memcpy(a, b, bytes);
    std::memcpy(b, tmp.data(), bytes);
  }
}

cv::Mat ReadBmp(std::FILE* file, std::string* error) {
  BmpLayout layout;
  if (!ReadBmpLayout(file, &layout, error)) return {};
  const long long width = layout.width, height = layout.height, stride = layout.stride;
  const int bpp = layout.bpp;
  const bool top_down = layout.top_down, grey = layout.grey, identity = layout.identity;
  const std::uint32_t pixel_offset = layout.pixel_offset;
  const auto& palette = layout.palette;
  const int channels = bpp == 8 && grey ? 1 : 3;
  cv::Mat out(static_cast<int>(height), static_cast<int>(width), CV_8UC(channels));
  // A grey frame whose rows need no padding or palette (the usual camera frame) is read straight
  // into the image and, stored bottom-up, its rows swapped in place: no second buffer to fault
  // in, clear and copy (8 MB per thesis frame).
  if (identity && stride == width) {
    if (!ReadAt(file, pixel_offset, out.data, static_cast<std::size_t>(stride * height))) {
      *error = "BMP pixel data truncated";
      return {};
    }
    if (!top_down) ReverseRows(&out);
    return out;
  }
  // Otherwise the whole pixel block in one read (not cleared first), then row by row into place.
  const std::unique_ptr<unsigned char[]> block_buffer(new unsigned char[static_cast<std::size_t>(stride * height)]);
  unsigned char* const block = block_buffer.get();
  if (!ReadAt(file, pixel_offset, block, static_cast<std::size_t>(stride * height))) {
    *error = "BMP pixel data truncated";
    return {};
  }
  for (long long r = 0; r < height; ++r) {
    const unsigned char* row = &block[static_cast<std::size_t>(r * stride)];
    unsigned char* dst = out.ptr<unsigned char>(static_cast<int>(top_down ? r : height - 1 - r));
    if (identity) {
      std::memcpy(dst, row, static_cast<std::size_t>(width));
    } else if (bpp == 8 && grey) {
      for (long long x = 0; x < width; ++x) dst[x] = palette[static_cast<std::size_t>(row[x]) * 3];
    } else if (bpp == 8) {
      for (long long x = 0; x < width; ++x) std::memcpy(dst + 3 * x, &palette[static_cast<std::size_t>(row[x]) * 3], 3);
    } else if (bpp == 24) {
      std::memcpy(dst, row, static_cast<std::size_t>(width * 3));
    } else {
      for (long long x = 0; x < width; ++x) std::memcpy(dst + 3 * x, &row[static_cast<std::size_t>(x * 4)], 3);
    }
  }
  return out;
}

}  // namespace ramtk::image::detail
