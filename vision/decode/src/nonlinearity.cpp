// Self-calibrating removal of the phase ripple caused by a non-linear projector response.
#include "ramtk/vision/decode/nonlinearity.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "nonlinearity_internal.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/core/error.h"
#include "ramtk/vision/kernels/rank_select.h"

namespace ramtk::vision {
namespace detail {

// Median camera fringe period (px) from the gradient of the unwrapped phase.
double CameraFringePeriod(const cv::Mat& phase, const cv::Mat& mask) {
  // Gradient magnitudes per sampled row (rows in parallel), then their median by histogram
  // select (rank_select.h: the element nth_element would give).
  const int rows = phase.rows / 2;
  std::vector<std::vector<float>> per_row(static_cast<std::size_t>(rows));
  tbb::parallel_for(0, rows, [&](int i) {
    const int y = 2 * i;
    const float* p = phase.ptr<float>(y);
    const float* pn = phase.ptr<float>(y + 1);
    const uchar* m = mask.ptr<uchar>(y);
    const uchar* mn = mask.ptr<uchar>(y + 1);
    std::vector<float>& g = per_row[i];
    for (int x = 0; x + 1 < phase.cols; x += 2) {
      if (!m[x] || !m[x + 1] || !mn[x]) continue;
      const double gx = p[x + 1] - p[x], gy = pn[x] - p[x];
      const double gm = std::sqrt(gx * gx + gy * gy);  // no overflow to guard against (hypot: 5x the time)
      if (gm > 1e-6 && gm < 3.0) g.push_back(static_cast<float>(gm));
    }
  });
  std::size_t count = 0;
  for (const std::vector<float>& r : per_row) count += r.size();
  if (count == 0) return 0;
  return 2 * CV_PI / ValuesAtRanks(per_row, {count / 2})[0];  // the rows' values together, not joined
}

std::vector<std::pair<int, int>> RippleFitRows(int height, int k) {
  if (k <= 1) return {{0, height}};
  std::vector<std::pair<int, int>> ranges;
  auto band_first_row = [height](int b) {
    return static_cast<int>((static_cast<long>(b) * height + kRippleBands - 1) / kRippleBands);
  };
  for (int b = 0; b < kRippleBands; ++b) {
    const int first = band_first_row(b), last = band_first_row(b + 1);
    if (last <= first) continue;
    const int rows = (last - first + k - 1) / k;
    // An even band's block ends where the next (odd) band's begins: the pair is one range.
    const std::pair<int, int> block = b % 2 == 0 ? std::pair(last - rows, last) : std::pair(first, first + rows);
    if (!ranges.empty() && ranges.back().second == block.first)
      ranges.back().second = block.second;
    else
      ranges.push_back(block);
  }
  return ranges;
}

NonlinearityEstimate FinishRippleEstimate(NonlinearityEstimate* est) {
  double r2 = 0;
  for (std::size_t o = 0; o < est->sin_rad.size(); ++o)
    r2 += est->sin_rad[o] * est->sin_rad[o] + est->cos_rad[o] * est->cos_rad[o];
  est->ripple_rms_rad = std::sqrt(r2 / 2);
  // Only a significant ripple has a gamma worth naming (and the search costs ~30 ms once per N).
  est->equivalent_gamma =
      est->applied ? EquivalentGamma(est->sin_rad[0], est->steps) : std::numeric_limits<double>::quiet_NaN();
  return *est;
}

int RippleRowSubsample(long valid, int row_subsample, long min_pixels) {
  const long by_pixels = min_pixels > 0 ? valid / min_pixels : row_subsample;
  return static_cast<int>(std::max(1L, std::min<long>(row_subsample, by_pixels)));
}

double FirstOrderRippleT2(const std::vector<Eigen::MatrixXd>& ata, const std::vector<Eigen::VectorXd>& atb) {
  if (ata.empty()) return 0;
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(ata[0].rows(), ata[0].cols());
  Eigen::VectorXd total_b = Eigen::VectorXd::Zero(atb[0].size());
  int bands = 0;
  for (std::size_t k = 0; k < ata.size(); ++k) {
    total += ata[k];
    total_b += atb[k];
    bands += ata[k](0, 0) > 0;  // entry (0, 0) counts the band's pixels
  }
  if (bands < 4) return 0;
  const Eigen::Vector2d full = total.ldlt().solve(total_b).segment<2>(1);
  std::vector<Eigen::Vector2d> loo;
  for (std::size_t k = 0; k < ata.size(); ++k) {
    if (!(ata[k](0, 0) > 0)) continue;
    const Eigen::VectorXd c = (total - ata[k]).ldlt().solve(total_b - atb[k]);
    if (!c.allFinite()) return 0;
    loo.push_back(c.segment<2>(1));
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& c : loo) mean += c;
  mean /= static_cast<double>(loo.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& c : loo) cov += (c - mean) * (c - mean).transpose();
  const double n = static_cast<double>(loo.size());
  cov *= (n - 1) / n;
  if (!full.allFinite()) return 0;
  // No scatter at all (noise-free data): any non-zero ripple is infinitely significant.
  if (!(cov.determinant() > 0)) return full.squaredNorm() > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  return full.dot(cov.ldlt().solve(full));
}

}  // namespace detail
namespace {
using detail::CameraFringePeriod;

// Masked box mean: (box(v*m) / box(m)).
cv::Mat MaskedMean(const cv::Mat& v, const cv::Mat& mf, const cv::Mat& den, int w) {
  cv::Mat num;
  cv::boxFilter(v.mul(mf), num, CV_64F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::Mat out;
  cv::divide(num, cv::max(den, 1e-6), out);
  return out;
}

}  // namespace

std::string NonlinearityOptions::Validate() const {
  if (orders < 1 || orders > 6) return "orders: expected 1..6";
  if (passes < 1 || passes > 10) return "passes: expected 1..10";
  if (window_px != 0 && (window_px < 3 || window_px % 2 == 0)) return "window_px: expected 0 or an odd number >= 3";
  if (!(outlier_rad > 0)) return "outlier_rad: must be positive";
  if (!(min_ripple_t2 >= 0)) return "min_ripple_t2: must be >= 0";
  if (row_subsample < 1 || row_subsample > 64) return "row_subsample: expected 1..64";
  if (row_subsample_min_pixels < 0) return "row_subsample_min_pixels: must be >= 0";
  return "";
}

std::string NonlinearityEstimate::BriefReport() const {
  std::ostringstream s;
  s << "nonlinearity (N=" << steps << "): " << (applied ? "corrected" : "not corrected") << " (ripple T² " << ripple_t2
    << "), s1 " << (sin_rad.empty() ? 0.0 : sin_rad[0]) << " rad, ripple RMS " << ripple_rms_rad
    << " rad, equivalent gamma " << equivalent_gamma << ", high-pass RMS " << residual_rms_before_rad << " -> "
    << residual_rms_after_rad << " rad over " << pixels_used << " px";
  return s.str();
}

namespace {

// The ripple basis sin((m + 1) N phi), cos((m + 1) N phi) of the wrapped phase, m < orders (CV_64F).
std::vector<cv::Mat> RippleBasisReference(const cv::Mat& wrapped, int steps, int orders) {
  std::vector<cv::Mat> basis(2 * orders);
  for (int m = 0; m < orders; ++m) {
    basis[2 * m].create(wrapped.size(), CV_64F);
    basis[2 * m + 1].create(wrapped.size(), CV_64F);
    for (int y = 0; y < wrapped.rows; ++y) {
      const float* p = wrapped.ptr<float>(y);
      for (int x = 0; x < wrapped.cols; ++x) {
        const double a = (m + 1.0) * steps * p[x];
        basis[2 * m].ptr<double>(y)[x] = std::sin(a);
        basis[2 * m + 1].ptr<double>(y)[x] = std::cos(a);
      }
    }
  }
  return basis;
}

// Subtracts sum_i coef[1 + i] basis[i] from the phase on the mask.
void SubtractRippleReference(const Eigen::VectorXd& coef, const std::vector<cv::Mat>& basis, const cv::Mat& mask,
                             cv::Mat& abs_phase) {
  const int nb = static_cast<int>(basis.size());
  for (int y = 0; y < abs_phase.rows; ++y) {
    float* p = abs_phase.ptr<float>(y);
    const uchar* m = mask.ptr<uchar>(y);
    for (int x = 0; x < abs_phase.cols; ++x) {
      if (!m[x]) continue;
      double ripple = 0;
      for (int i = 0; i < nb; ++i) ripple += coef[1 + i] * basis[i].ptr<double>(y)[x];
      p[x] = static_cast<float>(p[x] - ripple);
    }
  }
}

}  // namespace

NonlinearityEstimate detail::CorrectPhaseNonlinearityReference(cv::Mat& abs_phase, const cv::Mat& wrapped,
                                                               const cv::Mat& mask, int steps,
                                                               const NonlinearityOptions& options) {
  ThrowIfInvalid(options.Validate(), "NonlinearityOptions");
  NonlinearityEstimate est;
  est.steps = steps;
  est.sin_rad.assign(options.orders, 0.0);
  est.cos_rad.assign(options.orders, 0.0);
  int w = options.window_px;
  if (w == 0) {
    const double period = CameraFringePeriod(abs_phase, mask);
    if (!(period > 0)) return est;
    w = std::clamp(static_cast<int>(std::lround(2 * period)) | 1, 7, 101);
  }
  est.window_px = w;
  const int nb = 2 * options.orders;
  cv::Mat mf;
  mask.convertTo(mf, CV_64F, 1.0 / 255.0);
  cv::Mat den;
  cv::boxFilter(mf, den, CV_64F, cv::Size(w, w), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  const double full = w * w - 0.5;  // only windows with every pixel valid
  // Basis functions of the measured phase and their high-passed versions (independent of the pass).
  const std::vector<cv::Mat> basis = RippleBasisReference(wrapped, steps, options.orders);
  std::vector<cv::Mat> hp_basis(nb);
  for (int i = 0; i < nb; ++i) hp_basis[i] = basis[i] - MaskedMean(basis[i], mf, den, w);

  const cv::Rect box = cv::boundingRect(mask);
  const int k =
      detail::RippleRowSubsample(cv::countNonZero(mask), options.row_subsample, options.row_subsample_min_pixels);
  est.row_subsample = k;
  // Rows of the fit: inside the box and in the subsample.
  std::vector<uchar> fit_rows(static_cast<std::size_t>(mask.rows), 0);
  for (const auto& [from, to] : detail::RippleFitRows(box.height, k))
    std::fill(fit_rows.begin() + box.y + from, fit_rows.begin() + box.y + to, uchar(1));
  auto fit_row = [&](int y) { return fit_rows[y] != 0; };
  // The phase's high-pass, the masked phase less its window mean.
  auto high_pass = [&]() {
    cv::Mat clean;
    abs_phase.convertTo(clean, CV_64F);
    clean.setTo(0, mask == 0);
    return cv::Mat(clean - MaskedMean(clean, mf, den, w));
  };
  // The normal equations of the fit with the first `nbf` basis functions over the pixels whose
  // whole window is valid and whose high-pass is small; with `bands` also per band of rows.
  struct Normal {
    Eigen::MatrixXd ata;  // full (symmetric)
    Eigen::VectorXd atb;
    std::vector<Eigen::MatrixXd> band_ata;
    std::vector<Eigen::VectorXd> band_atb;
    double ss = 0;
    long used = 0;
  };
  auto accumulate = [&](const cv::Mat& hp, int nbf, bool bands) {
    Normal ne;
    ne.ata = Eigen::MatrixXd::Zero(nbf + 1, nbf + 1);
    ne.atb = Eigen::VectorXd::Zero(nbf + 1);
    if (bands) {
      ne.band_ata.assign(detail::kRippleBands, Eigen::MatrixXd::Zero(nbf + 1, nbf + 1));
      ne.band_atb.assign(detail::kRippleBands, Eigen::VectorXd::Zero(nbf + 1));
    }
    Eigen::VectorXd row(nbf + 1);
    for (int y = 0; y < hp.rows; ++y) {
      if (!fit_row(y)) continue;
      const double* r = hp.ptr<double>(y);
      const double* d = den.ptr<double>(y);
      const uchar* m = mask.ptr<uchar>(y);
      for (int x = 0; x < hp.cols; ++x) {
        if (!m[x] || d[x] < full || !(std::abs(r[x]) < options.outlier_rad)) continue;
        row[0] = 1.0;
        for (int i = 0; i < nbf; ++i) row[i + 1] = hp_basis[i].ptr<double>(y)[x];
        ne.ata.selfadjointView<Eigen::Lower>().rankUpdate(row);
        ne.atb += row * r[x];
        if (bands) {
          const int band = detail::RippleBand(y - box.y, box.height);
          ne.band_ata[band] += row * row.transpose();
          ne.band_atb[band] += row * r[x];
        }
        ne.ss += r[x] * r[x];
        ++ne.used;
      }
    }
    ne.ata = ne.ata.selfadjointView<Eigen::Lower>();
    return ne;
  };
  // The significance test first, on a first-order fit (detail::FirstOrderRippleGate).
  if (detail::FirstOrderRippleGate(options)) {
    const Normal ne = accumulate(high_pass(), 2, true);
    est.pixels_used = ne.used;
    est.passes = 1;
    if (ne.used < options.min_pixels) return detail::FinishRippleEstimate(&est);
    est.residual_rms_before_rad = std::sqrt(ne.ss / ne.used);
    est.ripple_t2 = detail::FirstOrderRippleT2(ne.band_ata, ne.band_atb);
    if (!(est.ripple_t2 >= options.min_ripple_t2)) {
      const Eigen::VectorXd coef = ne.ata.ldlt().solve(ne.atb);
      est.sin_rad[0] = coef[1];
      est.cos_rad[0] = coef[2];
      return detail::FinishRippleEstimate(&est);
    }
  }
  for (int pass = 0; pass < options.passes; ++pass) {
    const Normal ne = accumulate(high_pass(), nb, pass == 0);
    const long used = ne.used;
    est.pixels_used = used;
    est.passes = pass + 1;
    if (used < options.min_pixels) break;
    if (pass == 0) est.residual_rms_before_rad = std::sqrt(ne.ss / used);
    const Eigen::VectorXd coef = ne.ata.ldlt().solve(ne.atb);
    for (int mo = 0; mo < options.orders; ++mo) {
      est.sin_rad[mo] += coef[1 + 2 * mo];
      est.cos_rad[mo] += coef[2 + 2 * mo];
    }
    if (pass == 0) {
      est.ripple_t2 = detail::FirstOrderRippleT2(ne.band_ata, ne.band_atb);
      if (options.min_ripple_t2 > 0 && !(est.ripple_t2 >= options.min_ripple_t2)) break;  // not significant
    }
    SubtractRippleReference(coef, basis, mask, abs_phase);  // this pass's ripple
    est.applied = true;
  }
  if (est.applied) {
    // Residual after the correction, same pixel selection rule.
    const cv::Mat hp = high_pass();
    double ss = 0;
    long used = 0;
    for (int y = 0; y < hp.rows; ++y) {
      if (!fit_row(y)) continue;
      const double* r = hp.ptr<double>(y);
      const double* d = den.ptr<double>(y);
      const uchar* m = mask.ptr<uchar>(y);
      for (int x = 0; x < hp.cols; ++x)
        if (m[x] && d[x] >= full && std::abs(r[x]) < options.outlier_rad) ss += r[x] * r[x], ++used;
    }
    est.residual_rms_after_rad = used ? std::sqrt(ss / used) : 0;
  }
  return detail::FinishRippleEstimate(&est);
}

std::vector<double> MeasureHarmonicRatios(const std::vector<cv::Mat>& frames, const cv::Mat& mask) {
  const int n = static_cast<int>(frames.size());
  std::vector<double> ratios;
  const int max_h = (n + 1) / 2 - 1;
  if (n < 5 || max_h < 2) return ratios;
  std::vector<double> sum(max_h + 1, 0.0);
  long count = 0;
  for (int y = 0; y < mask.rows; ++y) {
    const uchar* m = mask.ptr<uchar>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (!m[x]) continue;
      std::vector<std::complex<double>> c(max_h + 1);
      for (int k = 0; k < n; ++k) {
        const double v = frames[k].ptr<float>(y)[x];
        for (int h = 1; h <= max_h; ++h) c[h] += v * std::polar(1.0, -2 * CV_PI * h * k / n);
      }
      const double a1 = std::abs(c[1]);
      if (a1 <= 0) continue;
      const std::complex<double> unit = std::conj(c[1]) / a1;  // e^{-i phi}
      std::complex<double> rot = unit;
      for (int h = 2; h <= max_h; ++h) {
        rot *= unit;
        sum[h] += (c[h] * rot).real() / a1;
      }
      ++count;
    }
  }
  for (int h = 2; h <= max_h; ++h) ratios.push_back(count ? sum[h] / count : 0.0);
  return ratios;
}

double SecondHarmonicOfGamma(double gamma) {
  // (0.5 + 0.5 cos t)^g = cos^(2g)(t / 2), whose Fourier coefficients are
  // c_h = C Gamma(2g + 1) / (Gamma(g + h + 1) Gamma(g - h + 1)): the ratio c_2 / c_1 is
  // Gamma(g + 2) Gamma(g) / (Gamma(g + 3) Gamma(g - 1)) = (g - 1) / (g + 2).
  return (gamma - 1.0) / (gamma + 2.0);
}

double GammaFromSecondHarmonic(double r2) {
  // The inverse of (g - 1) / (g + 2) over g in [0.3, 5] (r_2 in [-0.3043, 0.5714]).
  if (!(r2 >= SecondHarmonicOfGamma(0.3) && r2 <= SecondHarmonicOfGamma(5.0)))
    return std::numeric_limits<double>::quiet_NaN();
  return std::clamp((1.0 + 2.0 * r2) / (1.0 - r2), 0.3, 5.0);
}

double RippleOfGamma(double gamma, int steps) {
  // Same regression as the estimator (constant + orders 1..3 of N*phi', phi uniform in the
  // true phase), so the non-uniform density of phi' affects both alike.
  const int samples = 720, orders = 3;
  Eigen::MatrixXd a(samples, 1 + 2 * orders);
  Eigen::VectorXd e(samples);
  for (int i = 0; i < samples; ++i) {
    const double phi = 2 * CV_PI * i / samples;
    double s = 0, c = 0;
    for (int k = 0; k < steps; ++k) {
      const double d = 2 * CV_PI * k / steps;
      const double v = std::pow(0.5 + 0.5 * std::cos(phi + d), gamma);
      s += v * std::sin(d);
      c += v * std::cos(d);
    }
    const double measured = std::atan2(-s, c);
    e[i] = std::remainder(measured - phi, 2 * CV_PI);
    a(i, 0) = 1;
    for (int m = 0; m < orders; ++m) {
      a(i, 1 + 2 * m) = std::sin((m + 1.0) * steps * measured);
      a(i, 2 + 2 * m) = std::cos((m + 1.0) * steps * measured);
    }
  }
  const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(e);
  return coef[1];
}

double EquivalentGamma(double ripple_sin1, int steps) {
  // Projectors are expansive (gamma > 1), so [1, 5] is searched first, then [0.3, 1]. For N = 4
  // the ripple of a power law vanishes at gamma 1 and 2, so small ripples have two roots.
  // RippleOfGamma on the search grid depends only on N: computed once per N (a few ms each).
  static std::mutex cache_mutex;
  static std::map<std::pair<int, double>, double> cache;
  auto ripple = [&](double g) {
    const std::pair<int, double> key(steps, g);
    {
      const std::lock_guard<std::mutex> lock(cache_mutex);
      const auto it = cache.find(key);
      if (it != cache.end()) return it->second;
    }
    const double r = RippleOfGamma(g, steps);
    const std::lock_guard<std::mutex> lock(cache_mutex);
    cache.emplace(key, r);
    return r;
  };
  auto scan = [&](double from, double to) {
    double prev_g = from, prev_r = ripple(from);
    for (double g = from + 0.05; g <= to + 1e-9; g += 0.05) {
      const double r = ripple(g);
      if ((prev_r - ripple_sin1) * (r - ripple_sin1) <= 0 && r != prev_r)
        return prev_g + (g - prev_g) * (ripple_sin1 - prev_r) / (r - prev_r);
      prev_g = g;
      prev_r = r;
    }
    return std::numeric_limits<double>::quiet_NaN();
  };
  const double high = scan(1.0, 5.0);
  return std::isfinite(high) ? high : scan(0.3, 1.0);
}

}  // namespace ramtk::vision
