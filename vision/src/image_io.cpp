// Image loading and atomic writing. PNG and BMP go through OpenCV's decoders (their header is
// checked against the limits first); every other format, and float images, through the
// OpenImageIO backend module, loaded on first use (oiio_backend.h).
#include "ramtk/vision/image_io.h"

#include <dlfcn.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "oiio_backend.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"

namespace ramtk::vision {
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

// PNG or BMP, from the file's first bytes, with the size its header claims.
struct FastHeader {
  bool ok = false;
  long long width = 0, height = 0;
};

FastHeader ReadFastHeader(const std::string& path) {
  unsigned char b[32] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(b), sizeof(b));
  const std::streamsize n = in.gcount();
  FastHeader h;
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 24 && std::equal(kPng, kPng + 8, b) && b[12] == 'I' && b[13] == 'H' && b[14] == 'D' && b[15] == 'R') {
    h.width = (static_cast<long long>(b[16]) << 24) | (b[17] << 16) | (b[18] << 8) | b[19];
    h.height = (static_cast<long long>(b[20]) << 24) | (b[21] << 16) | (b[22] << 8) | b[23];
    h.ok = true;
  } else if (n >= 26 && b[0] == 'B' && b[1] == 'M') {
    const auto le32 = [&b](int i) {
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(b[i]) | (static_cast<std::uint32_t>(b[i + 1]) << 8) |
                                       (static_cast<std::uint32_t>(b[i + 2]) << 16) |
                                       (static_cast<std::uint32_t>(b[i + 3]) << 24));
    };
    h.width = le32(18);
    h.height = std::llabs(static_cast<long long>(le32(22)));  // negative: rows stored top-down
    h.ok = true;
  }
  return h;
}

// Dimensions from the header, checked before anything is allocated: a corrupt or hostile header
// must give an error naming the file, not an allocation failure.
void CheckDimensions(const std::string& path, long long width, long long height) {
  if (width <= 0 || height <= 0) Fail(path, "image has no pixels");
  if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)
    Fail(path, "image header claims " + std::to_string(width) + " x " + std::to_string(height) +
                   " pixels; the limits are " + std::to_string(kMaxImageSide) + " px per side and " +
                   std::to_string(kMaxImagePixels) + " pixels (kMaxImageSide, kMaxImagePixels)");
}

// OpenCV's decoder on a PNG/BMP whose header passed the limits; empty when it cannot read it (the
// backend then tries, and names the problem).
cv::Mat ReadFast(const std::string& path) {
  const FastHeader h = ReadFastHeader(path);
  if (!h.ok) return {};
  CheckDimensions(path, h.width, h.height);
  cv::Mat img;
  try {
    img = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    return {};
  }
  if (img.empty() || (img.depth() != CV_8U && img.depth() != CV_16U) || img.channels() > 4 ||
      img.cols != h.width || img.rows != h.height)
    return {};
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

cv::Mat LoadImageDn(const std::string& path, int* bits_per_sample) {
  if (!fs::exists(path)) Fail(path, "image file does not exist");
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
  if (!fs::exists(path)) Fail(path, "image file does not exist");
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

ImageStack LoadImageStack(const std::vector<std::string>& paths, double dark_fraction, bool native) {
  if (paths.empty()) Fail("", "no images given");
  // The files are decoded in parallel (PNG decoding is single-threaded inside the codec and was
  // the largest part of a thesis frame's decode); the checks below then run in file order, so
  // the error named for a bad set does not depend on which thread finished first.
  const std::size_t n = paths.size();
  std::vector<cv::Mat> images(n);
  std::vector<int> bits(n, 0);
  std::vector<double> brightest_of(n, 0.0);
  std::vector<std::exception_ptr> errors(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    try {
      images[i] = native ? LoadImageNative(paths[i], &bits[i]) : LoadImageDn(paths[i], &bits[i]);
      cv::minMaxLoc(images[i], nullptr, &brightest_of[i]);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  ImageStack stack;
  double brightest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (errors[i]) std::rethrow_exception(errors[i]);
    const cv::Mat& img = images[i];
    if (i == 0) {
      stack.bits_per_sample = bits[i];
      stack.full_scale = bits[i] == 8 ? 255.0 : 65535.0;
    } else {
      if (img.size() != stack.frames[0].size())
        Fail(paths[i], "image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) + ", the first image " +
                           paths[0] + " is " + std::to_string(stack.frames[0].cols) + "x" +
                           std::to_string(stack.frames[0].rows));
      if (bits[i] != stack.bits_per_sample)
        Fail(paths[i], std::to_string(bits[i]) + "-bit image in a set of " + std::to_string(stack.bits_per_sample) +
                           "-bit images (first: " + paths[0] + ")");
    }
    brightest = std::max(brightest, brightest_of[i]);
    stack.frames.push_back(img);
    stack.files.push_back(paths[i]);
  }
  if (brightest < dark_fraction * stack.full_scale)
    Fail(paths[0], "all " + std::to_string(paths.size()) + " images are dark (brightest sample " +
                       std::to_string(brightest) + " DN < " + std::to_string(dark_fraction * stack.full_scale) +
                       " DN): projector off or wrong exposure?");
  return stack;
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
  // 8/16-bit PNG through OpenCV (BGR order as given); everything else through the backend.
  if (ext == ".png" && depth != CV_32F && (image.channels() == 1 || image.channels() == 3)) {
    bool ok = false;
    try {
      ok = cv::imwrite(tmp.string(), image);
    } catch (const cv::Exception& e) {
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, std::string("cannot write image: ") + e.what());
    }
    if (!ok) {
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, "cannot write image");
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

}  // namespace ramtk::vision
