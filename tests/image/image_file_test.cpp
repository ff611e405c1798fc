// ramtk::image's own PNG and BMP codecs against the peer they replace, OpenCV's imgcodecs: every
// file OpenCV writes is read back identically, every file written here OpenCV reads identically,
// hand-built BMP variants decode to the pixels they were built from, and the real camera frames
// of the SLMaster set decode exactly as cv::imread decodes them.
#include <gtest/gtest.h>
#include <png.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/image/frame_rows.h"
#include "ramtk/image/image_file.h"
#include "ramtk/image/detail/fast_codecs.h"  // the one-call grey PNG decoder, tested on its own too

namespace fs = std::filesystem;
using ramtk::image::LoadImageGrey8;
using ramtk::image::LoadImageNative;

namespace {

std::string TempDir() {
  const fs::path dir = fs::temp_directory_path() / ("ramtk_image_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir.string();
}

cv::Mat Random(int rows, int cols, int type, unsigned seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_8U ? 256 : 65536);
  return m;
}

bool Identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  cv::Mat diff;
  cv::absdiff(a.reshape(1), b.reshape(1), diff);
  return cv::countNonZero(diff) == 0;
}

void PutLe(std::vector<unsigned char>* b, std::size_t at, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) (*b)[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(v >> (8 * i));
}

// A BMP written byte by byte from the format's definition (BITMAPINFOHEADER), independent of both
// decoders: `pixels` is CV_8UC1 (written through `palette`, 256 BGR entries) or CV_8UC3 (24 or 32
// bits per pixel).
std::vector<unsigned char> BuildBmp(const cv::Mat& pixels, int bpp, bool top_down,
                                    const std::vector<cv::Vec3b>& palette = {}) {
  const int w = pixels.cols, h = pixels.rows;
  const int stride = ((w * bpp + 31) / 32) * 4;
  const int palette_bytes = bpp == 8 ? 256 * 4 : 0;
  const int offset = 14 + 40 + palette_bytes;
  std::vector<unsigned char> b(static_cast<std::size_t>(offset + stride * h), 0);
  b[0] = 'B';
  b[1] = 'M';
  PutLe(&b, 2, static_cast<std::uint32_t>(b.size()), 4);
  PutLe(&b, 10, static_cast<std::uint32_t>(offset), 4);
  PutLe(&b, 14, 40, 4);
  PutLe(&b, 18, static_cast<std::uint32_t>(w), 4);
  PutLe(&b, 22, static_cast<std::uint32_t>(top_down ? -h : h), 4);
  PutLe(&b, 26, 1, 2);
  PutLe(&b, 28, static_cast<std::uint32_t>(bpp), 2);
  for (int i = 0; i < (bpp == 8 ? 256 : 0); ++i)
    for (int c = 0; c < 3; ++c) b[static_cast<std::size_t>(54 + 4 * i + c)] = palette[static_cast<std::size_t>(i)][c];
  for (int r = 0; r < h; ++r) {
    const int y = top_down ? r : h - 1 - r;
    unsigned char* row = &b[static_cast<std::size_t>(offset + r * stride)];
    for (int x = 0; x < w; ++x) {
      if (bpp == 8) {
        row[x] = pixels.at<unsigned char>(y, x);
      } else {
        const cv::Vec3b p = pixels.at<cv::Vec3b>(y, x);
        for (int c = 0; c < 3; ++c) row[x * (bpp / 8) + c] = p[c];
        if (bpp == 32) row[x * 4 + 3] = 0x5a;  // unused byte, must be ignored
      }
    }
  }
  return b;
}

std::string WriteBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                               static_cast<std::streamsize>(bytes.size()));
  return path;
}

// An interlaced palette PNG written with libpng directly (OpenCV never writes either).
void WritePalettePng(const std::string& path, const cv::Mat& index, const std::vector<cv::Vec3b>& palette_bgr,
                     bool interlaced) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(index.cols), static_cast<png_uint_32>(index.rows), 8,
               PNG_COLOR_TYPE_PALETTE, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> pal(palette_bgr.size());
  for (std::size_t i = 0; i < pal.size(); ++i) pal[i] = {palette_bgr[i][2], palette_bgr[i][1], palette_bgr[i][0]};
  png_set_PLTE(png, info, pal.data(), static_cast<int>(pal.size()));
  png_write_info(png, info);
  std::vector<png_bytep> rows(static_cast<std::size_t>(index.rows));
  for (int y = 0; y < index.rows; ++y) rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(index.ptr<png_byte>(y));
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

