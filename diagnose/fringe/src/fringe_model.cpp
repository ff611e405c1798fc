// The ideal fringe model fitted per pixel, its residuals and the noise floor.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "fringe_internal.h"
#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/phase_shift.h"
#include "ramtk/vision/fringe/unwrap.h"

namespace ramtk::diagnose::fringe {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Standard deviations of u's noise added to the edge band.
constexpr double kEdgeBandSigmas = 4.0;

// Antiderivative of Φ(t/σ): t·Φ(t/σ) + σ·φ(t/σ).
double IntegratedStep(double t, double sigma) {
  if (sigma < 1e-9) return std::max(t, 0.0);
  const double z = t / sigma;
  return t * 0.5 * std::erfc(-z / std::sqrt(2.0)) + sigma * std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi);
}

// A unit step at 0 seen through a box of width w and a Gaussian of std dev sigma, at offset d.
double SmoothStep(double d, double w, double sigma) {
  if (w < 1e-6) {
    if (sigma < 1e-9) return d > 0 ? 1.0 : (d < 0 ? 0.0 : 0.5);
    return 0.5 * std::erfc(-d / (sigma * std::sqrt(2.0)));
  }
  return (IntegratedStep(d + 0.5 * w, sigma) - IntegratedStep(d - 0.5 * w, sigma)) / w;
}

int GrayBit(int cell, int bits, int j) {
  cell = std::clamp(cell, 0, (1 << bits) - 1);
  const int g = cell ^ (cell >> 1);
  return (g >> (bits - 1 - j)) & 1;
}


// Crossing of the code edges relative to the cell boundaries (projector px): the step position
// o in [−1, 0.5] that best separates the normalised Gray samples q = (I − A)/(2B') + 1/2 (oriented
// to rise) within one projector px of c·cell − 0.25, least squares against the unit step at o.
double EstimateEdgeOffset(const FringeFit& fit) {
  const double cell_px = static_cast<double>(fit.extent) / (1 << fit.gray_bits);
  std::vector<std::pair<double, double>> samples;  // (u − c·cell, q)
  for (const PixelFit& p : fit.pixels) {
    double w, spread;
    Footprint(fit.kernel, p, &w, &spread);
    const double x = kPi * w / fit.period_u;
    const double box = x > 1e-9 ? std::sin(x) / x : 1.0;
    const double contrast = p.b / std::max(box * std::exp(-2.0 * kPi * kPi * spread * spread /
                                                           (fit.period_u * fit.period_u)), 0.05);
    const int c = static_cast<int>(std::lround((p.u + 0.25) / cell_px));
    const double d = p.u - c * cell_px;
    if (std::abs(d + 0.25) > 1.0) continue;
    for (int j = 0; j < fit.gray_bits; ++j) {
      const int jump = GrayBit(c, fit.gray_bits, j) - GrayBit(c - 1, fit.gray_bits, j);
      if (jump == 0) continue;
      const double q = (fit.images[fit.gray_frame[j]].at<float>(p.y, p.x) - p.a) / (2 * contrast) + 0.5;
      samples.emplace_back(d, jump > 0 ? q : 1.0 - q);
    }
  }
  if (samples.size() < 100) return 0.0;
  double best = 0, best_cost = 1e300;
  for (int k = 0; k <= 60; ++k) {
    const double o = -1.0 + 0.025 * k;
    double cost = 0;
    for (const auto& [d, q] : samples) cost += std::pow(q - (d > o ? 1.0 : 0.0), 2);
    if (cost < best_cost) best_cost = cost, best = o;
  }
  return best;
}

}  // namespace

double StepShift(int k, int steps) { return 2.0 * kPi * k / steps; }

void Footprint(const SamplingKernel& kernel, const PixelFit& p, double* width_u, double* spread_u) {
  const double ax = std::abs(p.grad_x), ay = std::abs(p.grad_y);
  const double f = kernel.fill_factor;
  *width_u = f * std::max(ax, ay);
  *spread_u = std::hypot(f * std::min(ax, ay) / std::sqrt(12.0), kernel.psf_sigma_px * std::hypot(ax, ay));
}

