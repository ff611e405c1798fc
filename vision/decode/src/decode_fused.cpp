// The fused decode pass (decode_internal.h DecodeFused; tested against decode_reference.cpp): one
// pass per image row over the 8/16-bit (or float) samples computes the LS phase, background,
// modulation, fit residual, quality mask, Gray code and absolute coordinate; rows run in parallel
// (TBB). The step angles come from a table, sums are exact integers for 8-bit frames, and the
// trigonometry runs only on pixels that pass the quality mask. The results equal the reference
// path's within float rounding (tests/vision/decode_fast_test.cpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <opencv2/core/hal/intrin.hpp>
#include <type_traits>

#include "ramtk/vision/decode/detail/decode_avx2.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/kernels/fast_atan2.h"
#include "ramtk/vision/kernels/fast_round.h"

namespace ramtk::vision::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kTwoPi = 6.283185307179586476925;

struct RowCounts {
  long dark = 0, saturated = 0, low = 0, unwrap_rejected = 0, corrected = 0, valid = 0, sampled = 0;
  double ss = 0, phase_ss = 0, worst = 0;  // over the valid pixels with B >= b_sample
  float brightest = 0;  // the row's brightest sample of the finest phase-shift frames
};

// One frame's samples added to a chunk's sums (distinct buffers, so the loop is vectorised).
template <typename T, typename Acc>
void AccumulateFrame(const T* __restrict row, int len, float sk, float ck, float* __restrict s, float* __restrict c,
                     Acc* __restrict sum, Acc* __restrict sum2, float* __restrict top) {
  for (int x = 0; x < len; ++x) {
    const float v = static_cast<float>(row[x]);
    s[x] += v * sk;
    c[x] += v * ck;
    const Acc a = static_cast<Acc>(row[x]);
    sum[x] += a;
    sum2[x] += a * a;
    top[x] = v > top[x] ? v : top[x];
  }
}

// Sums of one phase-shift block over one row: S = sum I sin, C = sum I cos, sum I, sum I^2, max I.
// Acc is float for 8-bit samples (every sum exact while N * 255^2 < 2^24), else double. The row
// goes in chunks of kChunk pixels, every frame over one chunk before the next: the five sums of a
// chunk stay in L1 (a whole 3312 px row of them is 66 KB). Each pixel's sums are taken over the
// frames in the same order as over whole rows, so the results do not change.
template <typename T, typename Acc>
void AccumulateRow(const cv::Mat* const* frames, int n, int y, int width, const float* sn, const float* cs, float* s,
                   float* c, Acc* sum, Acc* sum2, float* top, int first = 0) {
  constexpr int kChunk = 256;
  for (int x0 = first; x0 < width; x0 += kChunk) {
    const int len = std::min(kChunk, width - x0);
    std::fill(s + x0, s + x0 + len, 0.0f);
    std::fill(c + x0, c + x0 + len, 0.0f);
    std::fill(sum + x0, sum + x0 + len, Acc(0));
    std::fill(sum2 + x0, sum2 + x0 + len, Acc(0));
    std::fill(top + x0, top + x0 + len, -std::numeric_limits<float>::infinity());
    for (int k = 0; k < n; ++k)
      AccumulateFrame<T, Acc>(frames[k]->ptr<T>(y) + x0, len, sn[k], cs[k], s + x0, c + x0, sum + x0, sum2 + x0,
                              top + x0);
  }
}

