#pragma once
// 256-bit (AVX2) versions of the fused decode's row kernels (decode_fused.cpp), chosen at run time
// on CPUs that have AVX2. Each lane takes the same IEEE operations in the same order as the
// 128-bit kernels, and no fused multiply-add is used, so every output is bit-identical to theirs
// (tests/vision/decode_avx2_test.cpp). Each kernel returns how many leading pixels it did; the
// caller finishes the row with its own kernels.
#include <cstdint>
#include <opencv2/core.hpp>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {

// The five sums of AccumulateRowU8 (S, C, sum I, sum I^2, max I over the n frames' rows) for
// pixels [0, 16 k), the largest such k with 16 k <= width.
int AccumulateRowU8Avx2(const uchar* const* rows, int n, int width, const float* sn, const float* cs, float* s,
                        float* c, float* sum, float* sum2, float* top);

// AccumulateRow for 16-bit frames (sums of I and I^2 in double) for pixels [0, 8 k), 8 k <= width.
int AccumulateRowU16Avx2(const std::uint16_t* const* rows, int n, int width, const float* sn, const float* cs, float* s,
                         float* c, double* sum, double* sum2, float* top);

// WrappedPhaseRow for pixels [0, 8 k), 8 k <= n.
int WrappedPhaseRowAvx2(const float* s, const float* c, int n, float* phi);

// FinestStatsU8 (decode_fused.cpp) for pixels [0, 8 k), 8 k <= width; `brightest` is updated
// with the largest `top` among them.
int FinestStatsU8Avx2(int n, int width, const float* s, const float* c, const float* sum, const float* sum2,
                      const float* top, float dark_dn, float saturation_dn, float b_min, uchar* dark, uchar* sat,
                      uchar* low, float* a_row, float* b_row, float* res_ss, float* res_row, float* brightest);

// The absolute coordinate of DecodeRow's valid pixels [0, 4 k), 4 k <= width, from the Gray
// code's binary value `code` and the wrapped phase `phi` (PeriodFractionOf, LRound of the
// complementary code's order, the extent test): coord as float, or NaN with mk cleared outside
// the extent. Masked pixels (mk 0) are left as they are. Adds the orders the complementary bit
// corrected and the pixels rejected to the counts.
int GrayCoordinatesAvx2(const int* code, const float* phi, int width, double phase_at_origin_rad, double period,
                        int extent, bool complementary, uchar* mk, float* coord, long* corrected, long* rejected);

// DecodeRow's finest-block statistics from double sums (16-bit frames): the scalar loop's
// operations for pixels [0, 8 k), 8 k <= width (as FinestStatsU8Avx2 otherwise).
int FinestStatsDoubleAvx2(int n, int width, const float* s, const float* c, const double* sum, const double* sum2,
                          const float* top, float dark_dn, float saturation_dn, float b_min, uchar* dark, uchar* sat,
                          uchar* low, float* a_row, float* b_row, float* res_ss, float* res_row, float* brightest);

// SigmaRow (decode_internal.h) for pixels [0, 8 k), 8 k <= width.
int SigmaRowAvx2(const uchar* mk, const float* b, int width, double k_sigma, double ripple, double to_px, float* c,
                 float* sp, float* sc);

}  // namespace ramtk::vision::detail
