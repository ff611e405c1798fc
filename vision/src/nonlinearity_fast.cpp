// The same ripple estimator as CorrectPhaseNonlinearity (nonlinearity.cpp), organised for speed:
// only the bounding box of the mask is processed (every pixel the fit uses has its whole window
// inside it), the basis functions are evaluated at valid pixels only (one sincos, the higher
// orders by angle addition) and stored as float, the box filters of the basis run in parallel,
// and the normal equations are accumulated per row in parallel without per-pixel allocation.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "nonlinearity_internal.h"
#include "ramtk/vision/nonlinearity.h"

namespace ramtk::vision {
namespace {

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
};

// High-passed phase at every pixel (CV_64F): clean - box(clean) / den, with clean = the phase
// where the mask is set and 0 elsewhere. Computed in place in the window sum (no extra image).
cv::Mat HighPass(const cv::Mat& phase, const cv::Mat& mask, const cv::Mat& den, int w) {
  cv::Mat clean(phase.size(), CV_64F);
  tbb::parallel_for(tbb::blocked_range<int>(0, phase.rows, 32), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* p = phase.ptr<float>(y);
      const uchar* m = mask.ptr<uchar>(y);
      double* c = clean.ptr<double>(y);
      for (int x = 0; x < phase.cols; ++x) c[x] = m[x] ? static_cast<double>(p[x]) : 0.0;
    }
  });
  cv::Mat hp;
  cv::boxFilter(clean, hp, CV_64F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  tbb::parallel_for(tbb::blocked_range<int>(0, phase.rows, 32), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const double* c = clean.ptr<double>(y);
      const float* d = den.ptr<float>(y);
      double* h = hp.ptr<double>(y);
      for (int x = 0; x < phase.cols; ++x) h[x] = c[x] - h[x] / std::max(static_cast<double>(d[x]), 1e-6);
    }
  });
  return hp;
}

}  // namespace