// AccumulateRow for 8-bit frames with the five sums of eight pixels held in registers over all the
// frames (OpenCV universal intrinsics), so they are not loaded and stored once per frame. Each
// pixel's sums take the same float operations in the same order as AccumulateFrame's, so the
// results are the same bit for bit.
void AccumulateRowU8(const cv::Mat* const* frames, int n, int y, int width, const float* sn, const float* cs, float* s,
                     float* c, float* sum, float* sum2, float* top) {
  constexpr int kMaxFrames = 64;
  const uchar* rows[kMaxFrames];
  if (n > kMaxFrames) {
    AccumulateRow<uchar, float>(frames, n, y, width, sn, cs, s, c, sum, sum2, top);
    return;
  }
  for (int k = 0; k < n; ++k) rows[k] = frames[k]->ptr<uchar>(y);
  // Sixteen pixels at a time on CPUs with AVX2 (the same bits), then eight at a time.
  int x = Avx2Kernels() ? AccumulateRowU8Avx2(rows, n, width, sn, cs, s, c, sum, sum2, top) : 0;
#if CV_SIMD128
  cv::v_float32x4 vsn[kMaxFrames], vcs[kMaxFrames];
  for (int k = 0; k < n; ++k) vsn[k] = cv::v_setall_f32(sn[k]), vcs[k] = cv::v_setall_f32(cs[k]);
  // Eight pixels per step: v_load_expand reads their 8 bytes with an unaligned 64-bit load (the
  // 4-byte v_load_expand_q dereferences an int pointer, which UBSan reports as misaligned).
  for (; x + 8 <= width; x += 8) {
    cv::v_float32x4 vs[2], vc[2], va[2], va2[2], vt[2];
    for (int h = 0; h < 2; ++h) {
      vs[h] = vc[h] = va[h] = va2[h] = cv::v_setzero_f32();
      vt[h] = cv::v_setall_f32(-std::numeric_limits<float>::infinity());
    }
    for (int k = 0; k < n; ++k) {
      cv::v_uint32x4 half[2];
      cv::v_expand(cv::v_load_expand(rows[k] + x), half[0], half[1]);
      for (int h = 0; h < 2; ++h) {
        const cv::v_float32x4 v = cv::v_cvt_f32(cv::v_reinterpret_as_s32(half[h]));
        vs[h] = vs[h] + v * vsn[k];
        vc[h] = vc[h] + v * vcs[k];
        va[h] = va[h] + v;
        va2[h] = va2[h] + v * v;
        vt[h] = cv::v_max(vt[h], v);
      }
    }
    for (int h = 0; h < 2; ++h) {
      cv::v_store(s + x + 4 * h, vs[h]);
      cv::v_store(c + x + 4 * h, vc[h]);
      cv::v_store(sum + x + 4 * h, va[h]);
      cv::v_store(sum2 + x + 4 * h, va2[h]);
      cv::v_store(top + x + 4 * h, vt[h]);
    }
  }
#endif
  // The last columns (fewer than eight) as AccumulateRow sums them, frame by frame.
  if (x < width) {
    const int len = width - x;
    std::fill(s + x, s + width, 0.0f);
    std::fill(c + x, c + width, 0.0f);
    std::fill(sum + x, sum + width, 0.0f);
    std::fill(sum2 + x, sum2 + width, 0.0f);
    std::fill(top + x, top + width, -std::numeric_limits<float>::infinity());
    for (int k = 0; k < n; ++k)
      AccumulateFrame<uchar, float>(rows[k] + x, len, sn[k], cs[k], s + x, c + x, sum + x, sum2 + x, top + x);
  }
}

// One Gray-code frame's bit of every pixel of a row (sample above the pixel's background A),
// folded into the running binary code: bit ^= g > A, code = code << 1 | bit. 8-bit frames take
// sixteen pixels at a time (the same float comparison).
template <typename T>
void GrayBit(const T* __restrict g, const float* __restrict a, int width, int* __restrict bit, int* __restrict code) {
  int x0 = 0;
#if CV_SIMD128
  if constexpr (std::is_same_v<T, uchar>) {
    const cv::v_int32x4 one = cv::v_setall_s32(1);
    for (; x0 + 16 <= width; x0 += 16) {
      cv::v_uint16x8 g16[2];
      cv::v_expand(cv::v_load(g + x0), g16[0], g16[1]);
      for (int h = 0; h < 2; ++h) {
        cv::v_uint32x4 g32[2];
        cv::v_expand(g16[h], g32[0], g32[1]);
        for (int q = 0; q < 2; ++q) {
          const int x = x0 + 8 * h + 4 * q;
          const cv::v_float32x4 above = cv::v_cvt_f32(cv::v_reinterpret_as_s32(g32[q])) > cv::v_load(a + x);
          const cv::v_int32x4 b = cv::v_load(bit + x) ^ (cv::v_reinterpret_as_s32(above) & one);
          cv::v_store(bit + x, b);
          cv::v_store(code + x, (cv::v_load(code + x) << 1) | b);
        }
      }
    }
  }
#endif
  for (int x = x0; x < width; ++x) {
    bit[x] ^= static_cast<float>(g[x]) > a[x] ? 1 : 0;
    code[x] = (code[x] << 1) | bit[x];
  }
}

