#pragma once
// DistortNormalized and its Jacobian (camera_model.h) on four AVX2 lanes, for the kernels that map
// rays to pixels (undistort_chains.cpp, stereo_rectified_grid.cpp, stereo_walk_lanes.cpp). Call
// only from a RAMTK_AVX2 function where Avx2Kernels() holds.
#include <immintrin.h>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/camera.h"

namespace ramtk::vision::detail {

// The distorted point (ux, uy) of the ideal points (x, y), with r^2 and the radial factor (the
// Jacobian reuses them): DistortNormalized's expressions as written, operation for operation, so
// each lane is bit-identical to it.
RAMTK_AVX2_INLINE void DistortNormalized4(const Distortion& d, __m256d x, __m256d y, __m256d* r2, __m256d* radial,
                                          __m256d* ux, __m256d* uy) {
  const __m256d two = _mm256_set1_pd(2.0);
  *r2 = _mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y));
  *radial = _mm256_add_pd(
      _mm256_set1_pd(1.0),
      _mm256_mul_pd(*r2, _mm256_add_pd(_mm256_set1_pd(d.k1),
                                       _mm256_mul_pd(*r2, _mm256_add_pd(_mm256_set1_pd(d.k2),
                                                                        _mm256_mul_pd(*r2, _mm256_set1_pd(d.k3)))))));
  // x radial + 2 p1 x y + p2 (r^2 + 2 x^2), y radial + p1 (r^2 + 2 y^2) + 2 p2 x y.
  *ux = _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(x, *radial), _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2.0 * d.p1), x), y)),
      _mm256_mul_pd(_mm256_set1_pd(d.p2), _mm256_add_pd(*r2, _mm256_mul_pd(_mm256_mul_pd(two, x), x))));
  *uy = _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(y, *radial),
                    _mm256_mul_pd(_mm256_set1_pd(d.p1), _mm256_add_pd(*r2, _mm256_mul_pd(_mm256_mul_pd(two, y), y)))),
      _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2.0 * d.p2), x), y));
}

// DistortNormalizedJacobian's entries at the same points, from DistortNormalized4's r^2 and radial
// factor (the expressions as written, operation for operation).
RAMTK_AVX2_INLINE void DistortJacobian4(const Distortion& d, __m256d x, __m256d y, __m256d r2, __m256d radial,
                                        __m256d* j00, __m256d* j01, __m256d* j10, __m256d* j11) {
  const __m256d two = _mm256_set1_pd(2.0);
  const __m256d two_p1 = _mm256_set1_pd(2.0 * d.p1), two_p2 = _mm256_set1_pd(2.0 * d.p2);
  const __m256d dr = _mm256_add_pd(
      _mm256_set1_pd(d.k1),
      _mm256_mul_pd(r2, _mm256_add_pd(_mm256_set1_pd(2.0 * d.k2),
                                      _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(3.0), r2), _mm256_set1_pd(d.k3)))));
  const __m256d xd2 = _mm256_mul_pd(_mm256_mul_pd(x, dr), two), yd2 = _mm256_mul_pd(_mm256_mul_pd(y, dr), two);
  *j00 = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(radial, _mm256_mul_pd(xd2, x)), _mm256_mul_pd(two_p1, y)),
                       _mm256_mul_pd(_mm256_set1_pd(d.p2 * 6.0), x));
  *j01 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(xd2, y), _mm256_mul_pd(two_p1, x)),
                       _mm256_mul_pd(_mm256_set1_pd(d.p2 * 2.0), y));
  *j10 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(yd2, x), _mm256_mul_pd(_mm256_set1_pd(d.p1 * 2.0), x)),
                       _mm256_mul_pd(two_p2, y));
  *j11 = _mm256_add_pd(
      _mm256_add_pd(_mm256_add_pd(radial, _mm256_mul_pd(yd2, y)), _mm256_mul_pd(_mm256_set1_pd(d.p1 * 6.0), y)),
      _mm256_mul_pd(two_p2, x));
}

}  // namespace ramtk::vision::detail