// A grey PNG written with libpng with one filter type forced on every row (PNG section 9).
void WriteGreyPngFiltered(const std::string& path, const cv::Mat& grey, int filter) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(grey.cols), static_cast<png_uint_32>(grey.rows),
               grey.depth() == CV_8U ? 8 : 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(png, 0, filter);
  png_set_compression_buffer_size(png, 1000);  // several IDAT chunks
  png_write_info(png, info);
  if (grey.depth() == CV_16U) png_set_swap(png);
  std::vector<png_bytep> rows(static_cast<std::size_t>(grey.rows));
  for (int y = 0; y < grey.rows; ++y) rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(grey.ptr<png_byte>(y));
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace

TEST(ImageFile, OneCallGreyPngDecoderUndoesEveryFilterType) {
  const std::string dir = TempDir();
  for (int type : {CV_8UC1, CV_16UC1}) {
    // A fringe-like image: smooth rows with noise, so every filter predicts something.
    cv::Mat truth(37, 53, type);
    cv::RNG rng(21);
    const double full = type == CV_8UC1 ? 255.0 : 65535.0;
    for (int y = 0; y < truth.rows; ++y)
      for (int x = 0; x < truth.cols; ++x) {
        const double v = full * (0.5 + 0.45 * std::cos(0.3 * x + 0.1 * y)) + rng.gaussian(0.01 * full);
        if (type == CV_8UC1) truth.at<uchar>(y, x) = cv::saturate_cast<uchar>(v);
        else truth.at<std::uint16_t>(y, x) = cv::saturate_cast<std::uint16_t>(v);
      }
    for (int filter : {PNG_FILTER_NONE, PNG_FILTER_SUB, PNG_FILTER_UP, PNG_FILTER_AVG, PNG_FILTER_PAETH, PNG_ALL_FILTERS}) {
      SCOPED_TRACE("type " + std::to_string(type) + " filter " + std::to_string(filter));
      const std::string path = dir + "/f" + std::to_string(filter) + ".png";
      WriteGreyPngFiltered(path, truth, filter);
      std::FILE* f = std::fopen(path.c_str(), "rb");
      const cv::Mat fast = ramtk::image::detail::ReadGreyPngFast(f);
      std::fclose(f);
      EXPECT_TRUE(Identical(fast, truth));
      EXPECT_TRUE(Identical(cv::imread(path, cv::IMREAD_UNCHANGED), truth));  // the writer is right
    }
  }
  // Not its case (colour), or damaged (one bit flipped in the pixel data: the chunk CRC fails):
  // empty, so libpng decides, and names the damage.
  ASSERT_TRUE(cv::imwrite(dir + "/colour.png", Random(5, 5, CV_8UC3, 1)));
  std::FILE* f = std::fopen((dir + "/colour.png").c_str(), "rb");
  EXPECT_TRUE(ramtk::image::detail::ReadGreyPngFast(f).empty());
  std::fclose(f);
  std::vector<unsigned char> png = ramtk::image::EncodePng(Random(20, 20, CV_8UC1, 3));
  png[png.size() / 2] ^= 0x10;
  const std::string damaged = WriteBytes(dir + "/damaged.png", png);
  f = std::fopen(damaged.c_str(), "rb");
  EXPECT_TRUE(ramtk::image::detail::ReadGreyPngFast(f).empty());
  std::fclose(f);
  int bits = 0;
  EXPECT_THROW(LoadImageNative(damaged, &bits), ramtk::InputError);
  fs::remove_all(dir);
}