#if CV_SIMD128_64F
// The finest block's per-pixel statistics of DecodeRow for 8-bit frames (float sums), eight
// pixels at a time: the same operations in the same order on lanes (double products and square
// roots as there, the flags as 0/1 bytes), so every output is bit-identical. Returns the pixels
// done; the caller finishes the row.
int FinestStatsU8(int n, int width, const float* s, const float* c, const float* sum, const float* sum2,
                  const float* top, float dark_dn, float saturation_dn, float b_min, uchar* dark, uchar* sat,
                  uchar* low, float* a_row, float* b_row, float* res_ss, float* res_row, float* brightest) {
  using cv::v_float32x4;
  using cv::v_float64x2;
  const v_float64x2 k2 = cv::v_setall_f64(2.0 / n), nd = cv::v_setall_f64(static_cast<double>(n)),
                    zero = cv::v_setall_f64(0.0);
  const v_float32x4 dark_v = cv::v_setall_f32(dark_dn), sat_v = cv::v_setall_f32(saturation_dn),
                    bmin_v = cv::v_setall_f32(b_min), dof = cv::v_setall_f32(static_cast<float>(n - 3));
  const cv::v_int32x4 one = cv::v_setall_s32(1);
  v_float32x4 bright = cv::v_setall_f32(*brightest);
  // 0/1 bytes of two float masks, ORed into flags[x .. x + 8).
  auto or_flags = [&](uchar* flags, int x, const v_float32x4& m0, const v_float32x4& m1) {
    const cv::v_int16x8 w = cv::v_pack(cv::v_reinterpret_as_s32(m0) & one, cv::v_reinterpret_as_s32(m1) & one);
    cv::v_store_low(flags + x, cv::v_load_low(flags + x) | cv::v_pack_u(w, w));
  };
  // Eight pixels per step on 256-bit lanes on CPUs with AVX2 (the same bits), then here.
  int x = Avx2Kernels() ? FinestStatsU8Avx2(n, width, s, c, sum, sum2, top, dark_dn, saturation_dn, b_min, dark, sat,
                                            low, a_row, b_row, res_ss, res_row, brightest)
                        : 0;
  bright = cv::v_setall_f32(*brightest);
  for (; x + 8 <= width; x += 8) {
    v_float32x4 b4[2], a4[2], ss4[2];
    for (int q = 0; q < 2; ++q) {
      const int i = x + 4 * q;
      const v_float32x4 sf = cv::v_load(s + i), cf = cv::v_load(c + i);
      const v_float32x4 mf = cv::v_load(sum + i), m2f = cv::v_load(sum2 + i);
      v_float64x2 b2[2], a2[2], r2[2];
      for (int h = 0; h < 2; ++h) {
        const v_float64x2 sd = h ? cv::v_cvt_f64_high(sf) : cv::v_cvt_f64(sf);
        const v_float64x2 cd = h ? cv::v_cvt_f64_high(cf) : cv::v_cvt_f64(cf);
        const v_float64x2 amp2 = sd * sd + cd * cd;
        b2[h] = k2 * cv::v_sqrt(amp2);
        const v_float64x2 mean = (h ? cv::v_cvt_f64_high(mf) : cv::v_cvt_f64(mf)) / nd;
        a2[h] = mean;
        const v_float64x2 sq = h ? cv::v_cvt_f64_high(m2f) : cv::v_cvt_f64(m2f);
        r2[h] = cv::v_max((sq - nd * mean * mean) - k2 * amp2, zero);
      }
      b4[q] = cv::v_cvt_f32(b2[0], b2[1]);
      a4[q] = cv::v_cvt_f32(a2[0], a2[1]);
      ss4[q] = cv::v_cvt_f32(r2[0], r2[1]);
      cv::v_store(a_row + i, a4[q]);
      cv::v_store(b_row + i, b4[q]);
      cv::v_store(res_ss + i, ss4[q]);
      cv::v_store(res_row + i, n > 3 ? cv::v_sqrt(ss4[q] / dof) : cv::v_setall_f32(0.0f));
    }
    const v_float32x4 t0 = cv::v_load(top + x), t1 = cv::v_load(top + x + 4);
    or_flags(dark, x, t0 < dark_v, t1 < dark_v);
    or_flags(sat, x, t0 >= sat_v, t1 >= sat_v);
    or_flags(low, x, b4[0] < bmin_v, b4[1] < bmin_v);
    bright = cv::v_max(t0, bright);  // top > bright ? top : bright, lane by lane
    bright = cv::v_max(t1, bright);
  }
  float lanes[4];
  cv::v_store(lanes, bright);
  for (const float v : lanes) *brightest = v > *brightest ? v : *brightest;
  return x;
}
#endif

