// Image stacks: a set's frames loaded in parallel and checked together. Single files are read and
// written by ramtk::image (image/include/ramtk/image/image_file.h).
#include "ramtk/vision/fringe/image_io.h"

#include <exception>
#include <tbb/parallel_for.h>

#include "ramtk/core/error.h"

namespace ramtk::vision {
namespace {

[[noreturn]] void Fail(const std::string& file, const std::string& message) {
  throw InputError({file, 0, ""}, message);
}

}  // namespace

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

}  // namespace ramtk::vision