double EdgeBand(const SamplingKernel& kernel, const PixelFit& p) {
  return 0.5 * kernel.fill_factor * (std::abs(p.grad_x) + std::abs(p.grad_y)) + 0.5;
}

double GrayPattern(const FringeFit& fit, int j, double u, double width_u, double sigma_u) {
  const double cell_px = static_cast<double>(fit.extent) / (1 << fit.gray_bits);
  u -= fit.edge_offset;
  const int c0 = static_cast<int>(std::floor(u / cell_px));
  const double reach = 0.5 * width_u + 5.0 * sigma_u;
  const int span = 1 + static_cast<int>(std::ceil(reach / cell_px));
  double value = GrayBit(c0 - span, fit.gray_bits, j);
  for (int c = c0 - span + 1; c <= c0 + span; ++c) {
    const int jump = GrayBit(c, fit.gray_bits, j) - GrayBit(c - 1, fit.gray_bits, j);
    if (jump != 0) value += jump * SmoothStep(u - c * cell_px, width_u, sigma_u);
  }
  return value;
}

double EdgeDistance(const FringeFit& fit, int j, double u) {
  const double cell_px = static_cast<double>(fit.extent) / (1 << fit.gray_bits);
  u -= fit.edge_offset;
  const int c0 = static_cast<int>(std::floor(u / cell_px));
  double best = 1e30;
  for (int c = c0 - 2; c <= c0 + 3; ++c)
    if (GrayBit(c, fit.gray_bits, j) != GrayBit(c - 1, fit.gray_bits, j))
      best = std::min(best, std::abs(u - c * cell_px));
  return best;
}

double IdealIntensity(const FringeFit& fit, const PixelFit& p, int f) {
  for (int k = 0; k < fit.steps; ++k)
    if (fit.phase_frame[k] == f) return SensorExpectation(fit, p, p.a + p.b * std::cos(p.phi + StepShift(k, fit.steps)));
  for (int j = 0; j < fit.gray_bits; ++j)
    if (fit.gray_frame[j] == f) return SensorExpectation(fit, p, GrayIntensity(fit, p, j, 0.0));
  return 0.0;
}

double GrayIntensity(const FringeFit& fit, const PixelFit& p, int j, double blur_u) {
  return GrayIntensityWith(fit, fit.kernel, p, j, blur_u);
}

double GrayIntensityWith(const FringeFit& fit, const SamplingKernel& kernel, const PixelFit& p, int j, double blur_u) {
  double w, spread;
  Footprint(kernel, p, &w, &spread);
  const double su = std::sqrt(spread * spread + blur_u * blur_u);
  // B is the modulation of the fringe period; the pixel footprint and the blur attenuate it, not
  // the wide code stripes: their contrast is B divided by that attenuation.
  const double x = kPi * w / fit.period_u;
  const double box = x > 1e-9 ? std::sin(x) / x : 1.0;
  const double gauss = std::exp(-2.0 * kPi * kPi * su * su / (fit.period_u * fit.period_u));
  const double contrast = p.b / std::max(box * gauss, 0.05);
  return p.a + contrast * (2.0 * GrayPattern(fit, j, p.u, w, su) - 1.0);
}