// Row buffers of DecodeRow, one set per thread (allocated once, not per row).
template <typename Acc>
struct RowBuffers {
  std::vector<float> s, c, top, res_ss, a, res;
  std::vector<Acc> sum, sum2;
  std::vector<uchar> dark, sat, low;
  std::vector<int> code, bit;
  void Resize(int width) {
    const std::size_t w = static_cast<std::size_t>(width);
    for (std::vector<float>* v : {&s, &c, &top, &res_ss, &a, &res}) v->resize(w);
    sum.resize(w);
    sum2.resize(w);
    code.resize(w);
    bit.resize(w);
    for (std::vector<uchar>* v : {&dark, &sat, &low}) v->assign(w, 0);
  }
};

// The sums and per-pixel statistics of every phase-shift frequency of row y (coarser ones first,
// the finest last so its sums stay in the buffers): the dark, saturated and low-modulation flags,
// the finest block's A, B, residual sum of squares and residual RMS, and for heterodyne sets each
// coarser frequency's wrapped phase.
template <typename T, typename Acc>
void RowPhaseStats(const FastDecodeInput& in, int y, RowBuffers<Acc>& buffers, float* a_row, float* b_row,
                   float* res_row, RowCounts* rc, FastDecodeOutput* out) {
  const int width = in.width;
  std::vector<float>&s = buffers.s, &c = buffers.c, &top = buffers.top, &res_ss = buffers.res_ss;
  std::vector<Acc>&sum = buffers.sum, &sum2 = buffers.sum2;
  std::vector<uchar>&dark = buffers.dark, &sat = buffers.sat, &low = buffers.low;
  for (int f = static_cast<int>(in.ps_frames.size()) - 1; f >= 0; --f) {
    const int n = in.steps[f];
    if constexpr (std::is_same_v<T, uchar>)
      AccumulateRowU8(in.ps_frames[f].data(), n, y, width, in.sin_table[f].data(), in.cos_table[f].data(), s.data(),
                      c.data(), sum.data(), sum2.data(), top.data());
    else {
      // 16-bit frames: eight pixels at a time on CPUs with AVX2 (the same bits), the rest here.
      int first = 0;
      if constexpr (std::is_same_v<T, ushort>) {
        if (Avx2Kernels() && n <= 64) {
          const std::uint16_t* rows[64];
          for (int k = 0; k < n; ++k) rows[k] = in.ps_frames[f][k]->ptr<ushort>(y);
          first = AccumulateRowU16Avx2(rows, n, width, in.sin_table[f].data(), in.cos_table[f].data(), s.data(),
                                       c.data(), sum.data(), sum2.data(), top.data());
        }
      }
      AccumulateRow<T, Acc>(in.ps_frames[f].data(), n, y, width, in.sin_table[f].data(), in.cos_table[f].data(),
                            s.data(), c.data(), sum.data(), sum2.data(), top.data(), first);
    }
    int done = 0;
    if constexpr (std::is_same_v<T, ushort>)
      if (f == 0 && Avx2Kernels())
        done = FinestStatsDoubleAvx2(n, width, s.data(), c.data(), sum.data(), sum2.data(), top.data(), in.dark,
                                     in.saturation, in.b_min, dark.data(), sat.data(), low.data(), a_row, b_row,
                                     res_ss.data(), res_row, &rc->brightest);
#if CV_SIMD128_64F
    if constexpr (std::is_same_v<T, uchar>)
      if (f == 0)
        done = FinestStatsU8(n, width, s.data(), c.data(), sum.data(), sum2.data(), top.data(), in.dark, in.saturation,
                             in.b_min, dark.data(), sat.data(), low.data(), a_row, b_row, res_ss.data(), res_row,
                             &rc->brightest);
#endif
    for (int x = done; x < width; ++x) {
      const double amp2 = static_cast<double>(s[x]) * s[x] + static_cast<double>(c[x]) * c[x];
      const float b = static_cast<float>(2.0 / n * std::sqrt(amp2));
      dark[x] |= top[x] < in.dark;
      sat[x] |= top[x] >= in.saturation;
      if (f == 0) rc->brightest = top[x] > rc->brightest ? top[x] : rc->brightest;
      low[x] |= b < in.b_min;
      if (f == 0) {
        const double mean = static_cast<double>(sum[x]) / n;
        a_row[x] = static_cast<float>(mean);
        b_row[x] = b;
        res_ss[x] = static_cast<float>(std::max(0.0, static_cast<double>(sum2[x]) - n * mean * mean - 2.0 / n * amp2));
        res_row[x] = n > 3 ? std::sqrt(res_ss[x] / (n - 3)) : 0.0f;
      }
    }
    if (f > 0) {  // heterodyne: this frequency's wrapped phase where the pixel may be valid
      float* w = out->coarse_wrapped[f - 1].ptr<float>(y);
      for (int x0 = 0; x0 < width;) {  // runs of pixels that may be valid; 0 elsewhere
        if (dark[x0] | sat[x0] | low[x0]) {
          w[x0++] = 0.0f;
          continue;
        }
        int x1 = x0 + 1;
        while (x1 < width && !(dark[x1] | sat[x1] | low[x1])) ++x1;
        WrappedPhaseRow(s.data() + x0, c.data() + x0, x1 - x0, w + x0);
        x0 = x1;
      }
    }
  }
}

