// Windows around the ball for a scan (scan_roi.h).
#include "ramtk/vision/scan/scan_roi.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/parse.h"
#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision {
namespace {

// Bounding box of the projection of a sphere (centre in this camera's frame) into the camera,
// unclipped. The silhouette's box is the box of the projections of the sphere's points; 48 x 24
// samples of the sphere leave < 0.3 % of its projected radius uncovered, far below margin_px.
cv::Rect2d SilhouetteBox(const CameraIntrinsics& camera, const Vec3& centre, double radius, const std::string& which) {
  if (!(centre.z() > radius * 1.05))
    throw InputError({"", 0, "--roi"}, "the sphere at (" + std::to_string(centre.x()) + ", " +
                                           std::to_string(centre.y()) + ", " + std::to_string(centre.z()) +
                                           ") mm is not in front of the " + which + " camera");
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  const int na = 48, nb = 24;
  for (int b = 0; b <= nb; ++b) {
    const double theta = M_PI * b / nb;
    for (int a = 0; a < na; ++a) {
      const double phi = 2 * M_PI * a / na;
      const Vec3 p =
          centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const Vec2 px = ProjectPoint(camera, p);
      x0 = std::min(x0, px.x()), x1 = std::max(x1, px.x());
      y0 = std::min(y0, px.y()), y1 = std::max(y1, px.y());
    }
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

cv::Rect ClipToFrame(const cv::Rect2d& box, int margin_px, const CameraIntrinsics& camera, const std::string& which) {
  const int x0 = std::max(0, static_cast<int>(std::floor(box.x)) - margin_px);
  const int y0 = std::max(0, static_cast<int>(std::floor(box.y)) - margin_px);
  const int x1 = std::min(camera.width, static_cast<int>(std::ceil(box.x + box.width)) + margin_px + 1);
  const int y1 = std::min(camera.height, static_cast<int>(std::ceil(box.y + box.height)) + margin_px + 1);
  if (x1 - x0 < 2 || y1 - y0 < 2)
    throw InputError({"", 0, "--roi"}, "the sphere's window misses the " + which + " camera's " +
                                           std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                           " frame");
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

std::string ScanRoiOptions::Validate() const {
  if (mode == Mode::kPredicted) {
    if (predicted_centres_in_left_mm.empty())
      return "roi.predicted_centres_in_left_mm: a predicted window needs at least one centre";
    for (const Vec3& c : predicted_centres_in_left_mm)
      if (!c.allFinite()) return "roi.predicted_centres_in_left_mm: must be finite";
  }
  if (coarse_stride < 0 || coarse_stride > 64) return "roi.coarse_stride: must be 0 (automatic) or 1..64";
  if (!(margin_mm >= 0 && margin_mm <= 1000)) return "roi.margin_mm: must be in [0, 1000] mm";
  if (margin_px < 0 || margin_px > 10000) return "roi.margin_px: must be in [0, 10000] px";
  if (!(depth_margin_mm <= 10000)) return "roi.depth_margin_mm: must be <= 10000 mm (< 0: the whole range)";
  return "";
}

ScanRoiOptions ParseScanRoi(const std::string& text) {
  ScanRoiOptions o;
  if (text == "full" || text.empty()) return o;
  if (text == "auto") {
    o.mode = ScanRoiOptions::Mode::kAuto;
    return o;
  }
  const std::vector<double> v =
      ParseDoubleList(text, {"", 0, "--roi (full, auto, or a predicted centre X,Y,Z in mm)"}, 3);
  o.mode = ScanRoiOptions::Mode::kPredicted;
  o.predicted_centres_in_left_mm = {Vec3(v[0], v[1], v[2])};
  return o;
}

ScanWindows FullFrameWindows(const StereoCalibration& c) {
  return {cv::Rect(0, 0, c.left.width, c.left.height), cv::Rect(0, 0, c.right.width, c.right.height)};
}

ScanWindows WindowsAroundSpheres(const StereoCalibration& calibration, const std::vector<Sphere>& spheres,
                                 double margin_mm, int margin_px) {
  if (spheres.empty()) throw InputError({"", 0, "--roi"}, "no sphere to build a window around");
  cv::Rect2d left, right;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const double r = spheres[i].radius + margin_mm;
    const Vec3 c_left = spheres[i].centre_in_left;
    const Vec3 c_right = calibration.right_from_left * c_left;
    const cv::Rect2d bl = SilhouetteBox(calibration.left, c_left, r, "left");
    const cv::Rect2d br = SilhouetteBox(calibration.right, c_right, r, "right");
    left = i == 0 ? bl : (left | bl);
    right = i == 0 ? br : (right | br);
  }
  return {ClipToFrame(left, margin_px, calibration.left, "left"),
          ClipToFrame(right, margin_px, calibration.right, "right")};
}

StereoCalibration CropCalibration(const StereoCalibration& calibration, const ScanWindows& w) {
  StereoCalibration c = calibration;
  c.left.cx -= w.left.x, c.left.cy -= w.left.y;
  c.left.width = w.left.width, c.left.height = w.left.height;
  c.right.cx -= w.right.x, c.right.cy -= w.right.y;
  c.right.width = w.right.width, c.right.height = w.right.height;
  return c;
}

StereoCalibration SubsampleCalibration(const StereoCalibration& calibration, int stride) {
  StereoCalibration c = calibration;
  for (CameraIntrinsics* k : {&c.left, &c.right}) {
    k->fx /= stride, k->fy /= stride, k->cx /= stride, k->cy /= stride;
    k->width = (k->width + stride - 1) / stride;
    k->height = (k->height + stride - 1) / stride;
  }
  return c;
}

namespace {
template <typename T>
void SubsampleInto(const cv::Mat& f, int stride, cv::Mat* s) {
  for (int y = 0; y < s->rows; ++y) {
    const T* src = f.ptr<T>(y * stride);
    T* dst = s->ptr<T>(y);
    for (int x = 0; x < s->cols; ++x) dst[x] = src[x * stride];
  }
}
}  // namespace

std::vector<cv::Mat> SubsampleFrames(const std::vector<cv::Mat>& frames, int stride) {
  std::vector<cv::Mat> out(frames.size());
  // One frame per task (a thesis set: 38 frames of 8 MB, every stride-th row read).
  tbb::parallel_for(std::size_t{0}, frames.size(), [&](std::size_t i) {
    const cv::Mat& f = frames[i];
    cv::Mat s((f.rows + stride - 1) / stride, (f.cols + stride - 1) / stride, f.type());
    const std::size_t elem = f.elemSize();
    if (elem == 1) {
      SubsampleInto<std::uint8_t>(f, stride, &s);
    } else if (elem == 2) {
      SubsampleInto<std::uint16_t>(f, stride, &s);
    } else {
      for (int y = 0; y < s.rows; ++y) {
        const uchar* src = f.ptr<uchar>(y * stride);
        uchar* dst = s.ptr<uchar>(y);
        for (int x = 0; x < s.cols; ++x) std::copy_n(src + elem * x * stride, elem, dst + elem * x);
      }
    }
    out[i] = s;
  });
  return out;
}

std::vector<cv::Mat> CropFrames(const std::vector<cv::Mat>& frames, const cv::Rect& window) {
  std::vector<cv::Mat> out;
  out.reserve(frames.size());
  for (const cv::Mat& f : frames) out.push_back(f(window));
  return out;
}

std::string WindowText(const cv::Rect& w) {
  std::ostringstream s;
  s << w.x << "," << w.y << "," << w.width << "," << w.height;
  return s.str();
}

}  // namespace ramtk::vision
