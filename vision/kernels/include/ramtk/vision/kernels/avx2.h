#pragma once
// The one switch for the AVX2 kernels, and the attributes they are written with.
//
// The build targets baseline x86-64. A kernel that gains from 256-bit lanes has a second version,
// a function marked RAMTK_AVX2 (no file is built with -mavx2, so no inline function of a shared
// header is ever compiled for AVX2), called only where Avx2Kernels() holds. Each lane takes the
// portable code's operations in the same order and no FMA target is enabled, so the results are
// bit-identical; each kernel has a test that compares the two paths bit for bit. The kernels:
// decode_avx2.h (the decode's rows), fast_sincos.h (SinCos4), undistort_chains.h (the match's
// source rays), stereo_rectified_grid.cpp (the back pass's grid), stereo_walk_lanes.h (the
// match's walk), stereo_search_list.h (the rows' searched pixels and valid cells),
// back_reach_lanes.h (the left-right check's reach), rank_select.cpp (order statistics),
// intensity_noise.cpp (the noise estimate's triples) and sphere_fit_ransac.cpp (RANSAC's band
// test, the point grid's keys).

namespace ramtk::vision::detail {

// Whether the AVX2 kernels run: the CPU (and the OS) has AVX2 and the environment variable
// RAMTK_AVX2 is not 0 (read once). SetAvx2Kernels overrides both (tests compare the two paths
// in one process); it cannot turn them on where the CPU lacks AVX2.
bool Avx2Kernels();
void SetAvx2Kernels(bool on);

}  // namespace ramtk::vision::detail

#define RAMTK_AVX2 __attribute__((target("avx2")))
#define RAMTK_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