// The mask from the flags, counted by cause; masked pixels get phase 0 and a NaN coordinate. Runs
// of eight unflagged pixels (inside the object) or eight dark ones (the background) at once; the
// counts are the same as pixel by pixel.
inline void MaskRow(int width, const uchar* dark, const uchar* sat, const uchar* low, uchar* mk, float* phi,
                    float* coord, RowCounts* rc) {
  for (int x = 0; x < width; ++x) {
    if (x + 8 <= width) {
      std::uint64_t d8, s8, l8;
      std::memcpy(&d8, dark + x, sizeof d8);
      std::memcpy(&s8, sat + x, sizeof s8);
      std::memcpy(&l8, low + x, sizeof l8);
      if ((d8 | s8 | l8) == 0) {
        x += 7;
        continue;
      }
      if (d8 == 0x0101010101010101ull) {
        rc->dark += 8;
        std::fill_n(mk + x, 8, uchar(0));
        std::fill_n(phi + x, 8, 0.0f);
        std::fill_n(coord + x, 8, kNaN);
        x += 7;
        continue;
      }
    }
    if (dark[x]) {
      ++rc->dark;
    } else if (sat[x]) {
      ++rc->saturated;
    } else if (low[x]) {
      ++rc->low;
    } else {
      continue;
    }
    mk[x] = 0;
    phi[x] = 0;
    coord[x] = kNaN;
  }
}

// The wrapped phase on the row's runs of valid pixels, on lanes.
inline void PhaseOnValidRuns(int width, const uchar* mk, const float* s, const float* c, float* phi) {
  for (int x0 = 0; x0 < width;) {
    if (!mk[x0]) {
      ++x0;
      continue;
    }
    int x1 = x0 + 1;
    while (x1 < width && mk[x1]) ++x1;
    WrappedPhaseRow(s + x0, c + x0, x1 - x0, phi + x0);
    x0 = x1;
  }
}

