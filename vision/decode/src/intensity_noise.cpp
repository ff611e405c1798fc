// Random part of the intensity noise from neighbouring pixels' fit residuals (decode_internal.h).
#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/kernels/rank_select.h"

namespace ramtk::vision::detail {
namespace {

using Vec2 = Eigen::Vector2d;

// The fitted (cos, sin) amplitudes of the 3-parameter sinusoid fit (steps 2 pi k / N) of the
// samples v[0..n), whose angle is the phase, and their mean.
void Fit(const double* v, int n, const double* c, const double* s, double* a0, Vec2* phase) {
  double sum = 0, sc = 0, ss = 0;
  for (int k = 0; k < n; ++k) {
    sum += v[k];
    sc += v[k] * c[k];
    ss += v[k] * s[k];
  }
  *a0 = sum / n;
  *phase = Vec2(2 * sc / n, 2 * ss / n);
}

// The fit's residual vector: r[k] = v[k] - (a0 + a c[k] + b s[k]).
void Residual(const double* v, int n, const double* c, const double* s, double a0, const Vec2& phase, double* r) {
  for (int k = 0; k < n; ++k) r[k] = v[k] - (a0 + phase.x() * c[k] + phase.y() * s[k]);
}

// Four sampled pixels' triples at once on AVX2 lanes (Estimate's pixel loop, its operations in
// its order): per lane j and step k, dd^2 into dd2[j * n + k] and r0^2 into r2[j * n + k]. The
// fits of both neighbour pairs are taken; each lane uses the pair Estimate would (flags h, v).
constexpr int kMaxLaneSteps = 32;

// cos_between on four lanes: u.v / sqrt(|u|^2 |v|^2), Eigen's sums of two terms.
RAMTK_AVX2_INLINE __m256d CosBetween4(__m256d ux, __m256d uy, __m256d vx, __m256d vy) {
  const __m256d dot = _mm256_add_pd(_mm256_mul_pd(ux, vx), _mm256_mul_pd(uy, vy));
  const __m256d nu = _mm256_add_pd(_mm256_mul_pd(ux, ux), _mm256_mul_pd(uy, uy));
  const __m256d nv = _mm256_add_pd(_mm256_mul_pd(vx, vx), _mm256_mul_pd(vy, vy));
  return _mm256_div_pd(dot, _mm256_sqrt_pd(_mm256_mul_pd(nu, nv)));
}

// Residual on four lanes at one step: v - (a0 + a c + b s).
RAMTK_AVX2_INLINE __m256d Residual4(__m256d v, __m256d a0, __m256d a, __m256d b, __m256d c, __m256d s) {
  return _mm256_sub_pd(v, _mm256_add_pd(_mm256_add_pd(a0, _mm256_mul_pd(a, c)), _mm256_mul_pd(b, s)));
}
template <typename T>
RAMTK_AVX2 void FourTriples(const T* const* up, const T* const* mid, const T* const* down, int n, const double* c,
                            const double* s, const int* xs, const bool* h, const bool* v, double* dd2, double* r2) {
  __m256d val[5][kMaxLaneSteps];  // the pixel, left, right, above, below
  for (int k = 0; k < n; ++k) {
    const T *m = mid[k], *u = up[k], *d = down[k];
    val[0][k] = _mm256_setr_pd(m[xs[0]], m[xs[1]], m[xs[2]], m[xs[3]]);
    val[1][k] = _mm256_setr_pd(m[xs[0] - 1], m[xs[1] - 1], m[xs[2] - 1], m[xs[3] - 1]);
    val[2][k] = _mm256_setr_pd(m[xs[0] + 1], m[xs[1] + 1], m[xs[2] + 1], m[xs[3] + 1]);
    val[3][k] = _mm256_setr_pd(u[xs[0]], u[xs[1]], u[xs[2]], u[xs[3]]);
    val[4][k] = _mm256_setr_pd(d[xs[0]], d[xs[1]], d[xs[2]], d[xs[3]]);
  }
  // Fit: the sums in step order, then a0 = sum / n and the phase (2 sc / n, 2 ss / n).
  const __m256d nn = _mm256_set1_pd(n), two = _mm256_set1_pd(2.0);
  __m256d a0[5], px[5], py[5];
  for (int q = 0; q < 5; ++q) {
    __m256d sum = _mm256_setzero_pd(), sc = sum, ss = sum;
    for (int k = 0; k < n; ++k) {
      sum = _mm256_add_pd(sum, val[q][k]);
      sc = _mm256_add_pd(sc, _mm256_mul_pd(val[q][k], _mm256_set1_pd(c[k])));
      ss = _mm256_add_pd(ss, _mm256_mul_pd(val[q][k], _mm256_set1_pd(s[k])));
    }
    a0[q] = _mm256_div_pd(sum, nn);
    px[q] = _mm256_div_pd(_mm256_mul_pd(two, sc), nn);
    py[q] = _mm256_div_pd(_mm256_mul_pd(two, ss), nn);
  }
  // cos_between(u, v) = u.v / sqrt(|u|^2 |v|^2) of the left-right and the above-below phases.
  const __m256d ge =
      _mm256_cmp_pd(CosBetween4(px[1], py[1], px[2], py[2]), CosBetween4(px[3], py[3], px[4], py[4]), _CMP_GE_OQ);
  // use_h = h && (!v || cos_ab >= cos_cd), per lane.
  const __m256d hz = _mm256_castsi256_pd(_mm256_setr_epi64x(-h[0], -h[1], -h[2], -h[3]));
  const __m256d vt = _mm256_castsi256_pd(_mm256_setr_epi64x(-v[0], -v[1], -v[2], -v[3]));
  const __m256d use_h =
      _mm256_and_pd(hz, _mm256_or_pd(_mm256_andnot_pd(vt, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))), ge));
  const __m256d a1 = _mm256_blendv_pd(a0[3], a0[1], use_h), a2 = _mm256_blendv_pd(a0[4], a0[2], use_h);
  const __m256d x1 = _mm256_blendv_pd(px[3], px[1], use_h), x2 = _mm256_blendv_pd(px[4], px[2], use_h);
  const __m256d y1 = _mm256_blendv_pd(py[3], py[1], use_h), y2 = _mm256_blendv_pd(py[4], py[2], use_h);
  alignas(32) double dd_k[4], r_k[4];
  for (int k = 0; k < n; ++k) {
    const __m256d ck = _mm256_set1_pd(c[k]), sk = _mm256_set1_pd(s[k]);
    const __m256d r0 = Residual4(val[0][k], a0[0], px[0], py[0], ck, sk);
    const __m256d q1 = Residual4(_mm256_blendv_pd(val[3][k], val[1][k], use_h), a1, x1, y1, ck, sk);
    const __m256d q2 = Residual4(_mm256_blendv_pd(val[4][k], val[2][k], use_h), a2, x2, y2, ck, sk);
    const __m256d dd = _mm256_add_pd(_mm256_sub_pd(q1, _mm256_mul_pd(two, r0)), q2);
    _mm256_store_pd(dd_k, _mm256_mul_pd(dd, dd));
    _mm256_store_pd(r_k, _mm256_mul_pd(r0, r0));
    for (int j = 0; j < 4; ++j) dd2[j * n + k] = dd_k[j], r2[j * n + k] = r_k[j];
  }
}

