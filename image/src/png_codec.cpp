// PNG through libpng's progressive-free sequential API. libpng reports errors by longjmp, so each
// step that can fail runs in a small function whose frame holds plain values only (no destructor
// is skipped by the jump); matrices and buffers live in the callers' frames.
#include <png.h>

#include <csetjmp>
#include <cstring>

#include "ramtk/image/detail/fast_codecs.h"

namespace ramtk::image::detail {
namespace {

struct ErrorText {
  char text[200] = {};
};

void OnError(png_structp png, png_const_charp message) {
  auto* sink = static_cast<ErrorText*>(png_get_error_ptr(png));
  std::snprintf(sink->text, sizeof(sink->text), "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}

void OnWarning(png_structp, png_const_charp) {}

struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadStructs() {
    if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
  }
};

struct Layout {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, channels = 0;
  std::size_t row_bytes = 0;
};

// Header and transformations: grey/colour at 8 or 16 bits as OpenCV's IMREAD_UNCHANGED gives
// them (palette expanded to BGR, transparency to alpha, grey + alpha to BGRA, BGR order,
// 16-bit samples in little-endian host order).
bool ReadLayout(png_structp png, png_infop info, std::FILE* file, Layout* layout) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_user_limits(png, 0x7fffffffU, 0x7fffffffU);  // the caller checked the size already
  png_read_info(png, info);
  const int colour = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colour == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (colour == PNG_COLOR_TYPE_GRAY_ALPHA || (colour == PNG_COLOR_TYPE_GRAY && png_get_valid(png, info, PNG_INFO_tRNS)))
    png_set_gray_to_rgb(png);
  if (depth == 16) png_set_swap(png);
  png_set_bgr(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  layout->width = png_get_image_width(png, info);
  layout->height = png_get_image_height(png, info);
  layout->bit_depth = png_get_bit_depth(png, info);
  layout->channels = png_get_channels(png, info);
  layout->row_bytes = png_get_rowbytes(png, info);
  return true;
}

bool ReadRows(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  return true;
}

struct WriteStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~WriteStructs() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
  }
};

void Append(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}

void Flush(png_structp) {}

bool WriteAll(png_structp png, png_infop info, std::vector<unsigned char>* out, png_uint_32 width, png_uint_32 height,
              int bit_depth, int colour, png_bytepp rows, png_const_colorp palette, int palette_size) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, Append, Flush);
  png_set_IHDR(png, info, width, height, bit_depth, colour, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);
  png_set_compression_strategy(png, 3);  // Z_RLE
  // Colour pictures (false-colour previews: depth, phase) with the Up filter only: libpng's
  // per-row trial of all five filters was half the encoding of a thesis frame's depth picture
  // (0.25 -> 0.14 s), for files 4 % larger (depth picture and coordinate previews alike; Sub
  // alone made the coordinate previews 6x larger). Grey images (camera frames) keep the
  // adaptive choice.
  // Palette pictures too: Up made a depth picture's file 40 % smaller than no filter, for 0.7 ms
  // more on 1.3 Mpx.
  if (colour == PNG_COLOR_TYPE_RGB || colour == PNG_COLOR_TYPE_RGB_ALPHA || colour == PNG_COLOR_TYPE_PALETTE)
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_PLTE(png, info, palette, palette_size);
  png_write_info(png, info);
  if (bit_depth == 16) png_set_swap(png);
  if (colour == PNG_COLOR_TYPE_RGB || colour == PNG_COLOR_TYPE_RGB_ALPHA) png_set_bgr(png);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

