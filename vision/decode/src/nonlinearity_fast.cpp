// The ripple estimator of detail::CorrectPhaseNonlinearityReference (nonlinearity.cpp), organised for speed
// and memory: only the bounding box of the mask is processed (every pixel the fit uses has its
// whole window inside it), in strips of rows whose buffers are a few window heights deep (not
// maps of the box: 12 basis maps of a 1.3 Mpx frame were 60 MB), the basis functions are
// evaluated with a branch-free sincos on two lanes (fast_sincos.h; the higher orders by angle addition) and stored as
// float, the box filters of the basis run in parallel, and the normal equations are accumulated
// per row in parallel without per-pixel allocation.
#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/fast_sincos.h"
#include "nonlinearity_internal.h"
#include "ramtk/core/error.h"
#include "ramtk/vision/decode/nonlinearity.h"

namespace ramtk::vision {
namespace {

using detail::SinCos;

constexpr int kMaxTerms = 13;  // 1 + 2 * 6 orders

struct Normal {
  double ata[kMaxTerms][kMaxTerms] = {};
  double atb[kMaxTerms] = {};
  double ss = 0;
  long used = 0;
  void Add(const Normal& o, int terms) {
    for (int i = 0; i < terms; ++i) {
      for (int j = 0; j <= i; ++j) ata[i][j] += o.ata[i][j];
      atb[i] += o.atb[i];
    }
    ss += o.ss;
    used += o.used;
  }
  // The first `terms` equations as Eigen's (the full symmetric matrix).
  void ToEigen(int terms, Eigen::MatrixXd* a, Eigen::VectorXd* b) const {
    a->resize(terms, terms);
    b->resize(terms);
    for (int i = 0; i < terms; ++i) {
      for (int j = 0; j <= i; ++j) (*a)(i, j) = (*a)(j, i) = ata[i][j];
      (*b)[i] = atb[i];
    }
  }
  // The least-squares coefficients of the first `terms` equations.
  Eigen::VectorXd Solve(int terms) const {
    Eigen::MatrixXd a;
    Eigen::VectorXd b;
    ToEigen(terms, &a, &b);
    return a.ldlt().solve(b);
  }
};

// One strip of output rows [y0, y1) of the box with the rows its windows reach, [a, b) =
// [y0 - h, y1 + h) clipped to the box. Window sums are taken by box filters on views of the
// strip's rows [y0, y1) inside buffers holding [a, b): without BORDER_ISOLATED, OpenCV's filters
// read the rows around a view from its parent buffer, so the sums equal those over the whole box
// (zeros beyond the box, as the reference's zero border). Memory is a few rows deep, not the box.
struct Strip {
  int y0 = 0, y1 = 0, a = 0, b = 0;
  cv::Rect Rows(int width) const { return {0, y0 - a, width, y1 - y0}; }  // [y0, y1) inside [a, b)
};

// Valid pixels per window (exact integers in float), rows [y0, y1).
void StripDen(const cv::Mat& mask, const Strip& st, int w, cv::Mat* mf, cv::Mat* den) {
  mask.rowRange(st.a, st.b).convertTo(*mf, CV_32F, 1.0 / 255.0);
  cv::boxFilter((*mf)(st.Rows(mask.cols)), *den, CV_32F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
}

// High-passed phase on rows [y0, y1) (CV_64F): clean - box(clean) / den, with clean = the phase
// where the mask is set and 0 elsewhere. In two parts: the window sums box(clean) into `hp`
// (StripPhaseSums, which does not need den), then the difference in place (StripHighPass).
void StripPhaseSums(const cv::Mat& phase, const cv::Mat& mask, const Strip& st, int w, cv::Mat* clean, cv::Mat* hp) {
  clean->create(st.b - st.a, phase.cols, CV_64F);
  tbb::parallel_for(tbb::blocked_range<int>(st.a, st.b, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* p = phase.ptr<float>(y);
      const uchar* m = mask.ptr<uchar>(y);
      double* c = clean->ptr<double>(y - st.a);
      for (int x = 0; x < phase.cols; ++x) c[x] = m[x] ? static_cast<double>(p[x]) : 0.0;
    }
  });
  cv::boxFilter((*clean)(st.Rows(phase.cols)), *hp, CV_64F, cv::Size(w, w), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
}

void StripHighPass(int width, const cv::Mat& den, const Strip& st, const cv::Mat& clean, cv::Mat* hp) {
  tbb::parallel_for(tbb::blocked_range<int>(st.y0, st.y1, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const double* c = clean.ptr<double>(y - st.a);
      const float* d = den.ptr<float>(y - st.y0);
      double* h = hp->ptr<double>(y - st.y0);
      for (int x = 0; x < width; ++x) h[x] = c[x] - h[x] / std::max(static_cast<double>(d[x]), 1e-6);
    }
  });
}

// StripBasis's run of valid pixels [x, x1) four at a time on AVX2 lanes (the same bits as the
// two-lane loop); returns the first pixel not done.
RAMTK_AVX2 int BasisRunAvx2(const float* p, int x, int x1, int steps, int orders,
                                                 float* const* out) {
  const __m256d n4 = _mm256_set1_pd(static_cast<double>(steps));
  for (; x + 4 <= x1; x += 4) {
    __m256d s1, c1;
    detail::SinCos4(_mm256_mul_pd(n4, _mm256_cvtps_pd(_mm_loadu_ps(p + x))), &s1, &c1);
    _mm_storeu_ps(out[0] + x, _mm256_cvtpd_ps(s1));
    _mm_storeu_ps(out[1] + x, _mm256_cvtpd_ps(c1));
    __m256d sa = s1, ca = c1;
    for (int o = 1; o < orders; ++o) {
      const __m256d sn = _mm256_add_pd(_mm256_mul_pd(sa, c1), _mm256_mul_pd(ca, s1));
      const __m256d cn = _mm256_sub_pd(_mm256_mul_pd(ca, c1), _mm256_mul_pd(sa, s1));
      sa = sn, ca = cn;
      _mm_storeu_ps(out[2 * o] + x, _mm256_cvtpd_ps(sa));
      _mm_storeu_ps(out[2 * o + 1] + x, _mm256_cvtpd_ps(ca));
    }
  }
  return x;
}

// The ripple basis sin/cos(m N phi_wrapped), m = 1..orders, at valid pixels (0 elsewhere), of
// rows [a, b) into `basis` (one CV_32F buffer per function), and its window sums on [y0, y1).
void StripBasis(const cv::Mat& wrapped, const cv::Mat& mask, int steps, int orders, const Strip& st, int w,
                std::vector<cv::Mat>* basis, std::vector<cv::Mat>* bsum) {
  const int nb = 2 * orders;
  const bool avx2 = detail::Avx2Kernels();
  for (cv::Mat& b : *basis) b.create(st.b - st.a, wrapped.cols, CV_32F);
  tbb::parallel_for(tbb::blocked_range<int>(st.a, st.b, 8), [&](const tbb::blocked_range<int>& r) {
    std::vector<float*> out(nb);
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* p = wrapped.ptr<float>(y);
      const uchar* m = mask.ptr<uchar>(y);
      for (int i = 0; i < nb; ++i) {
        out[i] = (*basis)[i].ptr<float>(y - st.a);
        std::fill_n(out[i], wrapped.cols, 0.0f);  // 0 where masked, on a sparse mask most of the row
      }
      // The row's runs of valid pixels, four pixels at a time on two lanes (SinCos2, bit-identical
      // to SinCos), the rest one by one. The higher orders by angle addition from the first, in
      // double.
      for (int x0 = 0; x0 < wrapped.cols;) {
        if (!m[x0]) {
          ++x0;
          continue;
        }
        int x1 = x0 + 1;
        while (x1 < wrapped.cols && m[x1]) ++x1;
        int x = avx2 ? BasisRunAvx2(p, x0, x1, steps, orders, out.data()) : x0;
#if CV_SIMD128_64F
        const cv::v_float64x2 n2 = cv::v_setall_f64(static_cast<double>(steps));
        for (; x + 4 <= x1; x += 4) {
          const cv::v_float32x4 phase = cv::v_load(p + x);
          cv::v_float64x2 s1a, c1a, s1b, c1b;
          detail::SinCos2(n2 * cv::v_cvt_f64(phase), &s1a, &c1a);
          detail::SinCos2(n2 * cv::v_cvt_f64_high(phase), &s1b, &c1b);
          cv::v_store(out[0] + x, cv::v_cvt_f32(s1a, s1b));
          cv::v_store(out[1] + x, cv::v_cvt_f32(c1a, c1b));
          cv::v_float64x2 sa = s1a, ca = c1a, sb = s1b, cb = c1b;
          for (int o = 1; o < orders; ++o) {
            const cv::v_float64x2 sna = sa * c1a + ca * s1a, cna = ca * c1a - sa * s1a;
            const cv::v_float64x2 snb = sb * c1b + cb * s1b, cnb = cb * c1b - sb * s1b;
            sa = sna, ca = cna, sb = snb, cb = cnb;
            cv::v_store(out[2 * o] + x, cv::v_cvt_f32(sa, sb));
            cv::v_store(out[2 * o + 1] + x, cv::v_cvt_f32(ca, cb));
          }
        }
#endif
        for (; x < x1; ++x) {
          double s1, c1;
          SinCos(static_cast<double>(steps) * p[x], &s1, &c1);
          out[0][x] = static_cast<float>(s1);
          out[1][x] = static_cast<float>(c1);
          double s = s1, c = c1;
          for (int o = 1; o < orders; ++o) {
            const double sn = s * c1 + c * s1, cn = c * c1 - s * s1;
            s = sn;
            c = cn;
            out[2 * o][x] = static_cast<float>(s);
            out[2 * o + 1][x] = static_cast<float>(c);
          }
        }
        x0 = x1;
      }
    }
  });
  tbb::parallel_for(0, nb, [&](int i) {
    cv::boxFilter((*basis)[i](st.Rows(wrapped.cols)), (*bsum)[i], CV_32F, cv::Size(w, w), cv::Point(-1, -1), false,
                  cv::BORDER_CONSTANT);
  });
}

// One row's contribution to the normal equations: the pixels whose whole window is valid
// (den >= full) and whose high-pass is below `outlier`, each with the design row
// (1, basis_i - window mean of basis_i); with `design` false only the sum of squares and count.
// The row is summed in local accumulators (a fixed term count lets them live in registers) and
// added to `nk` once: the order of the additions differs from pixel-by-pixel accumulation into
// `nk` only by rounding, which the parallel reduction's own grouping varies anyway.
template <int kTerms>
void AccumulateRow(const double* h, const float* d, const uchar* m, const float* const* basis, const float* const* bsum,
                   int width, int terms_runtime, float full, double outlier, bool design, Normal* nk) {
  const int terms = kTerms > 0 ? kTerms : terms_runtime;
  double ata[kMaxTerms * (kMaxTerms + 1) / 2] = {}, atb[kMaxTerms] = {}, ss = 0;
  long used = 0;
  double row[kMaxTerms];
  row[0] = 1.0;
  for (int x = 0; x < width; ++x) {
    if (!m[x] || d[x] < full || !(std::abs(h[x]) < outlier)) continue;
    ss += h[x] * h[x];
    ++used;
    if (!design) continue;
    const double inv = 1.0 / std::max(static_cast<double>(d[x]), 1e-6);
    for (int i = 1; i < terms; ++i) row[i] = basis[i - 1][x] - bsum[i - 1][x] * inv;
    int k = 0;
    for (int i = 0; i < terms; ++i) {
      for (int j = 0; j <= i; ++j) ata[k++] += row[i] * row[j];
      atb[i] += row[i] * h[x];
    }
  }
  int k = 0;
  for (int i = 0; i < terms; ++i) {
    for (int j = 0; j <= i; ++j) nk->ata[i][j] += ata[k++];
    nk->atb[i] += atb[i];
  }
  nk->ss += ss;
  nk->used += used;
}

// The strips of rows the fit runs over (detail::RippleFitRows cut into strips of about
// `strip_rows` rows; a 70-row range is one strip, not 64 rows and 6 rows that would each compute
// the 2 * half rows of margin).
std::vector<Strip> MakeStrips(int box_height, int subsample, int strip_rows, int half) {
  std::vector<Strip> strips;
  for (const auto& [from, to] : detail::RippleFitRows(box_height, subsample)) {
    const int count = std::max(1, static_cast<int>(std::lround(static_cast<double>(to - from) / strip_rows)));
    const int rows = (to - from + count - 1) / count;
    for (int y0 = from; y0 < to; y0 += rows) {
      Strip st;
      st.y0 = y0;
      st.y1 = std::min(to, y0 + rows);
      st.a = std::max(0, y0 - half);
      st.b = std::min(box_height, st.y1 + half);
      strips.push_back(st);
    }
  }
  return strips;
}

// The strip buffers, reused from strip to strip by each thread.
struct StripBuffers {
  cv::Mat mf, den, clean, hp;
  std::vector<cv::Mat> basis, bsum;
};

// Normal equations over the pixels whose whole window is valid and whose high-pass is small, per
// band of rows (the ripple's jackknife test, detail::RippleBand), with the ripple basis of orders
// 1..`orders`. With `design` false only the sum of squares and the count.
// The strips run side by side (OpenCV runs each box filter on one thread: one strip's filters side
// by side left a core idle), each strip's rows reduced in a fixed grouping
// (parallel_deterministic_reduce), and the strips' sums added in strip order: the same sums on
// every run and any number of threads.
struct RippleSweep {
  const cv::Mat& abs_phase;
  const cv::Mat& wrapped;
  const cv::Mat& mask;
  int steps, w;
  float full;
  double outlier_rad;
  std::vector<Strip> strips;
  tbb::enumerable_thread_specific<StripBuffers> buffers;

