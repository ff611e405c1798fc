#pragma once
// The stereo match's undistortion of its source pixels (stereo_match.cpp, RunPass), taken out of
// the walk along the epipolar curves so that several rows can run side by side.
//
// Along a row the match undistorts its pixels in order, each by Gauss-Newton
// (UndistortNormalized) started from the solutions before it: the linear extrapolation of the
// two before when they were the previous two pixels of the row, else the previous solution, else
// the distorted point. That chain is sequential within a row, but rows are independent: on CPUs
// with AVX2 four rows run on four lanes, each lane taking exactly the scalar operations (no fused
// multiply-add), so the results are bit-identical to UndistortNormalized's
// (tests/vision/undistort_chains_test.cpp).
#include "ramtk/vision/camera.h"

namespace ramtk::vision::detail {

// One row's pixels to undistort: columns xs[0..count) (ascending) of row y; their ideal
// normalised coordinates go to ideal_x / ideal_y.
struct UndistortChain {
  const int* xs = nullptr;
  int count = 0;
  int y = 0;
  double* ideal_x = nullptr;
  double* ideal_y = nullptr;
};

// Undistorts every chain (as described above) with the camera's intrinsics.
void UndistortChains(const CameraIntrinsics& camera, const UndistortChain* chains, int n);

}  // namespace ramtk::vision::detail
