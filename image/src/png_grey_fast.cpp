// The camera-frame PNG (grey, 8 or 16 bit, not interlaced, no transparency) decoded in one pass:
// the chunks are walked here, the IDAT stream inflated with libdeflate in one call into a buffer
// the thread keeps, and the rows unfiltered straight into the matrix. libpng spent ~2 s of CPU on
// the 38 frames of a thesis set (zlib's streaming inflate, its row copies); docs/performance.md.
// Anything else, and any file that does not decode cleanly here, goes to libpng (png_codec.cpp),
// which then names the problem.
#include <libdeflate.h>

#include <cstdint>
#include <cstring>
#include <memory>

#include "ramtk/image/detail/fast_codecs.h"

namespace ramtk::image::detail {
namespace {

std::uint32_t Be32(const unsigned char* b) {
  return (static_cast<std::uint32_t>(b[0]) << 24) | (static_cast<std::uint32_t>(b[1]) << 16) |
         (static_cast<std::uint32_t>(b[2]) << 8) | static_cast<std::uint32_t>(b[3]);
}

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// Per-thread state: the decompressor and the buffers, reused from frame to frame (a batch decodes
// thousands of frames of one size; fresh 8-30 MB buffers would each cost their page faults).
struct ThreadState {
  std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor{libdeflate_alloc_decompressor()};
  std::vector<unsigned char> file, idat, filtered;
};

ThreadState& State() {
  thread_local ThreadState state;
  return state;
}

int Paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = p > a ? p - a : a - p, pb = p > b ? p - b : b - p, pc = p > c ? p - c : c - p;
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// The Average (3) and Paeth (4) filters of one row with `kBpp` bytes per pixel. Each output byte
// depends on the one kBpp bytes before it; that byte is kept in a register (one per byte lane),
// not read back from `out`: a read of the byte just stored waits for the store to forward, which
// made these filters' loop the slowest part of a frame's decode (~8 cycles a byte).
template <int kBpp, bool kPaeth>
void UnfilterAveragePaeth(const unsigned char* in, unsigned char* out, const unsigned char* prior, std::size_t n) {
  int left[kBpp] = {}, upper_left[kBpp] = {};  // 0 before the first pixel (PNG section 9.2)
  for (std::size_t i = 0; i + kBpp <= n; i += kBpp) {
    for (int k = 0; k < kBpp; ++k) {
      const int up = prior[i + k];
      const int predicted = kPaeth ? Paeth(left[k], up, upper_left[k]) : (left[k] + up) >> 1;
      left[k] = static_cast<unsigned char>(in[i + k] + predicted);
      upper_left[k] = up;
      out[i + k] = static_cast<unsigned char>(left[k]);
    }
  }
}

// Undoes one row's filter (PNG specification, section 9) from `in` into `out`: `bpp` bytes per
// pixel (1 or 2), `prior` the previous unfiltered row (zeros for the first). The Sub filter, which
// the common writers pick for smooth camera rows, runs on per-byte-lane accumulators, so its
// serial dependency stays in registers; so do Average and Paeth (UnfilterAveragePaeth).
bool Unfilter(int type, const unsigned char* in, unsigned char* out, const unsigned char* prior, std::size_t n,
              std::size_t bpp) {
  switch (type) {
    case 0:
      std::memcpy(out, in, n);
      return true;
    case 1:
      if (bpp == 1) {
        unsigned char acc = 0;
        for (std::size_t i = 0; i < n; ++i) out[i] = acc = static_cast<unsigned char>(acc + in[i]);
      } else {
        unsigned char hi = 0, lo = 0;
        for (std::size_t i = 0; i + 1 < n; i += 2) {
          out[i] = hi = static_cast<unsigned char>(hi + in[i]);
          out[i + 1] = lo = static_cast<unsigned char>(lo + in[i + 1]);
        }
      }
      return true;
    case 2:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(in[i] + prior[i]);
      return true;
    case 3:
    case 4:
      if (bpp == 1)
        (type == 4 ? UnfilterAveragePaeth<1, true> : UnfilterAveragePaeth<1, false>)(in, out, prior, n);
      else
        (type == 4 ? UnfilterAveragePaeth<2, true> : UnfilterAveragePaeth<2, false>)(in, out, prior, n);
      return true;
    default:
      return false;
  }
}

}  // namespace

cv::Mat ReadGreyPngFast(std::FILE* file) {
  ThreadState& st = State();
  if (!st.decompressor) return {};
  if (std::fseek(file, 0, SEEK_END) != 0) return {};
  const long size = std::ftell(file);
  if (size < 8 + 25 + 12 || std::fseek(file, 0, SEEK_SET) != 0) return {};
  st.file.resize(static_cast<std::size_t>(size));
  if (std::fread(st.file.data(), 1, st.file.size(), file) != st.file.size()) return {};
  const unsigned char* b = st.file.data();
  const std::size_t n = st.file.size();
  // IHDR first (PNG section 5.6), then chunks up to IEND; the IDAT data are gathered.
  std::size_t pos = 8;
  std::uint32_t width = 0, height = 0;
  int depth = 0;
  bool header = false, end = false;
  st.idat.clear();
  while (pos + 12 <= n && !end) {
    const std::uint32_t len = Be32(b + pos);
    if (len > n - pos - 12) return {};
    const unsigned char* type = b + pos + 4;
    const unsigned char* data = b + pos + 8;
    const bool critical = (type[0] & 0x20) == 0;
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION  // the fuzz build reaches past the CRC (fuzz/)
    if (critical && libdeflate_crc32(0, type, len + 4) != Be32(data + len)) return {};
#endif
    if (std::memcmp(type, "IHDR", 4) == 0) {
      if (header || pos != 8 || len != 13) return {};
      width = Be32(data);
      height = Be32(data + 4);
      depth = data[8];
      // colour type 0 (grey), compression 0, filter method 0, not interlaced
      if (data[9] != 0 || data[10] != 0 || data[11] != 0 || data[12] != 0 || (depth != 8 && depth != 16)) return {};
      header = true;
    } else if (!header) {
      return {};
    } else if (std::memcmp(type, "IDAT", 4) == 0) {
      st.idat.insert(st.idat.end(), data, data + len);
    } else if (std::memcmp(type, "IEND", 4) == 0) {
      end = true;
    } else if (critical || std::memcmp(type, "tRNS", 4) == 0) {
      return {};  // PLTE or an unknown critical chunk, or transparency: libpng's case
    }
    pos += 12 + len;
  }
  if (!header || !end || width == 0 || height == 0 || st.idat.empty()) return {};
  const std::size_t bpp = depth / 8;
  const std::size_t row_bytes = static_cast<std::size_t>(width) * bpp;
  const std::size_t expected = static_cast<std::size_t>(height) * (row_bytes + 1);
  // Deflate expands at most ~1032:1: a stream too short for the rows its header claims is damaged
  // (libpng then names it), and must not make this thread hold a buffer of the claimed size.
  if (expected / 1032 > st.idat.size() + 64) return {};
  st.filtered.resize(expected);
  std::size_t in_used = 0, out_made = 0;
  if (libdeflate_zlib_decompress_ex(st.decompressor.get(), st.idat.data(), st.idat.size(), st.filtered.data(), expected,
                                    &in_used, &out_made) != LIBDEFLATE_SUCCESS ||
      out_made != expected)
    return {};
  cv::Mat out(static_cast<int>(height), static_cast<int>(width), depth == 8 ? CV_8UC1 : CV_16UC1);
  // 8 bit: unfiltered straight into the matrix rows. 16 bit: into two alternating rows, then
  // swapped from PNG's big-endian order into the matrix.
  std::vector<unsigned char> rows16(depth == 16 ? 2 * row_bytes : 0);
  const std::vector<unsigned char> zeros(row_bytes, 0);
  const unsigned char* prior = zeros.data();
  for (std::uint32_t y = 0; y < height; ++y) {
    const unsigned char* in = &st.filtered[y * (row_bytes + 1)];
    unsigned char* dst = depth == 8 ? out.ptr<unsigned char>(static_cast<int>(y)) : &rows16[(y % 2) * row_bytes];
    if (!Unfilter(in[0], in + 1, dst, prior, row_bytes, bpp)) return {};
    prior = dst;
    if (depth == 16) {
      std::uint16_t* px = out.ptr<std::uint16_t>(static_cast<int>(y));
      for (std::uint32_t x = 0; x < width; ++x) px[x] = static_cast<std::uint16_t>((dst[2 * x] << 8) | dst[2 * x + 1]);
    }
  }
  return out;
}

}  // namespace ramtk::image::detail
