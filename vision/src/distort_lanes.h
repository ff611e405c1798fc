#pragma once
// DistortNormalized (camera_model.h) on four AVX2 lanes, for the kernels that map rays to pixels
// (undistort_chains.cpp, stereo_rectified_grid.cpp). Call only from a RAMTK_AVX2 function where
// Avx2Kernels() holds.
#include <immintrin.h>

#include "avx2.h"
#include "ramtk/vision/camera.h"

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

}  // namespace ramtk::vision::detail