TEST(ImageFile, ReadsWhatOpenCvWritesAndOpenCvReadsWhatItWrites) {
  const std::string dir = TempDir();
  int k = 0;
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3}) {
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(37, 23), cv::Size(640, 3)}) {
      SCOPED_TRACE("type " + std::to_string(type) + " size " + std::to_string(size.width) + "x" +
                   std::to_string(size.height));
      const cv::Mat truth = Random(size.height, size.width, type, 100u + static_cast<unsigned>(k));
      const std::string by_opencv = dir + "/cv" + std::to_string(k) + ".png";
      ASSERT_TRUE(cv::imwrite(by_opencv, truth));
      int bits = 0;
      const cv::Mat read_here = LoadImageNative(by_opencv, &bits);
      if (truth.channels() == 1) {
        EXPECT_TRUE(Identical(read_here, truth));
        EXPECT_EQ(bits, CV_MAT_DEPTH(type) == CV_8U ? 8 : 16);
      }
      const std::string by_us = dir + "/us" + std::to_string(k) + ".png";
      ramtk::image::WriteImage(by_us, truth);
      EXPECT_TRUE(Identical(cv::imread(by_us, cv::IMREAD_UNCHANGED), truth));
      const std::vector<unsigned char> bytes = ramtk::image::EncodePng(truth);
      EXPECT_TRUE(Identical(cv::imdecode(bytes, cv::IMREAD_UNCHANGED), truth));
      ++k;
    }
  }
  // Colour is averaged to grey DN, as before (the rounding to 1/16 DN is LoadImageDn's contract).
  const cv::Mat colour = Random(9, 11, CV_8UC3, 7);
  ASSERT_TRUE(cv::imwrite(dir + "/colour.png", colour));
  int bits = 0;
  const cv::Mat dn = ramtk::image::LoadImageDn(dir + "/colour.png", &bits);
  ASSERT_EQ(dn.type(), CV_32FC1);
  for (int y = 0; y < colour.rows; ++y)
    for (int x = 0; x < colour.cols; ++x) {
      const cv::Vec3b p = colour.at<cv::Vec3b>(y, x);
      EXPECT_NEAR(dn.at<float>(y, x), (p[0] + p[1] + p[2]) / 3.0, 1.0 / 32 + 1e-6);
    }
  fs::remove_all(dir);
}

// Palette pictures (false-colour previews): OpenCV's decoder expands every index to its colour,
// and an index beyond the palette or a palette of no / too many colours is an error, not a file.
TEST(ImageFile, IndexedPngDecodesToEachIndexsPaletteColour) {
  for (const int colours : {1, 7, 256}) {
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(37, 23), cv::Size(640, 3)}) {
      SCOPED_TRACE(std::to_string(colours) + " colours, " + std::to_string(size.width) + "x" +
                   std::to_string(size.height));
      cv::Mat index = Random(size.height, size.width, CV_8UC1, 40u + static_cast<unsigned>(colours));
      for (auto it = index.begin<uchar>(); it != index.end<uchar>(); ++it)
        *it = static_cast<uchar>(*it * colours / 256);  // 0 .. colours - 1
      const cv::Mat bgr = Random(1, colours, CV_8UC3, 90u + static_cast<unsigned>(colours));
      const std::vector<cv::Vec3b> palette(bgr.ptr<cv::Vec3b>(0), bgr.ptr<cv::Vec3b>(0) + colours);
      const cv::Mat decoded = cv::imdecode(ramtk::image::EncodeIndexedPng(index, palette), cv::IMREAD_UNCHANGED);
      ASSERT_EQ(decoded.type(), CV_8UC3);
      ASSERT_EQ(decoded.size(), size);
      long wrong = 0;
      for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x) {
          ASSERT_LT(index.at<uchar>(y, x), colours);
          wrong += decoded.at<cv::Vec3b>(y, x) != palette[index.at<uchar>(y, x)];
        }
      EXPECT_EQ(wrong, 0);
    }
  }
  cv::Mat index(4, 5, CV_8UC1, cv::Scalar(1));
  const std::vector<cv::Vec3b> two(2, cv::Vec3b(10, 20, 30));
  EXPECT_NO_THROW(ramtk::image::EncodeIndexedPng(index, two));
  index.at<uchar>(3, 2) = 2;  // beyond a palette of two
  try {
    ramtk::image::EncodeIndexedPng(index, two, "preview");
    ADD_FAILURE() << "an index beyond the palette was encoded";
  } catch (const ramtk::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(2, 3)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ramtk::image::EncodeIndexedPng(index, {}), ramtk::InputError);
  EXPECT_THROW(ramtk::image::EncodeIndexedPng(index, std::vector<cv::Vec3b>(257)), ramtk::InputError);
  EXPECT_THROW(ramtk::image::EncodeIndexedPng(cv::Mat(4, 5, CV_8UC3, cv::Scalar(0)), two), ramtk::InputError);
}