template <typename T>
IntensityNoise Estimate(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask, int stride) {
  const int n = static_cast<int>(frames.size());
  std::vector<double> c(n), s(n);
  for (int k = 0; k < n; ++k) c[k] = std::cos(2 * CV_PI * k / n), s[k] = std::sin(2 * CV_PI * k / n);
  // Cosine of the phase change between two pixels: the angle between their (a, b) vectors
  // (monotone in the wrapped phase difference |remainder(phase_b - phase_a, 2 pi)|, without atan2).
  auto cos_between = [](const Vec2& u, const Vec2& v) {
    return u.dot(v) / std::sqrt(u.squaredNorm() * v.squaredNorm());
  };
  // Sampled rows in parallel, each with its own sums; added in row order (deterministic).
  struct RowSums {
    double diff_ss = 0, total_ss = 0;
    long triples = 0;
  };
  const int rows = mask.rows > 2 ? (mask.rows - 2 + stride - 1) / stride : 0;
  std::vector<RowSums> per_row(rows);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 4), [&](const tbb::blocked_range<int>& range) {
    // The frames' rows y - 1, y, y + 1 (pointers taken once per row) and, per pixel, the samples
    // of the pixel and its four neighbours; residual vectors only for the pair used.
    std::vector<const T*> up(n), mid(n), down(n);
    std::vector<double> v0(n), va(n), vb(n), vc(n), vd(n), r0(n), q1(n), q2(n);
    const bool lanes = Avx2Kernels() && n <= kMaxLaneSteps;
    double dd2[4 * kMaxLaneSteps], r2[4 * kMaxLaneSteps];
    for (int i = range.begin(); i < range.end(); ++i) {
      const int y = 1 + i * stride;
      RowSums& rs = per_row[i];
      for (int k = 0; k < n; ++k) {
        up[k] = frames[k]->ptr<T>(y - 1);
        mid[k] = frames[k]->ptr<T>(y);
        down[k] = frames[k]->ptr<T>(y + 1);
      }
      const uchar* mu = mask.ptr<uchar>(y - 1);
      const uchar* m0 = mask.ptr<uchar>(y);
      const uchar* md = mask.ptr<uchar>(y + 1);
      // The pixel's triple the scalar way.
      auto one = [&](int x, bool horizontal, bool vertical) {
        double a0, aa = 0, ab = 0, ac = 0, ad = 0;
        Vec2 p0, pa, pb, pc, pd;
        for (int k = 0; k < n; ++k) v0[k] = mid[k][x];
        Fit(v0.data(), n, c.data(), s.data(), &a0, &p0);
        if (horizontal) {
          for (int k = 0; k < n; ++k) va[k] = mid[k][x - 1], vb[k] = mid[k][x + 1];
          Fit(va.data(), n, c.data(), s.data(), &aa, &pa);
          Fit(vb.data(), n, c.data(), s.data(), &ab, &pb);
        }
        if (vertical) {
          for (int k = 0; k < n; ++k) vc[k] = up[k][x], vd[k] = down[k][x];
          Fit(vc.data(), n, c.data(), s.data(), &ac, &pc);
          Fit(vd.data(), n, c.data(), s.data(), &ad, &pd);
        }
        // The direction along the fringe (smaller phase change): there the phase-dependent
        // (systematic) part of the residual, e.g. the projector's harmonics, changes least, and
        // the second difference r(-1) - 2 r(0) + r(+1) cancels its linear change as well.
        const bool use_h = horizontal && (!vertical || cos_between(pa, pb) >= cos_between(pc, pd));
        Residual(v0.data(), n, c.data(), s.data(), a0, p0, r0.data());
        if (use_h) {
          Residual(va.data(), n, c.data(), s.data(), aa, pa, q1.data());
          Residual(vb.data(), n, c.data(), s.data(), ab, pb, q2.data());
        } else {
          Residual(vc.data(), n, c.data(), s.data(), ac, pc, q1.data());
          Residual(vd.data(), n, c.data(), s.data(), ad, pd, q2.data());
        }
        for (int k = 0; k < n; ++k) {
          const double dd = q1[k] - 2 * r0[k] + q2[k];
          rs.diff_ss += dd * dd;
          rs.total_ss += r0[k] * r0[k];
        }
        ++rs.triples;
      };
      // The row's sampled pixels with a neighbour pair, four at a time on AVX2 lanes (the sums
      // taken in the pixels' order), the rest one by one.
      int xs[4];
      bool hs[4], vs[4];
      int queued = 0;
      for (int x = 1; x + 1 < mask.cols; x += stride) {
        if (!m0[x]) continue;
        const bool horizontal = m0[x - 1] && m0[x + 1], vertical = mu[x] && md[x];
        if (!horizontal && !vertical) continue;
        if (!lanes) {
          one(x, horizontal, vertical);
          continue;
        }
        xs[queued] = x, hs[queued] = horizontal, vs[queued] = vertical;
        if (++queued < 4) continue;
        queued = 0;
        FourTriples<T>(up.data(), mid.data(), down.data(), n, c.data(), s.data(), xs, hs, vs, dd2, r2);
        for (int j = 0; j < 4; ++j) {
          for (int k = 0; k < n; ++k) {
            rs.diff_ss += dd2[j * n + k];
            rs.total_ss += r2[j * n + k];
          }
          ++rs.triples;
        }
      }
      for (int j = 0; j < queued; ++j) one(xs[j], hs[j], vs[j]);
    }
  });
  double diff_ss = 0, total_ss = 0;
  long triples = 0;
  for (const RowSums& rs : per_row) {
    diff_ss += rs.diff_ss;
    total_ss += rs.total_ss;
    triples += rs.triples;
  }
  IntensityNoise out;
  out.pairs = triples;
  if (triples > 0 && n > 3) {
    // A residual vector spans N - 3 degrees of freedom: E|r|^2 = (N - 3) sigma^2, and for three
    // pixels with independent noise E|r_a - 2 r_0 + r_b|^2 = (1 + 4 + 1) (N - 3) sigma^2.
    out.random_dn = std::sqrt(diff_ss / (6.0 * triples * (n - 3)));
    out.total_dn = std::sqrt(total_ss / (static_cast<double>(triples) * (n - 3)));
  }
  return out;
}

}  // namespace