// The absolute coordinate of the row's valid pixels from the Gray code and the wrapped phase:
// Gray -> binary code of every pixel, one bit frame at a time (vectorised), then the period order.
template <typename T, typename Acc>
void GrayCoordinateRow(const FastDecodeInput& in, int y, RowBuffers<Acc>& buffers, const float* a_row,
                       const float* phi, uchar* mk, float* coord, RowCounts* rc) {
  const int width = in.width;
  const double period = in.period;
  const int bits = static_cast<int>(in.gray_frames.size());
  int* code = buffers.code.data();
  int* bit = buffers.bit.data();
  std::fill(code, code + width, 0);
  std::fill(bit, bit + width, 0);
  for (int j = 0; j < bits; ++j) GrayBit(in.gray_frames[j]->ptr<T>(y), a_row, width, bit, code);
  // Four pixels at a time on CPUs with AVX2 (the same bits and counts), then pixel by pixel.
  const int done = Avx2Kernels() ? GrayCoordinatesAvx2(code, phi, width, in.phase_at_origin_rad, period, in.extent,
                                                       in.complementary, mk, coord, &rc->corrected,
                                                       &rc->unwrap_rejected)
                                 : 0;
  for (int x = done; x < width; ++x) {
    if (x + 8 <= width && EightZero(mk + x)) {  // eight masked pixels at once
      x += 7;
      continue;
    }
    if (!mk[x]) continue;
    const int binary = code[x];
    const double t = PeriodFractionOf(phi[x], in.phase_at_origin_rad);
    long order;
    if (in.complementary) {
      order = LRound((binary + 0.5) / 2.0 - t);
      if (order != (binary >> 1)) ++rc->corrected;
    } else {
      order = binary;
    }
    const double u = (order + t) * period;
    if (u < -0.5 || u >= in.extent - 0.5) {
      coord[x] = kNaN;
      mk[x] = 0;
      ++rc->unwrap_rejected;
    } else {
      coord[x] = static_cast<float>(u);
    }
  }
}

// The row's valid pixels, and the residual sums of those with B >= b_sample, into `rc`.
inline void CountValidRow(int width, int n_fine, float b_sample, const uchar* mk, const float* res_ss,
                          const float* res_row, const float* b_row, RowCounts* rc) {
  for (int x = 0; x < width; ++x) {
    if (x + 8 <= width && EightZero(mk + x)) {  // eight masked pixels at once
      x += 7;
      continue;
    }
    if (!mk[x]) continue;
    ++rc->valid;
    const float r = res_row[x];
    const float b = b_row[x];
    if (b < b_sample) continue;
    ++rc->sampled;
    rc->ss += res_ss[x];
    rc->phase_ss += 2.0 / n_fine * r * r / (b * b);
    rc->worst = std::max(rc->worst, static_cast<double>(r));
  }
}

// One row of every block. Writes the fine block's maps and the coordinate; counts into `rc`.
template <typename T>
void DecodeRow(const FastDecodeInput& in, int y, RowCounts* rc, FastDecodeOutput* out) {
  using Acc = std::conditional_t<std::is_same_v<T, uchar>, float, double>;
  const int width = in.width;
  thread_local RowBuffers<Acc> buffers;
  buffers.Resize(width);
  uchar* mk = out->mask.ptr<uchar>(y);
  std::fill(mk, mk + width, uchar(255));
  float* phi = out->wrapped.ptr<float>(y);
  // Without the diagnostic maps (FastDecodeOutput), A and the residual live in row buffers.
  float* a_row = out->background.empty() ? buffers.a.data() : out->background.ptr<float>(y);
  float* b_row = out->modulation.ptr<float>(y);
  float* res_row = out->fit_residual.empty() ? buffers.res.data() : out->fit_residual.ptr<float>(y);
  float* coord = out->coordinate.ptr<float>(y);
  RowPhaseStats<T, Acc>(in, y, buffers, a_row, b_row, res_row, rc, out);
  MaskRow(width, buffers.dark.data(), buffers.sat.data(), buffers.low.data(), mk, phi, coord, rc);
  PhaseOnValidRuns(width, mk, buffers.s.data(), buffers.c.data(), phi);
  // Absolute coordinate; heterodyne sets get theirs after all rows (UnwrapHeterodyne over whole images).
  if (in.heterodyne) return;
  if (!in.gray_frames.empty()) {
    GrayCoordinateRow<T, Acc>(in, y, buffers, a_row, phi, mk, coord, rc);
  } else {  // one period across the projector: the phase is absolute
    for (int x = 0; x < width; ++x)
      if (mk[x]) coord[x] = static_cast<float>(PeriodFractionOf(phi[x], in.phase_at_origin_rad) * in.period);
  }
  CountValidRow(width, in.steps[0], in.b_sample, mk, buffers.res_ss.data(), res_row, b_row, rc);
}

}  // namespace