TEST(ImageFile, PalettedAndInterlacedPngMatchOpenCv) {
  const std::string dir = TempDir();
  const cv::Mat index = Random(29, 31, CV_8UC1, 11);
  std::vector<cv::Vec3b> grey(256), colour(256);
  std::mt19937 rng(5);
  for (int i = 0; i < 256; ++i) {
    grey[static_cast<std::size_t>(i)] = cv::Vec3b(static_cast<uchar>(i), static_cast<uchar>(i), static_cast<uchar>(i));
    colour[static_cast<std::size_t>(i)] = cv::Vec3b(static_cast<uchar>(rng()), static_cast<uchar>(rng()), static_cast<uchar>(rng()));
  }
  for (bool interlaced : {false, true}) {
    const std::string path = dir + "/pal" + std::to_string(interlaced) + ".png";
    WritePalettePng(path, index, colour, interlaced);
    // LoadImageGrey8 against OpenCV's grey conversion of the same file: OpenCV converts inside
    // libpng (fixed-point luma), ramtk with cv::cvtColor, so they may differ by the last bit.
    cv::Mat diff;
    cv::absdiff(LoadImageGrey8(path), cv::imread(path, cv::IMREAD_GRAYSCALE), diff);
    double worst = 0;
    cv::minMaxLoc(diff, nullptr, &worst);
    EXPECT_LE(worst, 1.0);
    int bits = 0;
    const cv::Mat dn = ramtk::image::LoadImageDn(path, &bits);
    for (int y = 0; y < index.rows; ++y)
      for (int x = 0; x < index.cols; ++x) {
        const cv::Vec3b p = colour[index.at<uchar>(y, x)];
        ASSERT_NEAR(dn.at<float>(y, x), (p[0] + p[1] + p[2]) / 3.0, 1.0 / 32 + 1e-6);
      }
  }
  fs::remove_all(dir);
}