IntensityNoise EstimateIntensityNoise(const std::vector<const cv::Mat*>& frames, const cv::Mat& mask, int stride) {
  if (frames.size() < 4 || frames[0]->empty()) return {};
  stride = std::max(1, stride);
  switch (frames[0]->depth()) {
    case CV_8U:
      return Estimate<uchar>(frames, mask, stride);
    case CV_16U:
      return Estimate<ushort>(frames, mask, stride);
    default:
      return Estimate<float>(frames, mask, stride);
  }
}

void ChooseIntensitySigma(const DecodeOptions& options, const std::vector<const cv::Mat*>& frames, const cv::Mat& mask,
                          int n, long valid, DecodeSummary* sum) {
  if (options.intensity_sigma_dn > 0) {
    sum->sigma_intensity_dn = options.intensity_sigma_dn;
    return;
  }
  if (n <= 3 || valid <= 0) {
    sum->sigma_intensity_dn = 1.0 / std::sqrt(12.0);
    RAMTK_LOG(kWarning) << "3-step set and no intensity noise given: sigma_phi uses quantisation noise only";
    return;
  }
  sum->sigma_intensity_dn = sum->fit_residual_rms_dn;
  if (!options.noise_from_neighbours) return;
  const IntensityNoise noise =
      EstimateIntensityNoise(frames, mask, EstimateStride(options.noise_stride, valid, options.estimate_max_samples));
  constexpr long kMinPairs = 200;  // the estimate's relative error is ~1 / sqrt(2 pairs (N - 3))
  if (noise.pairs < kMinPairs || !(noise.random_dn > 0)) {
    RAMTK_LOG(kInfo) << "intensity noise: " << noise.pairs
                     << " neighbour pairs, too few for the random part; sigma_I = the whole fit residual";
    return;
  }
  // The random part cannot exceed the residual; quantisation alone is a floor.
  const double random =
      std::clamp(noise.random_dn, 1.0 / std::sqrt(12.0), std::max(noise.total_dn, 1.0 / std::sqrt(12.0)));
  sum->sigma_intensity_random_dn = random;
  sum->sigma_intensity_systematic_dn = std::sqrt(std::max(0.0, noise.total_dn * noise.total_dn - random * random));
  sum->sigma_intensity_dn = random;
}

