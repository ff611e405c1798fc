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
#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision::detail {

// One row's pixels to undistort: columns xs[0..count) (ascending) of row y; their ideal
// normalised coordinates go to ideal_x / ideal_y.
struct UndistortChain {
  const int* xs = nullptr;
  int count = 0;
  int y = 0;
  double* ideal_x = nullptr;
  double* ideal_y = nullptr;
  // With ChainRays: a = R (ideal, 1), and with a rectified frame r = rect (ideal, 1) as f r_x / r_z,
  // f r_y / r_z and r_z (the caller tests r_z; the quotients are taken whatever its value).
  double *a_x = nullptr, *a_y = nullptr, *a_z = nullptr;
  double *rs_u = nullptr, *rs_v = nullptr, *rs_z = nullptr;
};

// The rotations the chains' rays are turned by (Eigen's 3 x 3 product: each entry the row's
// products summed left to right, as the lanes take them).
struct ChainRays {
  Mat3 rotation = Mat3::Identity();  // R of a
  bool rectified = false;            // also fill rs_u, rs_v, rs_z
  Mat3 rect_from_camera = Mat3::Identity();
  double rect_f = 1;
};

// Undistorts every chain (as described above) with the camera's intrinsics; with `rays`, also
// fills each chain's ray arrays.
void UndistortChains(const CameraIntrinsics& camera, const UndistortChain* chains, int n,
                     const ChainRays* rays = nullptr);

}  // namespace ramtk::vision::detail