TEST(ImageFile, BmpVariantsDecodeToThePixelsTheyWereBuiltFrom) {
  const std::string dir = TempDir();
  const cv::Mat index = Random(13, 17, CV_8UC1, 3);  // 17 px: rows need padding at every depth
  const cv::Mat bgr = Random(13, 17, CV_8UC3, 4);
  std::vector<cv::Vec3b> identity(256), inverted(256), colour(256);
  std::mt19937 rng(9);
  for (int i = 0; i < 256; ++i) {
    const auto v = static_cast<uchar>(i);
    identity[static_cast<std::size_t>(i)] = cv::Vec3b(v, v, v);
    inverted[static_cast<std::size_t>(i)] = cv::Vec3b(static_cast<uchar>(255 - i), static_cast<uchar>(255 - i), static_cast<uchar>(255 - i));
    colour[static_cast<std::size_t>(i)] = cv::Vec3b(static_cast<uchar>(rng()), static_cast<uchar>(rng()), static_cast<uchar>(rng()));
  }
  cv::Mat inverted_truth = 255 - index;
  cv::Mat colour_truth(index.size(), CV_8UC3);
  for (int y = 0; y < index.rows; ++y)
    for (int x = 0; x < index.cols; ++x) colour_truth.at<cv::Vec3b>(y, x) = colour[index.at<uchar>(y, x)];
  int n = 0;
  for (bool top_down : {false, true}) {
    SCOPED_TRACE(top_down ? "top-down" : "bottom-up");
    const auto file = [&](const std::vector<unsigned char>& b) {
      return WriteBytes(dir + "/v" + std::to_string(n++) + ".bmp", b);
    };
    int bits = 0;
    EXPECT_TRUE(Identical(LoadImageNative(file(BuildBmp(index, 8, top_down, identity)), &bits), index));
    EXPECT_EQ(bits, 8);
    EXPECT_TRUE(Identical(LoadImageNative(file(BuildBmp(index, 8, top_down, inverted)), &bits), inverted_truth));
    cv::Mat grey_truth;
    cv::cvtColor(colour_truth, grey_truth, cv::COLOR_BGR2GRAY);
    EXPECT_TRUE(Identical(LoadImageGrey8(file(BuildBmp(index, 8, top_down, colour))), grey_truth));
    cv::cvtColor(bgr, grey_truth, cv::COLOR_BGR2GRAY);
    EXPECT_TRUE(Identical(LoadImageGrey8(file(BuildBmp(bgr, 24, top_down))), grey_truth));
    EXPECT_TRUE(Identical(LoadImageGrey8(file(BuildBmp(bgr, 32, top_down))), grey_truth));
  }
  // What OpenCV writes (8-bit grey with a grey palette, 24-bit colour) reads back identically.
  ASSERT_TRUE(cv::imwrite(dir + "/cv8.bmp", index));
  int bits = 0;
  EXPECT_TRUE(Identical(LoadImageNative(dir + "/cv8.bmp", &bits), index));
  ASSERT_TRUE(cv::imwrite(dir + "/cv24.bmp", bgr));
  cv::Mat grey_truth;
  cv::cvtColor(bgr, grey_truth, cv::COLOR_BGR2GRAY);
  EXPECT_TRUE(Identical(LoadImageGrey8(dir + "/cv24.bmp"), grey_truth));
  fs::remove_all(dir);
}

// Grey frames whose rows need no padding (camera frames) take the one-read path (a bottom-up
// file's rows then swapped in place): one row, an even and an odd count, stored bottom-up and
// top-down.
TEST(ImageFile, UnpaddedGreyBmpRowsLandInPlaceWhateverTheirCount) {
  const std::string dir = TempDir();
  std::vector<cv::Vec3b> identity(256);
  for (int i = 0; i < 256; ++i) identity[static_cast<std::size_t>(i)] = cv::Vec3b::all(static_cast<uchar>(i));
  int n = 0;
  for (const int rows : {1, 1024, 1025, 2600}) {
    const cv::Mat truth = Random(rows, 12, CV_8UC1, 60u + static_cast<unsigned>(rows));
    for (const bool top_down : {false, true}) {
      SCOPED_TRACE(std::to_string(rows) + (top_down ? " rows, top-down" : " rows, bottom-up"));
      int bits = 0;
      const std::string path =
          WriteBytes(dir + "/t" + std::to_string(n++) + ".bmp", BuildBmp(truth, 8, top_down, identity));
      EXPECT_TRUE(Identical(LoadImageNative(path, &bits), truth));
      EXPECT_TRUE(Identical(cv::imread(path, cv::IMREAD_UNCHANGED), truth));  // the peer agrees with the truth
    }
  }
  fs::remove_all(dir);
}