double PhaseRipple(const DecodeOptions& options, const cv::Mat& coordinate, const cv::Mat& mask, int n,
                   double period_px, long valid) {
  if (!options.noise_from_neighbours || options.intensity_sigma_dn > 0 || n <= 3) return 0;
  return EstimatePhaseRipple(coordinate, mask, period_px,
                             EstimateStride(options.noise_stride, valid, options.estimate_max_samples));
}

int EstimateStride(int stride, long valid, long max_samples) {
  stride = std::max(1, stride);
  if (max_samples <= 0 || valid <= 0) return stride;
  const int by_count = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(valid) / max_samples)));
  return std::max(stride, by_count);
}

double EstimatePhaseRipple(const cv::Mat& coordinate, const cv::Mat& mask, double period_px, int stride) {
  // Second differences of the phase (rad) along rows and along columns, 3 valid pixels each,
  // per sampled row in parallel; the gradient sums are added in row order.
  const double to_rad = 2 * CV_PI / period_px;
  stride = std::max(1, stride);
  const int rows = mask.rows > 2 ? (mask.rows - 2 + stride - 1) / stride : 0;
  struct Row {
    std::vector<float> along_x, along_y;
    double grad_x = 0, grad_y = 0;
  };
  std::vector<Row> per_row(static_cast<std::size_t>(rows));
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 8), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i < range.end(); ++i) {
      const int y = 1 + i * stride;
      Row& row = per_row[i];
      const uchar* mu = mask.ptr<uchar>(y - 1);
      const uchar* m0 = mask.ptr<uchar>(y);
      const uchar* md = mask.ptr<uchar>(y + 1);
      const float* cu = coordinate.ptr<float>(y - 1);
      const float* c0 = coordinate.ptr<float>(y);
      const float* cd = coordinate.ptr<float>(y + 1);
      for (int x = 1; x + 1 < mask.cols; x += stride) {
        if (!m0[x]) continue;
        if (m0[x - 1] && m0[x + 1]) {
          row.along_x.push_back(static_cast<float>(to_rad * (c0[x - 1] - 2.0 * c0[x] + c0[x + 1])));
          row.grad_x += std::abs(c0[x + 1] - c0[x - 1]);
        }
        if (mu[x] && md[x]) {
          row.along_y.push_back(static_cast<float>(to_rad * (cu[x] - 2.0 * c0[x] + cd[x])));
          row.grad_y += std::abs(cd[x] - cu[x]);
        }
      }
    }
  });
  std::vector<float> along_x, along_y;
  double grad_x = 0, grad_y = 0;
  for (const Row& row : per_row) {
    along_x.insert(along_x.end(), row.along_x.begin(), row.along_x.end());
    along_y.insert(along_y.end(), row.along_y.begin(), row.along_y.end());
    grad_x += row.grad_x;
    grad_y += row.grad_y;
  }
  if (along_x.size() < 200 || along_y.size() < 200) return 0;
  // Robust variances (MAD): occlusion edges and code-edge errors are outliers. The median of
  // the magnitudes by histogram select (rank_select.h: the element nth_element would give).
  auto robust_var = [](std::vector<float>& v) {
    for (float& e : v) e = std::abs(e);
    const double mad = 1.4826 * ValuesAtRanks(v, {v.size() / 2})[0];
    return mad * mad;
  };
  const bool fringes_vertical = grad_x / along_x.size() >= grad_y / along_y.size();  // phase changes along x
  const double across = robust_var(fringes_vertical ? along_x : along_y);
  const double along = robust_var(fringes_vertical ? along_y : along_x);
  // Pixel-independent noise gives both directions 6 sigma^2; a phase-dependent ripple (the
  // projector's harmonics left after the nonlinearity correction) varies across the fringes
  // only. Its excess, with the same white-noise gain 6, is the ripple's variance.
  return std::sqrt(std::max(0.0, across - along) / 6.0);
}

}  // namespace ramtk::vision::detail
