// Image loading and atomic writing (image_file.h). PNG and uncompressed BMP are decoded here
// (ramtk/image/detail/fast_codecs.h; their header is checked against the limits first); every other format, and
// float images, go through the OpenImageIO backend module, loaded on first use (oiio_backend.h).
#include "ramtk/image/image_file.h"

#include <dlfcn.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "ramtk/image/detail/fast_codecs.h"
#include "oiio_backend.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"

namespace ramtk::image {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void Fail(const std::string& file, const std::string& message) {
  throw InputError({file, 0, ""}, message);
}

// Where the OpenImageIO backend module is: $RAMTK_OIIO_BACKEND, lib/ramtk/ beside the running
// program's prefix, the build tree, the install prefix.
std::vector<std::string> BackendCandidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("RAMTK_OIIO_BACKEND"); env && *env) out.push_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back((exe.parent_path().parent_path() / "lib/ramtk/libramtk_oiio_backend.so").string());
#ifdef RAMTK_OIIO_BACKEND_BUILD
  out.push_back(RAMTK_OIIO_BACKEND_BUILD);
#endif
#ifdef RAMTK_OIIO_BACKEND_INSTALL
  out.push_back(RAMTK_OIIO_BACKEND_INSTALL);
#endif
  return out;
}

const detail::OiioBackend& Backend(const std::string& for_file) {
  static std::once_flag once;
  static const detail::OiioBackend* backend = nullptr;
  static std::string tried;
  std::call_once(once, [] {
    for (const std::string& path : BackendCandidates()) {
      std::error_code ec;
      if (!fs::exists(path, ec)) continue;
      void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        tried += std::string(tried.empty() ? "" : "; ") + ::dlerror();
        continue;
      }
      using Entry = const detail::OiioBackend* (*)();
      auto entry = reinterpret_cast<Entry>(::dlsym(handle, "ramtk_oiio_backend"));
      if (entry && entry()->version == 1) {
        backend = entry();
        return;
      }
      tried += std::string(tried.empty() ? "" : "; ") + path + ": not a ramtk OpenImageIO backend";
    }
  });
  if (!backend)
    Fail(for_file, "this format needs the OpenImageIO backend (libramtk_oiio_backend.so), which was not found" +
                       (tried.empty() ? std::string(" (set RAMTK_OIIO_BACKEND)") : ": " + tried));
  return *backend;
}

// A PNG or BMP whose header passed the limits, decoded here; empty when the file is another
// format or a variant the fast decoders do not take (the backend then tries, and names the
// problem).
cv::Mat ReadFast(const std::string& path) {
  detail::FileCloser file{std::fopen(path.c_str(), "rb")};
  if (!file.f) return {};
  unsigned char b[32] = {};
  const std::size_t n = std::fread(b, 1, sizeof(b), file.f);
  const detail::FastFormat format = detail::SniffFormat(b, n);
  if (format == detail::FastFormat::kOther) return {};
  long long width = 0, height = 0;
  if (format == detail::FastFormat::kPng) {
    if (n < 24 || b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R') return {};
    width = (static_cast<long long>(b[16]) << 24) | (b[17] << 16) | (b[18] << 8) | b[19];
    height = (static_cast<long long>(b[20]) << 24) | (b[21] << 16) | (b[22] << 8) | b[23];
  } else {
    if (n < 26) return {};
    const auto le32 = [&b](int i) {
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(b[i]) | (static_cast<std::uint32_t>(b[i + 1]) << 8) |
                                       (static_cast<std::uint32_t>(b[i + 2]) << 16) |
                                       (static_cast<std::uint32_t>(b[i + 3]) << 24));
    };
    const bool core_header = le32(14) == 12;  // BITMAPCOREHEADER: 16-bit sizes
    width = core_header ? (b[18] | (b[19] << 8)) : le32(18);
    height = core_header ? static_cast<std::int16_t>(b[20] | (b[21] << 8)) : le32(22);
    height = std::llabs(height);  // negative: rows stored top-down
  }
  detail::CheckDimensions(path, width, height);
  std::rewind(file.f);
  std::string error;
  cv::Mat img;
  if (format == detail::FastFormat::kPng) {
    img = detail::ReadGreyPngFast(file.f);
    if (img.empty()) {
      std::rewind(file.f);
      img = detail::ReadPng(file.f, &error);
    }
  } else {
    img = detail::ReadBmp(file.f, &error);
  }
  // A damaged PNG/BMP is named here: OpenImageIO would read it with the same libpng (printing
  // libpng's complaint on stderr) or not at all. Variants not read here go to OpenImageIO.
  if (img.empty() && !error.empty() && error.find(detail::kNotReadHere) == std::string::npos) Fail(path, error);
  if (img.empty() || img.cols != width || img.rows != height) return {};
  return img;
}

// 8/16-bit, 1..4 channels -> single-channel CV_32F DN: colour averaged, alpha ignored.
cv::Mat GreyDn(const cv::Mat& img) {
  const int nc = img.channels();
  const int grey = nc >= 3 ? 3 : 1;
  cv::Mat f;
  img.convertTo(f, CV_MAKETYPE(CV_32F, nc));
  cv::Mat out(img.rows, img.cols, CV_32FC1);
  for (int y = 0; y < img.rows; ++y) {
    const float* src = f.ptr<float>(y);
    float* row = out.ptr<float>(y);
    for (int x = 0; x < img.cols; ++x) {
      float s = 0;
      for (int c = 0; c < grey; ++c) s += src[x * nc + c];
      row[x] = std::round(s / grey * 16.0f) / 16.0f;
    }
  }
  return out;
}

}  // namespace