TEST(ImageFile, TruncatedOrHostileFilesAreInputErrorsNamingTheFile) {
  const std::string dir = TempDir();
  const cv::Mat index = Random(8, 8, CV_8UC1, 1);
  std::vector<cv::Vec3b> identity(256);
  for (int i = 0; i < 256; ++i) identity[static_cast<std::size_t>(i)] = cv::Vec3b::all(static_cast<uchar>(i));
  std::vector<unsigned char> bmp = BuildBmp(index, 8, false, identity);
  bmp.resize(bmp.size() - 5);
  const std::string truncated_bmp = WriteBytes(dir + "/truncated.bmp", bmp);
  std::vector<unsigned char> png = ramtk::image::EncodePng(Random(40, 40, CV_8UC1, 2));
  png.resize(png.size() / 2);
  const std::string truncated_png = WriteBytes(dir + "/truncated.png", png);
  std::vector<unsigned char> huge = BuildBmp(index, 8, false, identity);
  PutLe(&huge, 18, 1000000, 4);
  PutLe(&huge, 22, 1000000, 4);
  const std::string huge_bmp = WriteBytes(dir + "/huge.bmp", huge);
  for (const std::string& path : {truncated_bmp, truncated_png, huge_bmp}) {
    SCOPED_TRACE(path);
    int bits = 0;
    try {
      LoadImageNative(path, &bits);
      ADD_FAILURE() << "no error";
    } catch (const ramtk::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}

TEST(ImageFile, RealCameraFramesDecodeAsOpenCvDecodesThem) {
  const fs::path set = fs::path(RAMTK_SHARED_DIR) / "data/slmaster-binocular";
  if (!fs::exists(set / "L/0.bmp")) GTEST_SKIP() << "shared data not present: " << set;
  int files = 0;
  for (const char* side : {"L", "R"}) {
    for (const auto& entry : fs::directory_iterator(set / side)) {
      if (entry.path().extension() != ".bmp") continue;
      int bits = 0;
      const cv::Mat ours = LoadImageNative(entry.path().string(), &bits);
      EXPECT_TRUE(Identical(ours, cv::imread(entry.path().string(), cv::IMREAD_UNCHANGED))) << entry.path();
      ++files;
    }
  }
  EXPECT_GE(files, 38);
}

namespace {

// FrameRows against the pixels a file was built from: every window (including single pixels, the
// last row and column) and every step give the built pixels at the rows and columns named.
cv::Mat CutTruth(const cv::Mat& pixels, const cv::Rect& w, int step) {
  cv::Mat t((w.height + step - 1) / step, (w.width + step - 1) / step, CV_8UC1);
  for (int k = 0; k < t.rows; ++k)
    for (int j = 0; j < t.cols; ++j) t.at<uchar>(k, j) = pixels.at<uchar>(w.y + k * step, w.x + j * step);
  return t;
}

std::vector<cv::Vec3b> GreyRamp(bool inverted) {
  std::vector<cv::Vec3b> p(256);
  for (int i = 0; i < 256; ++i)
    p[static_cast<std::size_t>(i)] = cv::Vec3b::all(static_cast<uchar>(inverted ? 255 - i : i));
  return p;
}

}  // namespace

TEST(FrameRows, WindowsAndStepsReadThePixelsTheFileWasBuiltFrom) {
  const std::string dir = TempDir();
  int n = 0;
  // 37 px: padded rows (one read per row); 40 px: unpadded (whole-width windows in one read).
  for (const int width : {37, 40}) {
    const cv::Mat pixels = Random(29, width, CV_8UC1, static_cast<unsigned>(width));
    for (const bool top_down : {false, true}) {
      SCOPED_TRACE(std::to_string(width) + (top_down ? " px, top-down" : " px, bottom-up"));
      const std::string path =
          WriteBytes(dir + "/f" + std::to_string(n++) + ".bmp", BuildBmp(pixels, 8, top_down, GreyRamp(false)));
      ramtk::image::FrameRows rows;
      std::string why;
      ASSERT_TRUE(rows.Open(path, &why)) << why;
      EXPECT_EQ(rows.width(), width);
      EXPECT_EQ(rows.height(), 29);
      const cv::Rect windows[] = {{0, 0, width, 29},     {0, 5, width, 7},  {3, 5, 20, 11},
                                  {width - 1, 28, 1, 1}, {0, 28, width, 1}, {width - 2, 0, 2, 29}};
      for (const cv::Rect& w : windows)
        for (const int step : {1, 2, 3, 10, 64}) {
          SCOPED_TRACE(testing::Message() << w << " step " << step);
          EXPECT_TRUE(Identical(rows.Read(w, step), CutTruth(pixels, w, step)));
        }
      EXPECT_THROW(rows.Read({1, 0, width, 29}), std::invalid_argument);
      EXPECT_THROW(rows.Read({0, -1, 4, 4}), std::invalid_argument);
      EXPECT_THROW(rows.Read({0, 0, 4, 4}, 0), std::invalid_argument);
    }
  }
  fs::remove_all(dir);
}

TEST(FrameRows, OtherFilesAreLeftToTheWholeFileLoadersAndDamageIsNamed) {
  const std::string dir = TempDir();
  const cv::Mat pixels = Random(9, 12, CV_8UC1, 5);
  ramtk::image::FrameRows rows;
  std::string why;
  // Not row-readable: load whole (the palette maps the bytes, the samples are colour, or compressed).
  const std::string inverted = WriteBytes(dir + "/inverted.bmp", BuildBmp(pixels, 8, false, GreyRamp(true)));
  EXPECT_FALSE(rows.Open(inverted, &why));
  EXPECT_NE(why.find("identity"), std::string::npos) << why;
  const std::string bgr = WriteBytes(dir + "/bgr.bmp", BuildBmp(Random(9, 12, CV_8UC3, 6), 24, false));
  EXPECT_FALSE(rows.Open(bgr, &why));
  const std::string png = WriteBytes(dir + "/f.png", ramtk::image::EncodePng(pixels));
  EXPECT_FALSE(rows.Open(png, &why));
  EXPECT_FALSE(rows.is_open());
  // Damaged or missing: InputError naming the file.
  std::vector<unsigned char> bmp = BuildBmp(pixels, 8, false, GreyRamp(false));
  bmp.resize(bmp.size() - 5);
  const std::string truncated = WriteBytes(dir + "/truncated.bmp", bmp);
  for (const std::string& path : {truncated, dir + "/missing.bmp"}) {
    try {
      rows.Open(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const ramtk::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  // A file cut short after it was opened: the read names it.
  const std::string later = WriteBytes(dir + "/later.bmp", BuildBmp(pixels, 8, false, GreyRamp(false)));
  ASSERT_TRUE(rows.Open(later));
  fs::resize_file(later, 100);
  try {
    rows.Read({0, 0, 12, 9});
    ADD_FAILURE() << "no error";
  } catch (const ramtk::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(later), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// No descriptor is held between reads: a scan keeps 38 frames per camera open, and a batch
// with many sets in flight would otherwise exhaust the process's descriptors (1 024 by default).
TEST(FrameRows, OpenFramesHoldNoFileDescriptor) {
  const std::string dir = TempDir();
  const cv::Mat pixels = Random(6, 8, CV_8UC1, 7);
  const std::string path = WriteBytes(dir + "/f.bmp", BuildBmp(pixels, 8, true, GreyRamp(false)));
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &saved), 0);
  rlimit low = saved;
  low.rlim_cur = 64;
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &low), 0);
  std::vector<ramtk::image::FrameRows> frames(200);
  bool all = true, same = true;
  try {
    for (auto& f : frames) all = all && f.Open(path);
    for (const auto& f : frames) same = same && Identical(f.Read({0, 0, 8, 6}), pixels);
  } catch (const ramtk::InputError& e) {  // "Too many open files"
    all = false;
    ADD_FAILURE() << e.what();
  }
  setrlimit(RLIMIT_NOFILE, &saved);
  EXPECT_TRUE(all);
  EXPECT_TRUE(same);
  fs::remove_all(dir);
}

// The real frames (OpenCV-written bottom-up BMPs): windows as cut from the whole frame as
// cv::imread decodes it.
TEST(FrameRows, RealCameraFrameWindowsAreCutsOfTheFrameOpenCvDecodes) {
  const fs::path frame = fs::path(RAMTK_SHARED_DIR) / "data/slmaster-binocular/L/5.bmp";
  if (!fs::exists(frame)) GTEST_SKIP() << "shared data not present: " << frame;
  const cv::Mat truth = cv::imread(frame.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(truth.type(), CV_8UC1);
  ramtk::image::FrameRows rows;
  std::string why;
  ASSERT_TRUE(rows.Open(frame.string(), &why)) << why;
  for (const cv::Rect& w : {cv::Rect(0, 0, truth.cols, truth.rows), cv::Rect(411, 300, 313, 314)})
    for (const int step : {1, 4, 10}) EXPECT_TRUE(Identical(rows.Read(w, step), CutTruth(truth, w, step))) << w << step;
}
