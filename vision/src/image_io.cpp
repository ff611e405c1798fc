// OpenImageIO loading and atomic writing of images.
#include "ramtk/vision/image_io.h"

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ramtk/core/outputs.h"
#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

[[noreturn]] void Fail(const std::string& file, const std::string& message) {
  throw InputError({file, 0, ""}, message);
}

// Dimensions from the header, checked before anything is allocated: a corrupt or hostile header
// must give an error naming the file, not an allocation failure.
void CheckDimensions(const std::string& path, const OIIO::ImageSpec& spec) {
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) Fail(path, "image has no pixels");
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide ||
      static_cast<std::int64_t>(spec.width) * spec.height > kMaxImagePixels || spec.nchannels > 4) {
    Fail(path, "image header claims " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " x " +
                   std::to_string(spec.nchannels) + " samples; the limits are " + std::to_string(kMaxImageSide) +
                   " px per side, " + std::to_string(kMaxImagePixels) + " pixels and 4 channels (kMaxImageSide, "
                   "kMaxImagePixels)");
  }
}

}  // namespace

cv::Mat LoadImageDn(const std::string& path, int* bits_per_sample) {
  if (!std::filesystem::exists(path)) Fail(path, "image file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) Fail(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  int bits = 0;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    bits = 8;
  } else if (spec.format == OIIO::TypeDesc::UINT16) {
    bits = 16;
  } else {
    Fail(path, std::string("unsupported pixel type ") + spec.format.c_str() + " (expected 8- or 16-bit)");
  }
  CheckDimensions(path, spec);
  const int w = spec.width, h = spec.height, nc = spec.nchannels;
  std::vector<float> buf(static_cast<std::size_t>(w) * h * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, buf.data()))
    Fail(path, "cannot read pixels: " + in->geterror());
  in->close();
  const float scale = bits == 8 ? 255.0f : 65535.0f;
  const int grey_channels = nc >= 3 ? 3 : 1;  // ignore alpha
  cv::Mat out(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y) {
    float* row = out.ptr<float>(y);
    const float* src = buf.data() + static_cast<std::size_t>(y) * w * nc;
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int c = 0; c < grey_channels; ++c) s += src[x * nc + c];
      row[x] = std::round(s / grey_channels * scale * 16.0f) / 16.0f;  // undo float noise of the conversion
    }
  }
  if (bits_per_sample) *bits_per_sample = bits;
  return out;
}

cv::Mat LoadImageNative(const std::string& path, int* bits_per_sample) {
  if (!std::filesystem::exists(path)) Fail(path, "image file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) Fail(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  in->close();
  CheckDimensions(path, spec);
  if (spec.nchannels != 1 || (spec.format != OIIO::TypeDesc::UINT8 && spec.format != OIIO::TypeDesc::UINT16))
    return LoadImageDn(path, bits_per_sample);  // colour or unsupported: the converting loader (its errors)
  const bool eight = spec.format == OIIO::TypeDesc::UINT8;
  if (spec.width <= 0 || spec.height <= 0) Fail(path, "image has no pixels");
  // OpenCV's decoders read 8/16-bit grey BMP/PNG/TIFF straight into the matrix (measured faster
  // than OpenImageIO's scanline path for BMP, docs/performance.md); OpenImageIO for the rest.
  cv::Mat out = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (out.empty() || out.channels() != 1 || out.depth() != (eight ? CV_8U : CV_16U) || out.cols != spec.width ||
      out.rows != spec.height) {
    out.create(spec.height, spec.width, eight ? CV_8UC1 : CV_16UC1);
    auto again = OIIO::ImageInput::open(path);
    if (!again || !again->read_image(0, 0, 0, 1, spec.format, out.data))
      Fail(path, "cannot read pixels: " + (again ? again->geterror() : OIIO::geterror()));
  }
  if (bits_per_sample) *bits_per_sample = eight ? 8 : 16;
  return out;
}

ImageStack LoadImageStack(const std::vector<std::string>& paths, double dark_fraction, bool native) {
  if (paths.empty()) Fail("", "no images given");
  ImageStack stack;
  double brightest = 0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    int bits = 0;
    cv::Mat img = native ? LoadImageNative(paths[i], &bits) : LoadImageDn(paths[i], &bits);
    if (i == 0) {
      stack.bits_per_sample = bits;
      stack.full_scale = bits == 8 ? 255.0 : 65535.0;
    } else {
      if (img.size() != stack.frames[0].size())
        Fail(paths[i], "image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) + ", the first image " +
                           paths[0] + " is " + std::to_string(stack.frames[0].cols) + "x" +
                           std::to_string(stack.frames[0].rows));
      if (bits != stack.bits_per_sample)
        Fail(paths[i], std::to_string(bits) + "-bit image in a set of " + std::to_string(stack.bits_per_sample) +
                           "-bit images (first: " + paths[0] + ")");
    }
    double mx = 0;
    cv::minMaxLoc(img, nullptr, &mx);
    brightest = std::max(brightest, mx);
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
  OIIO::TypeDesc type;
  switch (image.depth()) {
    case CV_8U:
      type = OIIO::TypeDesc::UINT8;
      break;
    case CV_16U:
      type = OIIO::TypeDesc::UINT16;
      break;
    case CV_32F:
      type = OIIO::TypeDesc::FLOAT;
      break;
    default:
      throw InputError({path, 0, ""}, "unsupported matrix type for writing");
  }
  cv::Mat img = image.isContinuous() ? image : image.clone();
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2RGB);
  const std::filesystem::path target(path);
  const std::filesystem::path tmp =
      target.parent_path() / (target.stem().string() + ".tmp" + target.extension().string());
  RegisterTemporary(tmp);  // removed if interrupted (core/outputs.h)
  struct Unregister {
    const std::filesystem::path& p;
    ~Unregister() { UnregisterTemporary(p); }
  } unregister{tmp};
  {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw InputError({path, 0, ""}, "no image writer for this extension: " + OIIO::geterror());
    OIIO::ImageSpec spec(img.cols, img.rows, img.channels(), type);
    if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
    if (!out->open(tmp.string(), spec) || !out->write_image(type, img.data)) {
      const std::string err = out->geterror();
      out->close();
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, "cannot write image: " + err);
    }
    out->close();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError({path, 0, ""}, "cannot move the written image into place: " + ec.message());
  }
}

}  // namespace ramtk::vision