FringeFit FitIdealModel(const vision::FringeManifest& manifest, const std::vector<cv::Mat>& images, double full_scale,
                        const SamplingKernel& kernel) {
  const std::string file = manifest.path;
  const vision::SequenceBlock* ps = nullptr;
  const vision::SequenceBlock* gc = nullptr;
  FringeFit fit;
  fit.kernel = kernel;
  int frame = 0;
  for (const vision::SequenceBlock& b : manifest.sequence) {
    const vision::CodecRole role = vision::CodecOf(b).role;
    if (role == vision::CodecRole::kPhase && !ps) {
      ps = &b;
      for (int k = 0; k < b.steps; ++k) fit.phase_frame.push_back(frame + k);
    } else if (role == vision::CodecRole::kOrder && !gc) {
      gc = &b;
      for (int j = 0; j < b.bits; ++j) fit.gray_frame.push_back(frame + j);
    } else {
      throw InputError({file, 0, "sequence"},
                       "the fringe diagnosis needs exactly one phase_shift block and one gray_code block");
    }
    frame += b.ImageCount();
  }
  if (!ps || !gc)
    throw InputError({file, 0, "sequence"}, "the fringe diagnosis needs a phase_shift block and a gray_code block");
  if (static_cast<int>(images.size()) != frame)
    throw InputError({file, 0, "cameras"},
                     "expected " + std::to_string(frame) + " images, got " + std::to_string(images.size()));
  fit.steps = ps->steps;
  fit.frames = frame;
  fit.gray_bits = gc->bits;
  fit.extent = manifest.Extent();
  fit.period_u = fit.extent / ps->cycles[0];
  fit.full_scale = full_scale;
  fit.vertical = manifest.direction == vision::FringeDirection::kVertical;
  for (const cv::Mat& m : images) {
    cv::Mat f;
    m.convertTo(f, CV_32F);
    fit.images.push_back(f);
  }
  fit.width = fit.images[0].cols;
  fit.height = fit.images[0].rows;

  std::vector<cv::Mat> phase_images, gray_images;
  for (int f : fit.phase_frame) phase_images.push_back(fit.images[f]);
  for (int f : fit.gray_frame) gray_images.push_back(fit.images[f]);
  const vision::PhaseShiftResult phase = vision::ComputePhaseShift(phase_images);
  const cv::Mat cells = vision::DecodeGrayCode(gray_images, phase.background);
  const vision::UnwrapResult unwrapped = vision::UnwrapGrayCode(phase.wrapped, ps->phase_at_origin_rad, ps->cycles[0],
                                                                fit.extent, cells, gc->bits, gc->complementary);
  const cv::Mat& u = unwrapped.coordinate;

  const double min_b = 0.06 * full_scale;
  const int w = fit.width, h = fit.height;
  auto ok = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && unwrapped.valid.at<uchar>(y, x) &&
           phase.modulation.at<float>(y, x) > min_b;
  };
  fit.index = cv::Mat(h, w, CV_32S, cv::Scalar(-1));
  const double clip = full_scale - 0.5;
  for (int y = 2; y < h - 2; ++y)
    for (int x = 2; x < w - 2; ++x) {
      bool all = true;
      for (int dy = -2; dy <= 2 && all; ++dy)
        for (int dx = -2; dx <= 2 && all; ++dx) all = ok(x + dx, y + dy);
      if (!all) continue;
      const double uc = u.at<float>(y, x);
      const double ul = u.at<float>(y, x - 1), ur = u.at<float>(y, x + 1);
      const double uu = u.at<float>(y - 1, x), ud = u.at<float>(y + 1, x);
      // Depth steps, shadows and misread code orders break the local smoothness of u.
      if (std::abs(ul + ur - 2 * uc) > 0.5 || std::abs(uu + ud - 2 * uc) > 0.5) continue;
      // Fringes under-sampled by the pixel (grazing surfaces): more than a quarter period per pixel.
      if (std::abs(ur - ul) + std::abs(ud - uu) > 0.5 * fit.period_u) continue;
      PixelFit p;
      p.x = x;
      p.y = y;
      p.tile =
          std::min(fit.tiles_x - 1, x * fit.tiles_x / w) + fit.tiles_x * std::min(fit.tiles_y - 1, y * fit.tiles_y / h);
      p.a = phase.background.at<float>(y, x);
      p.b = phase.modulation.at<float>(y, x);
      p.phi = phase.wrapped.at<float>(y, x);
      p.u = uc;
      p.grad_x = 0.5 * (ur - ul);
      p.grad_y = 0.5 * (ud - uu);
      p.clipped = phase.max_sample.at<float>(y, x) >= clip;
      fit.index.at<int>(y, x) = static_cast<int>(fit.pixels.size());
      fit.pixels.push_back(p);
    }
  if (fit.pixels.size() < 1000)
    throw InputError({file, 0, "cameras"}, "fewer than 1000 pixels with fringes to analyse (dark or unfocused set?)");
  const int nf = fit.frames;
  fit.residual.resize(fit.pixels.size() * nf);
  const auto compute_residuals = [&] {
    cv::parallel_for_(cv::Range(0, static_cast<int>(fit.pixels.size())), [&](const cv::Range& r) {
      for (int i = r.start; i < r.end; ++i) {
        const PixelFit& p = fit.pixels[i];
        for (int f = 0; f < nf; ++f)
          fit.residual[static_cast<size_t>(i) * nf + f] =
              static_cast<float>(fit.images[f].at<float>(p.y, p.x) - IdealIntensity(fit, p, f));
      }
    });
  };
  // Where the code edges lie: on the cell boundaries of the continuous coordinate (a pattern
  // evaluated at every ray), or half a projector pixel before them (a projector of box pixels whose
  // centres are at integer u, the pattern convention). A symmetric kernel leaves a code edge's 50 %
  // crossing in place: the crossing is estimated from the samples near the edges, and the nearer
  // convention kept.
  fit.edge_offset_estimate = EstimateEdgeOffset(fit);
  const double best_offset = fit.edge_offset_estimate < -0.25 ? -0.5 : 0.0;
  fit.edge_offset = best_offset;
  compute_residuals();
  // The noise of one sample, from the phase-shift residuals (which keep N − 3 of N degrees of
  // freedom), and through it the noise of u: σ_u = P/(2π)·√(2/N)·σ/B.
  double phase_ss = 0;
  for (size_t i = 0; i < fit.pixels.size(); ++i)
    for (int f : fit.phase_frame) phase_ss += std::pow(fit.residual[i * nf + f], 2);
  const double sample_sigma = std::sqrt(phase_ss / (fit.pixels.size() * (fit.steps - 3.0)));
  const double u_noise = fit.period_u / (2 * kPi) * std::sqrt(2.0 / fit.steps) * sample_sigma;
  cv::parallel_for_(cv::Range(0, static_cast<int>(fit.pixels.size())), [&](const cv::Range& r) {
    for (int i = r.start; i < r.end; ++i) {
      const PixelFit& p = fit.pixels[i];
      // Gray samples within the edge band of a code edge are left out (EdgeBand), widened by 4σ of
      // u: with point sampling a sample whose u errs across the edge would carry the full contrast.
      const double reach = EdgeBand(fit.kernel, p) + kEdgeBandSigmas * u_noise / p.b;
      for (int j = 0; j < fit.gray_bits; ++j)
        if (EdgeDistance(fit, j, p.u) < reach)
          fit.residual[static_cast<size_t>(i) * nf + fit.gray_frame[j]] = std::numeric_limits<float>::quiet_NaN();
    }
  });
  return fit;
}