NonlinearityEstimate CorrectPhaseNonlinearityFast(cv::Mat& abs_phase_full, const cv::Mat& wrapped_full,
                                                  const cv::Mat& mask_full, int steps,
                                                  const NonlinearityOptions& options) {
  options.Validate();
  NonlinearityEstimate est;
  est.steps = steps;
  est.sin_rad.assign(options.orders, 0.0);
  est.cos_rad.assign(options.orders, 0.0);
  const cv::Rect box = cv::boundingRect(mask_full);
  int w = options.window_px;
  if (w == 0) {
    if (box.empty()) return est;
    // The reference samples the period on even rows and columns: start the view on even ones.
    const cv::Rect even(box.x & ~1, box.y & ~1, box.br().x - (box.x & ~1), box.br().y - (box.y & ~1));
    const double period = detail::CameraFringePeriod(abs_phase_full(even), mask_full(even));
    if (!(period > 0)) return est;
    w = std::clamp(static_cast<int>(std::lround(2 * period)) | 1, 7, 101);
  }
  est.window_px = w;
  if (box.empty()) {
    est.passes = 1;
    return est;
  }
  // Outside the box the mask is zero, as the reference's zero border: same window sums inside.
  cv::Mat abs_phase = abs_phase_full(box);
  const cv::Mat wrapped = wrapped_full(box), mask = mask_full(box);
  const int nb = 2 * options.orders, terms = nb + 1;
  cv::Mat mf;
  mask.convertTo(mf, CV_32F, 1.0 / 255.0);
  cv::Mat den;  // valid pixels per window (exact integers in float)
  cv::boxFilter(mf, den, CV_32F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  const float full = static_cast<float>(w * w - 0.5);
  std::vector<cv::Mat> basis(nb), bsum(nb);
  for (cv::Mat& b : basis) b = cv::Mat::zeros(box.size(), CV_32F);
  tbb::parallel_for(tbb::blocked_range<int>(0, box.height, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* p = wrapped.ptr<float>(y);
      const uchar* m = mask.ptr<uchar>(y);
      for (int x = 0; x < box.width; ++x) {
        if (!m[x]) continue;
        const double a = static_cast<double>(steps) * p[x];
        const double s1 = std::sin(a), c1 = std::cos(a);
        double s = s1, c = c1;
        for (int o = 0; o < options.orders; ++o) {
          basis[2 * o].ptr<float>(y)[x] = static_cast<float>(s);
          basis[2 * o + 1].ptr<float>(y)[x] = static_cast<float>(c);
          const double sn = s * c1 + c * s1, cn = c * c1 - s * s1;
          s = sn;
          c = cn;
        }
      }
    }
  });
  tbb::parallel_for(0, nb, [&](int i) {
    cv::boxFilter(basis[i], bsum[i], CV_32F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  });

  // Normal equations over the pixels whose whole window is valid and whose high-pass is small.
  auto accumulate = [&](const cv::Mat& hp, bool design, int y_begin, int y_end) {
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(y_begin, y_end, 16), Normal{},
        [&](const tbb::blocked_range<int>& r, Normal acc) {
          double row[kMaxTerms];
          for (int y = r.begin(); y < r.end(); ++y) {
            const double* h = hp.ptr<double>(y);
            const float* d = den.ptr<float>(y);
            const uchar* m = mask.ptr<uchar>(y);
            for (int x = 0; x < box.width; ++x) {
              if (!m[x] || d[x] < full || !(std::abs(h[x]) < options.outlier_rad)) continue;
              acc.ss += h[x] * h[x];
              ++acc.used;
              if (!design) continue;
              row[0] = 1.0;
              const double inv = 1.0 / std::max(static_cast<double>(d[x]), 1e-6);
              for (int i = 0; i < nb; ++i)
                row[i + 1] = basis[i].ptr<float>(y)[x] - bsum[i].ptr<float>(y)[x] * inv;
              for (int i = 0; i < terms; ++i) {
                for (int j = 0; j <= i; ++j) acc.ata[i][j] += row[i] * row[j];
                acc.atb[i] += row[i] * h[x];
              }
            }
          }
          return acc;
        },
        [&](Normal a, const Normal& b) {
          a.Add(b, terms);
          return a;
        });
  };

  for (int pass = 0; pass < options.passes; ++pass) {
    const cv::Mat hp = HighPass(abs_phase, mask, den, w);
    // Per band of rows on the first pass (the ripple's jackknife test), else in one go.
    Normal ne;
    std::vector<Eigen::MatrixXd> band_ata;
    std::vector<Eigen::VectorXd> band_atb;
    if (pass == 0) {
      int y0 = 0;
      for (int k = 0; k < detail::kRippleBands; ++k) {
        int y1 = y0;
        while (y1 < box.height && detail::RippleBand(y1, box.height) == k) ++y1;
        const Normal nk = accumulate(hp, true, y0, y1);
        ne.Add(nk, terms);
        Eigen::MatrixXd a(terms, terms);
        Eigen::VectorXd b(terms);
        for (int i = 0; i < terms; ++i) {
          for (int j = 0; j <= i; ++j) a(i, j) = a(j, i) = nk.ata[i][j];
          b[i] = nk.atb[i];
        }
        band_ata.push_back(a);
        band_atb.push_back(b);
        y0 = y1;
      }
    } else {
      ne = accumulate(hp, true, 0, box.height);
    }
    est.pixels_used = ne.used;
    est.passes = pass + 1;
    if (ne.used < options.min_pixels) break;
    if (pass == 0) est.residual_rms_before_rad = std::sqrt(ne.ss / ne.used);
    Eigen::MatrixXd ata(terms, terms);
    Eigen::VectorXd atb(terms);
    for (int i = 0; i < terms; ++i) {
      for (int j = 0; j <= i; ++j) ata(i, j) = ata(j, i) = ne.ata[i][j];
      atb[i] = ne.atb[i];
    }
    const Eigen::VectorXd coef = ata.ldlt().solve(atb);
    for (int o = 0; o < options.orders; ++o) {
      est.sin_rad[o] += coef[1 + 2 * o];
      est.cos_rad[o] += coef[2 + 2 * o];
    }
    if (pass == 0) {
      est.ripple_t2 = detail::FirstOrderRippleT2(band_ata, band_atb);
      if (options.min_ripple_t2 > 0 && !(est.ripple_t2 >= options.min_ripple_t2)) break;  // not significant
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, box.height, 16), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y) {
        float* p = abs_phase.ptr<float>(y);
        const uchar* m = mask.ptr<uchar>(y);
        for (int x = 0; x < box.width; ++x) {
          if (!m[x]) continue;
          double ripple = 0;
          for (int i = 0; i < nb; ++i) ripple += coef[1 + i] * basis[i].ptr<float>(y)[x];
          p[x] = static_cast<float>(p[x] - ripple);
        }
      }
    });
    est.applied = true;
  }
  if (est.applied) {
    const Normal after = accumulate(HighPass(abs_phase, mask, den, w), false, 0, box.height);
    est.residual_rms_after_rad = after.used ? std::sqrt(after.ss / after.used) : 0;
  }
  double r2 = 0;
  for (int o = 0; o < options.orders; ++o) r2 += est.sin_rad[o] * est.sin_rad[o] + est.cos_rad[o] * est.cos_rad[o];
  est.ripple_rms_rad = std::sqrt(r2 / 2);
  est.equivalent_gamma = EquivalentGamma(est.sin_rad[0], steps);
  return est;
}

}  // namespace ramtk::vision