void WrappedPhaseRow(const float* s, const float* c, int n, float* phi) {
  int x = Avx2Kernels() ? WrappedPhaseRowAvx2(s, c, n, phi) : 0;
#if CV_SIMD128_64F
  const cv::v_int64x2 sign = cv::v_setall_s64(static_cast<int64_t>(0x8000000000000000ull));
  auto negate = [&](const cv::v_float64x2& v) { return cv::v_reinterpret_as_f64(cv::v_reinterpret_as_s64(v) ^ sign); };
  const cv::v_float32x4 pi = cv::v_setall_f32(static_cast<float>(CV_PI));
  const cv::v_float32x4 two_pi = cv::v_setall_f32(static_cast<float>(kTwoPi));
  for (; x + 4 <= n; x += 4) {
    const cv::v_float32x4 sv = cv::v_load(s + x), cv4 = cv::v_load(c + x);
    const cv::v_float64x2 lo = Atan2x2(negate(cv::v_cvt_f64(sv)), cv::v_cvt_f64(cv4));
    const cv::v_float64x2 hi = Atan2x2(negate(cv::v_cvt_f64_high(sv)), cv::v_cvt_f64_high(cv4));
    const cv::v_float32x4 p = cv::v_cvt_f32(lo, hi);
    cv::v_store(phi + x, cv::v_select(p >= pi, p - two_pi, p));
  }
#endif
  for (; x < n; ++x) phi[x] = WrappedPhase(s[x], c[x]);
}

float WrappedPhase(float s, float c) {
  // In double without a library call (fast_atan2.h), then rounded to float: the correctly
  // rounded phase (glibc's atan2f, used before, was for ~84 % of pixels).
  float p = static_cast<float>(Atan2(-static_cast<double>(s), static_cast<double>(c)));
  if (p >= static_cast<float>(CV_PI)) p -= static_cast<float>(kTwoPi);
  return p;
}

void DecodeFused(const FastDecodeInput& in, FastDecodeOutput* out, FastDecodeCounts* counts) {
  const cv::Size size(in.width, in.height);
  out->wrapped.create(size, CV_32F);
  // The heterodyne unwrap reads the residual map after all rows.
  if (in.keep_diagnostic_maps) out->background.create(size, CV_32F);
  out->modulation.create(size, CV_32F);
  if (in.keep_diagnostic_maps || in.heterodyne) out->fit_residual.create(size, CV_32F);
  out->coordinate.create(size, CV_32F);
  out->mask.create(size, CV_8U);
  out->coarse_wrapped.clear();
  for (std::size_t f = 1; f < in.ps_frames.size(); ++f) out->coarse_wrapped.emplace_back(size, CV_32F);
  const int depth = in.ps_frames[0][0]->depth();
  std::vector<RowCounts> rows(static_cast<std::size_t>(in.height));
  tbb::parallel_for(tbb::blocked_range<int>(0, in.height, 8), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      if (depth == CV_8U) {
        DecodeRow<uchar>(in, y, &rows[y], out);
      } else if (depth == CV_16U) {
        DecodeRow<ushort>(in, y, &rows[y], out);
      } else {
        DecodeRow<float>(in, y, &rows[y], out);
      }
    }
  });
  FastDecodeCounts& c = *counts;
  c = FastDecodeCounts{};
  for (const RowCounts& rc : rows) {
    c.dark += rc.dark;
    c.saturated += rc.saturated;
    c.low_modulation += rc.low;
    c.unwrap_rejected += rc.unwrap_rejected;
    c.corrected += rc.corrected;
    c.valid += rc.valid;
    c.sampled += rc.sampled;
    c.residual_ss += rc.ss;
    c.phase_ss += rc.phase_ss;
    c.worst_residual = std::max(c.worst_residual, rc.worst);
    c.brightest = std::max(c.brightest, static_cast<double>(rc.brightest));
  }
}

}  // namespace ramtk::vision::detail