  std::vector<Normal> operator()(bool design, int orders) {
    const int nbo = 2 * orders, to = nbo + 1;
    std::vector<std::vector<Normal>> per_strip(strips.size());
    tbb::parallel_for(std::size_t{0}, strips.size(), [&](std::size_t si) {
      const Strip& st = strips[si];
      StripBuffers& b = buffers.local();
      StripDen(mask, st, w, &b.mf, &b.den);
      StripPhaseSums(abs_phase, mask, st, w, &b.clean, &b.hp);
      if (design) StripBasis(wrapped, mask, steps, orders, st, w, &b.basis, &b.bsum);
      StripHighPass(abs_phase.cols, b.den, st, b.clean, &b.hp);
      // Row by row; each row adds to its own band (rows of one band are contiguous).
      per_strip[si] = tbb::parallel_deterministic_reduce(
          tbb::blocked_range<int>(st.y0, st.y1, 8), std::vector<Normal>(detail::kRippleBands),
          [&](const tbb::blocked_range<int>& r, std::vector<Normal> acc) {
            const float* bp[kMaxTerms] = {};
            const float* bs[kMaxTerms] = {};
            for (int y = r.begin(); y < r.end(); ++y) {
              Normal& nk = acc[detail::RippleBand(y, mask.rows)];
              const double* h = b.hp.ptr<double>(y - st.y0);
              const float* d = b.den.ptr<float>(y - st.y0);
              const uchar* m = mask.ptr<uchar>(y);
              if (design)
                for (int i = 0; i < nbo; ++i) {
                  bp[i] = b.basis[i].ptr<float>(y - st.a);
                  bs[i] = b.bsum[i].ptr<float>(y - st.y0);
                }
              if (to == 7)  // the default three orders
                AccumulateRow<7>(h, d, m, bp, bs, mask.cols, to, full, outlier_rad, design, &nk);
              else if (to == 3)  // the first order (the significance test)
                AccumulateRow<3>(h, d, m, bp, bs, mask.cols, to, full, outlier_rad, design, &nk);
              else
                AccumulateRow<0>(h, d, m, bp, bs, mask.cols, to, full, outlier_rad, design, &nk);
            }
            return acc;
          },
          [&](std::vector<Normal> a, const std::vector<Normal>& c) {
            for (int k = 0; k < detail::kRippleBands; ++k) a[k].Add(c[k], to);
            return a;
          },
          tbb::simple_partitioner());
    });
    std::vector<Normal> bands(detail::kRippleBands);
    for (const std::vector<Normal>& rows : per_strip)
      for (int k = 0; k < detail::kRippleBands; ++k) bands[k].Add(rows[k], to);
    return bands;
  }
};

// The jackknife statistic of the first-order ripple over the bands' normal equations
// (detail::FirstOrderRippleT2 on Eigen matrices).
double BandsRippleT2(const std::vector<Normal>& bands, int to) {
  std::vector<Eigen::MatrixXd> band_ata(bands.size());
  std::vector<Eigen::VectorXd> band_atb(bands.size());
  for (std::size_t k = 0; k < bands.size(); ++k) bands[k].ToEigen(to, &band_ata[k], &band_atb[k]);
  return detail::FirstOrderRippleT2(band_ata, band_atb);
}

// Subtracts the fitted ripple from the phase (the basis again: one sincos per pixel).
void SubtractRipple(const Eigen::VectorXd& coef, int orders, int steps, const cv::Mat& wrapped, const cv::Mat& mask,
                    cv::Mat& abs_phase) {
  tbb::parallel_for(tbb::blocked_range<int>(0, mask.rows, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      float* p = abs_phase.ptr<float>(y);
      const float* wr = wrapped.ptr<float>(y);
      const uchar* m = mask.ptr<uchar>(y);
      for (int x = 0; x < mask.cols; ++x) {
        if (!m[x]) continue;
        double s1, c1;
        SinCos(static_cast<double>(steps) * wr[x], &s1, &c1);
        double s = s1, c = c1, ripple = 0;
        for (int o = 0; o < orders; ++o) {
          // As float, as the stored basis the reference and the fit use.
          ripple += coef[1 + 2 * o] * static_cast<float>(s) + coef[2 + 2 * o] * static_cast<float>(c);
          const double sn = s * c1 + c * s1, cn = c * c1 - s * s1;
          s = sn;
          c = cn;
        }
        p[x] = static_cast<float>(p[x] - ripple);
      }
    }
  });
}

