#pragma once
// Camera frames read a few rows at a time. An uncompressed 8-bit grey BMP (what cameras, their
// SDKs and OpenCV write for grey frames) stores every row at a fixed offset, so a window, or every
// n-th row and column, costs only those rows' bytes: a scan windowed around the ball reads a few
// percent of a thesis frame's 8 MB. Compressed files (PNG) have no such offsets; their readers
// load them whole (image_file.h).

#include <opencv2/core.hpp>
#include <string>

namespace ramtk::image {

class FrameRows {
 public:
  FrameRows() = default;

  // Opens `path` and reads its header. False (nothing kept open; *why, if given, says why) if the
  // file is not an uncompressed 8-bit BMP whose palette is the identity grey ramp: load it whole
  // instead. InputError naming the file if it is missing or its header is damaged or beyond the
  // limits of image_file.h.
  bool Open(const std::string& path, std::string* why = nullptr);

  bool is_open() const { return open_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& path() const { return path_; }

  // The samples (CV_8UC1) at rows window.y + k * step < window.y + window.height and columns
  // window.x + j * step < window.x + window.width, k, j = 0, 1, ...: what LoadImageNative gives,
  // cut and subsampled. One read per row (one for all rows of a whole-width window with step 1);
  // the file is opened for the call only. Safe to call from several threads.
  // std::invalid_argument if the window leaves the image or step < 1; InputError naming the file
  // if it cannot be opened again or a read comes up short (the file changed since Open).
  cv::Mat Read(const cv::Rect& window, int step = 1) const;

 private:
  bool open_ = false;
  std::string path_;
  int width_ = 0, height_ = 0;
  long long stride_ = 0, pixel_offset_ = 0;
  bool top_down_ = false;
};

}  // namespace ramtk::image
