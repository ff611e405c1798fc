#pragma once
// The rectified grid of the stereo match's rectified search (StereoMatchOptions::rectified).
//
// Both cameras are turned, about their own centres, to one common orientation whose x axis is the
// baseline (from the left camera's centre to the right's): a scene point then lies on the same
// rectified row v = f Y / Z in both, and the epipolar curve of a pixel becomes a straight row. A
// camera's coordinate map is resampled once onto integer rectified pixels; the match then walks
// along one row pair instead of along a curve in the distorted image.

#include <opencv2/core.hpp>
#include <vector>

#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision::detail {

struct RectifiedPair {
  Mat3 rect_from_left = Mat3::Identity();   // rotation of the left camera's frame into the rectified one
  Mat3 rect_from_right = Mat3::Identity();  // the same for the right camera
  double f = 1;                             // focal length of the rectified pixels, px
  double baseline_mm = 0;                   // distance between the camera centres, mm
};

// x along the baseline, z the mean of the two optical axes made orthogonal to it, y = z × x; f the
// mean of the four focal lengths. Not finite (NaN rotations) for a rig without a usable baseline
// (cameras at one centre, or one behind the other along the mean axis, or facing opposite ways):
// ResampleOnRectifiedGrid then gives no grid and the match keeps the curve search.
RectifiedPair MakeRectifiedPair(const StereoCalibration& calibration);

// One camera's coordinate map on its rectified grid: sample (column i, row j) is the map's
// bilinear value at the distorted pixel of rectified pixel (u0 + i, v0 + j), where the cell under
// it is one `cell_ok` allows (index row * cols + column of its top-left pixel), else NaN.
struct RectifiedGrid {
  int u0 = 0, v0 = 0;
  cv::Mat coord;                        // CV_32F; empty if no cell is valid or the grid is too large
  std::vector<float> row_min, row_max;  // per grid row: the smallest and largest valid sample
  // Per grid row and block of kBlock cells (samples k kBlock .. (k + 1) kBlock, `blocks` per row,
  // index row * blocks + k): the smallest and largest valid sample, +inf / -inf if none.
  static constexpr int kBlock = 16;
  int blocks = 0;
  std::vector<float> block_min, block_max;
};

// The grid spans the rectified image of the valid cells' bounding box (2 px margin). It is left
// empty when it would exceed `max_pixels` (a calibration turning a camera far from its own axis),
// when the box's border reaches behind the rectified frame, or when the pair is not finite.
RectifiedGrid ResampleOnRectifiedGrid(const CameraIntrinsics& camera, const Mat3& rect_from_camera, double f,
                                      const cv::Mat& coord, const std::vector<uchar>& cell_ok, double max_pixels);

}  // namespace ramtk::vision::detail