// The window of the ripple fit: options.window_px, or twice the camera fringe period (odd, 7..101)
// measured on the mask's box; 0 if there is no fringe to measure.
int RippleWindow(const cv::Mat& abs_phase_full, const cv::Mat& mask_full, const cv::Rect& box,
                 const NonlinearityOptions& options) {
  if (options.window_px != 0) return options.window_px;
  if (box.empty()) return 0;
  // The reference samples the period on even rows and columns: start the view on even ones.
  const cv::Rect even(box.x & ~1, box.y & ~1, box.br().x - (box.x & ~1), box.br().y - (box.y & ~1));
  const double period = detail::CameraFringePeriod(abs_phase_full(even), mask_full(even));
  if (!(period > 0)) return 0;
  return std::clamp(static_cast<int>(std::lround(2 * period)) | 1, 7, 101);
}

}  // namespace

NonlinearityEstimate CorrectPhaseNonlinearity(cv::Mat& abs_phase_full, const cv::Mat& wrapped_full,
                                              const cv::Mat& mask_full, int steps, const NonlinearityOptions& options) {
  ThrowIfInvalid(options.Validate(), "NonlinearityOptions");
  NonlinearityEstimate est;
  est.steps = steps;
  est.sin_rad.assign(options.orders, 0.0);
  est.cos_rad.assign(options.orders, 0.0);
  const cv::Rect box = cv::boundingRect(mask_full);
  const int w = RippleWindow(abs_phase_full, mask_full, box, options);
  if (w == 0) return est;
  est.window_px = w;
  if (box.empty()) {
    est.passes = 1;
    return est;
  }
  // Outside the box the mask is zero, as the reference's zero border: same window sums inside.
  cv::Mat abs_phase = abs_phase_full(box);
  const cv::Mat wrapped = wrapped_full(box), mask = mask_full(box);
  const int nb = 2 * options.orders, terms = nb + 1;
  const int half = w / 2;
  // Each strip recomputes the basis and window sums of the `half` rows on either side, so taller
  // strips waste less (w = 55 on the SLMaster set: 64-row strips compute 1.8x the rows, 256-row
  // ones 1.2x, ~20 % faster). The height is bounded by ~24 MB of strip buffers (basis and its sums
  // as float, the phase and its high-pass as double, mask and counts as float).
  const double strip_row_bytes = static_cast<double>(box.width) * (8.0 * nb + 24.0);
  const int strip_rows = std::clamp(static_cast<int>(24e6 / strip_row_bytes) - 2 * half, 64, 512);
  // The rows of the fit (NonlinearityOptions::row_subsample): all, or 1/k of each band's rows.
  const int subsample =
      detail::RippleRowSubsample(cv::countNonZero(mask), options.row_subsample, options.row_subsample_min_pixels);
  est.row_subsample = subsample;
  RippleSweep sweep{abs_phase,
                    wrapped,
                    mask,
                    steps,
                    w,
                    static_cast<float>(w * w - 0.5),
                    options.outlier_rad,
                    MakeStrips(box.height, subsample, strip_rows, half),
                    tbb::enumerable_thread_specific<StripBuffers>([&] {
                      StripBuffers b;
                      b.basis.resize(nb);
                      b.bsum.resize(nb);
                      return b;
                    })};

  // The significance test first, on a first-order fit (detail::FirstOrderRippleGate): without a
  // significant ripple (a 12-step set, a linear projector) the higher orders are never fitted.
  if (detail::FirstOrderRippleGate(options)) {
    const std::vector<Normal> bands = sweep(true, 1);
    Normal ne;
    for (const Normal& nk : bands) ne.Add(nk, 3);
    est.pixels_used = ne.used;
    est.passes = 1;
    if (ne.used < options.min_pixels) return detail::FinishRippleEstimate(&est);
    est.residual_rms_before_rad = std::sqrt(ne.ss / ne.used);
    est.ripple_t2 = BandsRippleT2(bands, 3);
    if (!(est.ripple_t2 >= options.min_ripple_t2)) {
      const Eigen::VectorXd coef = ne.Solve(3);
      est.sin_rad[0] = coef[1];
      est.cos_rad[0] = coef[2];
      return detail::FinishRippleEstimate(&est);
    }
  }

  for (int pass = 0; pass < options.passes; ++pass) {
    const std::vector<Normal> bands = sweep(true, options.orders);
    Normal ne;
    for (const Normal& nk : bands) ne.Add(nk, terms);
    est.pixels_used = ne.used;
    est.passes = pass + 1;
    if (ne.used < options.min_pixels) break;
    if (pass == 0) est.residual_rms_before_rad = std::sqrt(ne.ss / ne.used);
    const Eigen::VectorXd coef = ne.Solve(terms);
    for (int o = 0; o < options.orders; ++o) {
      est.sin_rad[o] += coef[1 + 2 * o];
      est.cos_rad[o] += coef[2 + 2 * o];
    }
    if (pass == 0) {
      est.ripple_t2 = BandsRippleT2(bands, terms);
      if (options.min_ripple_t2 > 0 && !(est.ripple_t2 >= options.min_ripple_t2)) break;  // not significant
    }
    SubtractRipple(coef, options.orders, steps, wrapped, mask, abs_phase);
    est.applied = true;
  }
  if (est.applied) {
    Normal after;
    for (const Normal& nk : sweep(false, options.orders)) after.Add(nk, terms);
    est.residual_rms_after_rad = after.used ? std::sqrt(after.ss / after.used) : 0;
  }
  return detail::FinishRippleEstimate(&est);
}

}  // namespace ramtk::vision
