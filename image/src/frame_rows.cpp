// Frames read by rows (frame_rows.h): the BMP layout of bmp_codec.cpp, rows read with pread.
#include "ramtk/image/frame_rows.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "ramtk/image/detail/fast_codecs.h"
#include "ramtk/core/error.h"

namespace ramtk::image {

namespace {

[[noreturn]] void Fail(const std::string& file, const std::string& message) {
  throw InputError({file, 0, ""}, message);
}

struct FdCloser {
  int fd;
  ~FdCloser() {
    if (fd >= 0) ::close(fd);
  }
};

// pread until `n` bytes are in or the file ends; false on a short read.
bool ReadFully(int fd, void* out, std::size_t n, long long offset) {
  auto* p = static_cast<unsigned char*>(out);
  while (n > 0) {
    const ssize_t got = ::pread(fd, p, n, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    p += got, n -= static_cast<std::size_t>(got), offset += got;
  }
  return true;
}

}  // namespace

bool FrameRows::Open(const std::string& path, std::string* why) {
  *this = FrameRows();
  auto say = [why](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  detail::RequireImageFile(path);
  detail::FileCloser file{std::fopen(path.c_str(), "rb")};
  if (!file.f) Fail(path, std::string("cannot open: ") + std::strerror(errno));
  unsigned char b[8] = {};
  const std::size_t n = std::fread(b, 1, sizeof(b), file.f);
  if (detail::SniffFormat(b, n) != detail::FastFormat::kBmp) return say("not a BMP file");
  detail::BmpLayout layout;
  std::string error;
  if (!detail::ReadBmpLayout(file.f, &layout, &error)) {
    if (error.find(detail::kNotReadHere) != std::string::npos) return say(error);
    Fail(path, error);
  }
  detail::CheckDimensions(path, layout.width, layout.height);
  if (!layout.identity) return say("not an 8-bit grey BMP with the identity palette");
  open_ = true;
  path_ = path;
  width_ = static_cast<int>(layout.width);
  height_ = static_cast<int>(layout.height);
  stride_ = layout.stride;
  pixel_offset_ = layout.pixel_offset;
  top_down_ = layout.top_down;
  return true;
}

cv::Mat FrameRows::Read(const cv::Rect& window, int step) const {
  if (!open_) throw std::invalid_argument("FrameRows::Read: no file open");
  if (step < 1 || window.width < 1 || window.height < 1 || window.x < 0 || window.y < 0 ||
      window.x + window.width > width_ || window.y + window.height > height_)
    throw std::invalid_argument("FrameRows::Read: window (" + std::to_string(window.x) + ", " +
                                std::to_string(window.y) + ", " + std::to_string(window.width) + " x " +
                                std::to_string(window.height) + ") step " + std::to_string(step) + " outside " +
                                std::to_string(width_) + " x " + std::to_string(height_) + " (" + path_ + ")");
  // The file is opened for each read and closed after it: no descriptor is held between reads
  // (a batch with many sets in flight would otherwise hold 76 per set, beyond the usual limit
  // of 1 024).
  const FdCloser file{::open(path_.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) Fail(path_, std::string("cannot open: ") + std::strerror(errno));
  const int rows = (window.height + step - 1) / step, cols = (window.width + step - 1) / step;
  cv::Mat out(rows, cols, CV_8UC1);
  auto row_offset = [&](long long y) { return pixel_offset_ + (top_down_ ? y : height_ - 1 - y) * stride_; };
  auto short_read = [&](int y) {
    Fail(path_, "row " + std::to_string(y) +
                    " could not be read (the file is shorter than its header says; changed "
                    "since it was opened?)");
  };
  if (step == 1 && window.width == width_ && stride_ == width_) {
    // Whole rows, contiguous in the file: one read, reversed if stored bottom-up.
    const long long first = top_down_ ? window.y : window.y + window.height - 1;
    if (!ReadFully(file.fd, out.data, static_cast<std::size_t>(stride_) * rows, row_offset(first)))
      short_read(window.y);
    if (!top_down_) detail::ReverseRows(&out);
    return out;
  }
  // One read per row: straight into the output with step 1, else the row's span and every
  // step-th sample of it.
  std::vector<unsigned char> span(step == 1 ? 0 : static_cast<std::size_t>((cols - 1) * step + 1));
  for (int k = 0; k < rows; ++k) {
    const int y = window.y + k * step;
    unsigned char* dst = out.ptr<unsigned char>(k);
    unsigned char* into = step == 1 ? dst : span.data();
    const std::size_t bytes = step == 1 ? static_cast<std::size_t>(cols) : span.size();
    if (!ReadFully(file.fd, into, bytes, row_offset(y) + window.x)) short_read(y);
    if (step > 1)
      for (int j = 0; j < cols; ++j) dst[j] = span[static_cast<std::size_t>(j) * step];
  }
  return out;
}

}  // namespace ramtk::image