void detail::RequireImageFile(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) Fail(path, "image file does not exist");
  RequireRegularFile(path);  // a FIFO or a device would block or never end
}

// Dimensions from the header, checked before anything is allocated: a corrupt or hostile header
// must give an error naming the file, not an allocation failure.
void detail::CheckDimensions(const std::string& path, long long width, long long height) {
  if (width <= 0 || height <= 0) Fail(path, "image has no pixels");
  if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)
    Fail(path, "image header claims " + std::to_string(width) + " x " + std::to_string(height) +
                   " pixels; the limits are " + std::to_string(kMaxImageSide) + " px per side and " +
                   std::to_string(kMaxImagePixels) + " pixels (kMaxImageSide, kMaxImagePixels)");
}

cv::Mat LoadImageDn(const std::string& path, int* bits_per_sample) {
  detail::RequireImageFile(path);
  const cv::Mat fast = ReadFast(path);
  if (!fast.empty()) {
    if (bits_per_sample) *bits_per_sample = fast.depth() == CV_8U ? 8 : 16;
    return GreyDn(fast);
  }
  cv::Mat out;
  int bits = 0;
  std::string error;
  if (!Backend(path).load_dn(path, kMaxImageSide, kMaxImagePixels, &out, &bits, &error)) Fail(path, error);
  if (bits_per_sample) *bits_per_sample = bits;
  return out;
}

cv::Mat LoadImageNative(const std::string& path, int* bits_per_sample) {
  detail::RequireImageFile(path);
  // OpenCV's decoders read 8/16-bit grey BMP/PNG straight into the matrix (measured faster than
  // OpenImageIO's scanline path for BMP, docs/performance.md); the backend for the rest.
  const cv::Mat fast = ReadFast(path);
  if (!fast.empty()) {
    if (bits_per_sample) *bits_per_sample = fast.depth() == CV_8U ? 8 : 16;
    return fast.channels() == 1 ? fast : GreyDn(fast);
  }
  cv::Mat out;
  int bits = 0;
  std::string error;
  if (!Backend(path).load_native(path, kMaxImageSide, kMaxImagePixels, &out, &bits, &error)) Fail(path, error);
  if (bits_per_sample) *bits_per_sample = bits;
  return out;
}

void WriteImage(const std::string& path, const cv::Mat& image) {
  const int depth = image.depth();
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F)
    throw InputError({path, 0, ""}, "unsupported matrix type for writing");
  const fs::path target(path);
  const fs::path tmp = target.parent_path() / (target.stem().string() + ".tmp" + target.extension().string());
  RegisterTemporary(tmp);  // removed if interrupted (core/outputs.h)
  struct Unregister {
    const fs::path& p;
    ~Unregister() { UnregisterTemporary(p); }
  } unregister{tmp};
  std::string ext = target.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // 8/16-bit PNG through libpng (BGR order as given); everything else through the backend.
  if (ext == ".png" && depth != CV_32F && (image.channels() == 1 || image.channels() == 3)) {
    std::vector<unsigned char> bytes;
    std::string error;
    const bool encoded = detail::EncodePng(image, &bytes, &error);
    std::FILE* f = encoded ? std::fopen(tmp.c_str(), "wb") : nullptr;
    const bool ok = f && std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = f && std::fclose(f) == 0;
    if (!ok || !closed) {
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, encoded ? "cannot write image" : error);
    }
  } else {
    std::string error;
    if (!Backend(path).write(tmp.string(), image, &error)) {
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, error);
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError({path, 0, ""}, "cannot move the written image into place: " + ec.message());
  }
}

cv::Mat LoadImageGrey8(const std::string& path) {
  detail::RequireImageFile(path);
  cv::Mat img = ReadFast(path);
  if (img.empty()) {
    int bits = 0;
    std::string error;
    if (!Backend(path).load_native(path, kMaxImageSide, kMaxImagePixels, &img, &bits, &error)) Fail(path, error);
    if (img.depth() == CV_32F) img.convertTo(img, CV_8U, bits == 16 ? 255.0 / 65535.0 : 1.0);
  }
  if (img.depth() == CV_16U) img.convertTo(img, CV_8U, 255.0 / 65535.0);
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  return img;
}

std::vector<unsigned char> EncodePng(const cv::Mat& image, const std::string& what) {
  std::vector<unsigned char> bytes;
  std::string error;
  if (!detail::EncodePng(image, &bytes, &error)) throw InputError({what, 0, ""}, error);
  return bytes;
}

std::vector<unsigned char> EncodeIndexedPng(const cv::Mat& index, const std::vector<cv::Vec3b>& palette_bgr,
                                            const std::string& what) {
  std::vector<unsigned char> bytes;
  std::string error;
  if (!detail::EncodeIndexedPng(index, palette_bgr, &bytes, &error)) throw InputError({what, 0, ""}, error);
  return bytes;
}

}  // namespace ramtk::image