cv::Mat ReadPng(std::FILE* file, std::string* error) {
  ErrorText sink;
  ReadStructs s;
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &sink, OnError, OnWarning);
  if (s.png) s.info = png_create_info_struct(s.png);
  if (!s.png || !s.info) {
    *error = "libpng could not start";
    return {};
  }
  Layout layout;
  if (!ReadLayout(s.png, s.info, file, &layout)) {
    *error = std::string("corrupt PNG: ") + sink.text;
    return {};
  }
  if ((layout.bit_depth != 8 && layout.bit_depth != 16) || layout.channels < 1 || layout.channels > 4 ||
      layout.channels == 2) {
    *error = "PNG layout not read here (" + std::to_string(layout.channels) + " channels of " +
             std::to_string(layout.bit_depth) + " bits)";
    return {};
  }
  const int type = CV_MAKETYPE(layout.bit_depth == 8 ? CV_8U : CV_16U, layout.channels);
  cv::Mat out(static_cast<int>(layout.height), static_cast<int>(layout.width), type);
  if (out.step[0] < layout.row_bytes) {
    *error = "PNG row size inconsistent with its header";
    return {};
  }
  std::vector<png_bytep> rows(layout.height);
  for (png_uint_32 y = 0; y < layout.height; ++y) rows[y] = out.ptr<png_byte>(static_cast<int>(y));
  if (!ReadRows(s.png, rows.data())) {
    *error = std::string("corrupt PNG: ") + sink.text;
    return {};
  }
  return out;
}

namespace {

// The PNG of `image`'s rows (bit depth, colour type and, for a palette picture, its colours).
bool EncodeRows(const cv::Mat& image, int bit_depth, int colour, const std::vector<png_color>& palette,
                std::vector<unsigned char>* bytes, std::string* error) {
  ErrorText sink;
  WriteStructs s;
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, OnError, OnWarning);
  if (s.png) s.info = png_create_info_struct(s.png);
  if (!s.png || !s.info) {
    *error = "libpng could not start";
    return false;
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.ptr<png_byte>(y));
  bytes->clear();
  bytes->reserve(image.total() * image.elemSize() / 2 + 1024);
  if (!WriteAll(s.png, s.info, bytes, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
                bit_depth, colour, rows.data(), palette.empty() ? nullptr : palette.data(),
                static_cast<int>(palette.size()))) {
    *error = std::string("cannot encode PNG: ") + sink.text;
    return false;
  }
  return true;
}

}  // namespace

bool EncodePng(const cv::Mat& image, std::vector<unsigned char>* bytes, std::string* error) {
  const int depth = image.depth();
  const int nc = image.channels();
  if ((depth != CV_8U && depth != CV_16U) || (nc != 1 && nc != 3 && nc != 4) || image.empty()) {
    *error = "PNG needs an 8/16-bit image with 1, 3 or 4 channels";
    return false;
  }
  const int colour = nc == 1 ? PNG_COLOR_TYPE_GRAY : nc == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA;
  return EncodeRows(image, depth == CV_8U ? 8 : 16, colour, {}, bytes, error);
}

bool EncodeIndexedPng(const cv::Mat& index, const std::vector<cv::Vec3b>& palette_bgr,
                      std::vector<unsigned char>* bytes, std::string* error) {
  if (index.type() != CV_8UC1 || index.empty()) {
    *error = "an indexed PNG needs an 8-bit single-channel image of palette indices";
    return false;
  }
  if (palette_bgr.empty() || palette_bgr.size() > 256) {
    *error = "an indexed PNG needs 1 to 256 palette colours, not " + std::to_string(palette_bgr.size());
    return false;
  }
  // An index beyond the palette would make a file that readers reject: checked here, not by libpng.
  const int last = static_cast<int>(palette_bgr.size()) - 1;
  for (int y = 0; y < index.rows && last < 255; ++y) {
    const uchar* row = index.ptr<uchar>(y);
    for (int x = 0; x < index.cols; ++x)
      if (row[x] > last) {
        *error = "palette index " + std::to_string(row[x]) + " at (" + std::to_string(x) + ", " + std::to_string(y) +
                 ") is beyond the palette's " + std::to_string(palette_bgr.size()) + " colours";
        return false;
      }
  }
  std::vector<png_color> palette(palette_bgr.size());
  for (std::size_t i = 0; i < palette.size(); ++i)
    palette[i] = png_color{palette_bgr[i][2], palette_bgr[i][1], palette_bgr[i][0]};
  return EncodeRows(index, 8, PNG_COLOR_TYPE_PALETTE, palette, bytes, error);
}

}  // namespace ramtk::image::detail