double NoiseFloor(const FringeFit& fit, long* pairs) {
  std::vector<double> d2;
  const int nf = fit.frames;
  for (size_t i = 0; i < fit.pixels.size(); ++i) {
    const PixelFit& p = fit.pixels[i];
    const int nx = fit.vertical ? p.x : p.x + 1, ny = fit.vertical ? p.y + 1 : p.y;
    if (nx >= fit.width || ny >= fit.height) continue;
    const int j = fit.index.at<int>(ny, nx);
    if (j < 0) continue;
    for (int f = 0; f < nf; ++f) {
      const double d = fit.residual[i * nf + f] - fit.residual[static_cast<size_t>(j) * nf + f];
      if (std::isfinite(d)) d2.push_back(d * d);
    }
  }
  if (pairs) *pairs = static_cast<long>(d2.size());
  if (d2.empty()) return 0.0;
  std::vector<double> sorted = d2;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];  // median of d² = (0.6745 σ_d)² for Gaussian d
  const double limit = 36.0 * median / (0.6745 * 0.6745);
  double sum = 0;
  long n = 0;
  for (double v : d2)
    if (v <= limit) sum += v, ++n;
  return n > 0 ? std::sqrt(sum / n / 2.0) : 0.0;
}

}  // namespace ramtk::diagnose::fringe
