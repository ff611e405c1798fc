// OpenImageIO reading and writing for image_file.cpp, compiled into the ramtk_oiio_backend module
// (see oiio_backend.h).
#include "oiio_backend.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace {

using ramtk::image::detail::OiioBackend;

bool CheckDimensions(const OIIO::ImageSpec& spec, int max_side, long long max_pixels, std::string* error) {
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    *error = "image has no pixels";
    return false;
  }
  if (spec.width > max_side || spec.height > max_side ||
      static_cast<std::int64_t>(spec.width) * spec.height > max_pixels || spec.nchannels > 4) {
    *error = "image header claims " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " x " +
             std::to_string(spec.nchannels) + " samples; the limits are " + std::to_string(max_side) +
             " px per side, " + std::to_string(max_pixels) +
             " pixels and 4 channels (kMaxImageSide, kMaxImagePixels)";
    return false;
  }
  return true;
}

bool LoadDn(const std::string& path, int max_side, long long max_pixels, cv::Mat* out, int* bits,
            std::string* error) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    *error = "cannot read image: " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.format == OIIO::TypeDesc::UINT8) {
    *bits = 8;
  } else if (spec.format == OIIO::TypeDesc::UINT16) {
    *bits = 16;
  } else {
    *error = std::string("unsupported pixel type ") + spec.format.c_str() + " (expected 8- or 16-bit)";
    return false;
  }
  if (!CheckDimensions(spec, max_side, max_pixels, error)) return false;
  const int w = spec.width, h = spec.height, nc = spec.nchannels;
  std::vector<float> buf(static_cast<std::size_t>(w) * h * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, buf.data())) {
    *error = "cannot read pixels: " + in->geterror();
    return false;
  }
  in->close();
  const float scale = *bits == 8 ? 255.0f : 65535.0f;
  const int grey_channels = nc >= 3 ? 3 : 1;  // ignore alpha
  out->create(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y) {
    float* row = out->ptr<float>(y);
    const float* src = buf.data() + static_cast<std::size_t>(y) * w * nc;
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int c = 0; c < grey_channels; ++c) s += src[x * nc + c];
      row[x] = std::round(s / grey_channels * scale * 16.0f) / 16.0f;  // undo float noise of the conversion
    }
  }
  return true;
}

bool LoadNative(const std::string& path, int max_side, long long max_pixels, cv::Mat* out, int* bits,
                std::string* error) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    *error = "cannot read image: " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec spec = in->spec();
  if (!CheckDimensions(spec, max_side, max_pixels, error)) return false;
  if (spec.nchannels != 1 || (spec.format != OIIO::TypeDesc::UINT8 && spec.format != OIIO::TypeDesc::UINT16)) {
    in->close();
    return LoadDn(path, max_side, max_pixels, out, bits, error);  // colour or other: the converting loader
  }
  const bool eight = spec.format == OIIO::TypeDesc::UINT8;
  out->create(spec.height, spec.width, eight ? CV_8UC1 : CV_16UC1);
  if (!in->read_image(0, 0, 0, 1, spec.format, out->data)) {
    *error = "cannot read pixels: " + in->geterror();
    return false;
  }
  *bits = eight ? 8 : 16;
  return true;
}

bool Write(const std::string& path, const cv::Mat& image, std::string* error) {
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
      *error = "unsupported matrix type for writing";
      return false;
  }
  cv::Mat img = image.isContinuous() ? image : image.clone();
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2RGB);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    *error = "no image writer for this extension: " + OIIO::geterror();
    return false;
  }
  OIIO::ImageSpec spec(img.cols, img.rows, img.channels(), type);
  if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
  // No write time in the file (OpenImageIO's TIFF writer stamps the clock otherwise): the same
  // inputs give the same bytes; the run's time is in the provenance block beside it.
  spec.attribute("DateTime", "");
  if (!out->open(path, spec) || !out->write_image(type, img.data)) {
    *error = "cannot write image: " + out->geterror();
    out->close();
    return false;
  }
  if (!out->close()) {
    *error = "cannot write image: " + out->geterror();
    return false;
  }
  return true;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const OiioBackend* ramtk_oiio_backend() {
  static const OiioBackend backend = [] {
    OiioBackend b;
    b.load_dn = &LoadDn;
    b.load_native = &LoadNative;
    b.write = &Write;
    return b;
  }();
  return &backend;
}
