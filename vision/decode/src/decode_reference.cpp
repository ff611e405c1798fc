// The reference decode (detail::DecodeFramesReference): float frames, one pass per stage over
// every pixel (phase_shift.h, unwrap.h and the reference nonlinearity estimator). The fast path
// (decode_fast.cpp, decode_fused.cpp) is tested against it; the test hook
// DecodeTestHooks::reference_path runs it in place of the fast path.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/phase_shift.h"
#include "ramtk/vision/fringe/unwrap.h"

namespace ramtk::vision::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

double MedianOf(std::vector<float>& v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

bool Report(const DecodeOptions& o, const std::string& stage, std::size_t done, std::size_t total) {
  return !o.progress || o.progress(Progress{stage, done, total});
}

// The quality mask over every frequency's phase (dark, saturated, low modulation), counted by cause.
// ModulationRule::kSigma: no darkness test, and B below the quantisation noise floor (the lowest
// the rule's threshold can be) is counted as dark; the rule itself follows once sigma_I is known.
cv::Mat QualityMask(const std::vector<PhaseShiftResult>& phases, const DecodeOptions& options, double full_scale,
                    DecodeSummary* sum) {
  cv::Mat mask(phases[0].wrapped.size(), CV_8U, cv::Scalar(255));
  const bool sigma_rule = options.modulation_rule == ModulationRule::kSigma;
  const float b_min =
      sigma_rule ? static_cast<float>(SigmaModulationThreshold({}, phases[0].steps, 0.0, options).floor_dn)
                 : static_cast<float>(options.min_modulation_fraction * full_scale);
  const float sat = static_cast<float>(options.saturation_fraction * full_scale);
  const float dark = sigma_rule ? -std::numeric_limits<float>::infinity()
                                : static_cast<float>(options.dark_fraction * full_scale);
  for (int y = 0; y < mask.rows; ++y) {
    uchar* mk = mask.ptr<uchar>(y);
    for (int x = 0; x < mask.cols; ++x) {
      bool low = false, is_sat = false, is_dark = false;
      for (const PhaseShiftResult& p : phases) {
        const float mx = p.max_sample.ptr<float>(y)[x];
        is_dark |= mx < dark;
        is_sat |= mx >= sat;
        low |= p.modulation.ptr<float>(y)[x] < b_min;
      }
      if (is_dark) {
        ++sum->dark;
      } else if (is_sat) {
        ++sum->saturated;
      } else if (low) {
        ++(sigma_rule ? sum->dark : sum->low_modulation);
      } else {
        continue;
      }
      mk[x] = 0;
    }
  }
  return mask;
}

// Temporal unwrapping: heterodyne, Gray code, or a single period across the projector (the phase
// is absolute).
UnwrapResult UnwrapReference(const std::vector<PhaseShiftResult>& phases, const SequenceBlock& ps_block,
                             const SequenceBlock* gc_block, const std::vector<cv::Mat>& gc_frames, int extent,
                             double max_order_residual, double period_px) {
  const PhaseShiftResult& fine = phases[0];
  UnwrapResult unwrapped;
  if (ps_block.type == BlockType::kHeterodyne) {
    std::vector<cv::Mat> w;
    for (const PhaseShiftResult& p : phases) w.push_back(p.wrapped);
    unwrapped = UnwrapHeterodyne(w, ps_block.cycles, ps_block.phase_at_origin_rad, extent, max_order_residual);
  } else if (gc_block) {
    const cv::Mat cells = DecodeGrayCode(gc_frames, fine.background);
    unwrapped = UnwrapGrayCode(fine.wrapped, ps_block.phase_at_origin_rad, ps_block.cycles[0], extent, cells,
                               gc_block->bits, gc_block->complementary);
  } else {
    unwrapped.coordinate.create(fine.wrapped.size(), CV_32F);
    unwrapped.valid = cv::Mat(fine.wrapped.size(), CV_8U, cv::Scalar(255));
    for (int y = 0; y < fine.wrapped.rows; ++y)
      for (int x = 0; x < fine.wrapped.cols; ++x)
        unwrapped.coordinate.at<float>(y, x) = static_cast<float>(
            PeriodFraction(fine.wrapped.at<float>(y, x), ps_block.phase_at_origin_rad) * period_px);
  }
  return unwrapped;
}

// The ripple added to sigma_phase, sigma_coordinate from it, NaN where masked (also in the
// coordinate). Returns the median sigma_phi of the valid pixels.
double FinishSigmaMaps(const cv::Mat& mask, double ripple, double period_px, cv::Mat& coord, DecodedCamera* out) {
  std::vector<float> sig;
  out->sigma_coordinate.create(mask.size(), CV_32F);
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<uchar>(y, x)) {
        coord.at<float>(y, x) = kNaN;
        out->sigma_phase.at<float>(y, x) = kNaN;
        out->sigma_coordinate.at<float>(y, x) = kNaN;
      } else {
        float& sp = out->sigma_phase.at<float>(y, x);
        sp = static_cast<float>(std::sqrt(static_cast<double>(sp) * sp + ripple * ripple));
        sig.push_back(sp);
        out->sigma_coordinate.at<float>(y, x) =
            static_cast<float>(out->sigma_phase.at<float>(y, x) * period_px / (2 * CV_PI));
      }
    }
  }
  return MedianOf(sig);
}

// The per-pixel fit residual map, and the summary's residual figures over the noise sample.
// Returns the sample's pixel count.
long ResidualFigures(const PhaseShiftResult& fine, const cv::Mat& sample, cv::Mat* fit_residual, DecodeSummary* sum) {
  const int n = fine.steps;
  *fit_residual = cv::Mat::zeros(sample.size(), CV_32F);
  double ss = 0, phase_ss = 0;
  long sampled = 0;
  for (int y = 0; y < sample.rows; ++y) {
    for (int x = 0; x < sample.cols; ++x) {
      if (n > 3) fit_residual->at<float>(y, x) = std::sqrt(fine.residual_ss.at<float>(y, x) / (n - 3));
      if (!sample.at<uchar>(y, x)) continue;
      const float r = fit_residual->at<float>(y, x);
      const float b = fine.modulation.at<float>(y, x);
      ss += fine.residual_ss.at<float>(y, x);
      phase_ss += 2.0 / n * r * r / (b * b);
      sum->worst_residual_dn = std::max(sum->worst_residual_dn, static_cast<double>(r));
      ++sampled;
    }
  }
  if (n > 3 && sampled > 0) {
    sum->fit_residual_rms_dn = std::sqrt(ss / (static_cast<double>(sampled) * (n - 3)));
    sum->phase_residual_rms_rad = std::sqrt(phase_ss / sampled);
  }
  return sampled;
}

}  // namespace

DecodedCamera DecodeFramesReference(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                                    const DecodeOptions& options, const std::string& camera) {
  const std::string where = m.path.empty() ? camera : m.path;
  DecodedCamera out;
  DecodeSummary& sum = out.summary;
  sum.camera = camera;
  sum.width = frames[0].cols;
  sum.height = frames[0].rows;
  const int extent = m.Extent();

  // Split the frames by block.
  const SequenceBlock* ps_block = nullptr;
  const SequenceBlock* gc_block = nullptr;
  std::vector<std::vector<cv::Mat>> ps_frames;  // one entry per frequency (finest first)
  std::vector<cv::Mat> gc_frames;
  std::size_t next = 0;
  for (const SequenceBlock& b : m.sequence) {
    if (CodecOf(b).role == CodecRole::kOrder) {  // the period order of the phase block
      gc_block = &b;
      gc_frames.assign(frames.begin() + next, frames.begin() + next + b.bits);
    } else {
      ps_block = &b;
      for (std::size_t f = 0; f < b.cycles.size(); ++f)
        ps_frames.emplace_back(frames.begin() + next + f * b.steps, frames.begin() + next + (f + 1) * b.steps);
    }
    next += b.ImageCount();
  }
  double brightest = 0;
  for (const cv::Mat& f : frames) {
    double mx = 0;
    cv::minMaxLoc(f, nullptr, &mx);
    brightest = std::max(brightest, mx);
  }
  if (brightest < options.dark_fraction * full_scale)
    throw InputError({where, 0, "cameras." + camera}, "all images are dark: projector off or wrong exposure?");

  // Phase of every frequency; the quality mask uses all of them.
  std::vector<PhaseShiftResult> phases;
  for (const auto& f : ps_frames) phases.push_back(ComputePhaseShift(f));
  const PhaseShiftResult& fine = phases[0];
  sum.steps = fine.steps;
  sum.period_px = extent / ps_block->cycles[0];
  if (!Report(options, "phase", 1, 4)) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return out;
  }
  cv::Mat mask = QualityMask(phases, options, full_scale, &sum);
  const UnwrapResult unwrapped =
      UnwrapReference(phases, *ps_block, gc_block, gc_frames, extent, options.max_order_residual, sum.period_px);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<uchar>(y, x) && !unwrapped.valid.at<uchar>(y, x)) {
        mask.at<uchar>(y, x) = 0;
        ++sum.unwrap_rejected;
      }
  // Count corrected edges on valid pixels only.
  sum.edge_corrections = unwrapped.corrected;
  if (!Report(options, "unwrap", 2, 4)) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return out;
  }

  // Noise: per-pixel fit residual, sigma_I (over the noise sample), the sigma rule's threshold, sigma_phi.
  const int n = fine.steps;
  const bool sigma_rule = options.modulation_rule == ModulationRule::kSigma;
  const float b_sample = sigma_rule ? static_cast<float>(options.min_modulation_fraction * full_scale) : 0.0f;
  cv::Mat sample = sigma_rule ? NoiseSampleMask(mask, fine.modulation, b_sample) : mask;
  const long sampled = ResidualFigures(fine, sample, &out.fit_residual, &sum);
  std::vector<const cv::Mat*> finest;
  for (const cv::Mat& f : ps_frames[0]) finest.push_back(&f);
  detail::ChooseIntensitySigma(options, finest, sample, n, sampled, &sum);
  cv::Mat coord = unwrapped.coordinate.clone();
  if (sigma_rule) {
    OrderDecision decision = OrderDecisionOf(m);
    if (decision.gray_bits > 0) {
      std::vector<const cv::Mat*> gray;
      for (const cv::Mat& g : gc_frames) gray.push_back(&g);
      decision.gray_contrast = GrayContrastRatio(
          finest, gray, sample, EstimateStride(options.noise_stride, sampled, options.estimate_max_samples));
      sum.gray_contrast_ratio = decision.gray_contrast;
    }
    const ModulationThreshold t = SigmaModulationThreshold(decision, n, sum.sigma_intensity_dn, options);
    ApplyModulationThreshold(t, fine.modulation, mask, coord, &sum.dark, &sum.low_modulation);
    sum.modulation_threshold_dn = t.threshold_dn;
    sum.noise_floor_dn = t.floor_dn;
    cv::bitwise_and(sample, mask, sample);
  } else {
    sum.modulation_rule = "fixed";
    sum.modulation_threshold_dn = static_cast<float>(options.min_modulation_fraction * full_scale);
  }
  std::vector<float> bs;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<uchar>(y, x)) bs.push_back(fine.modulation.at<float>(y, x));
  const long count = static_cast<long>(bs.size());
  sum.valid_pixels = count;
  sum.valid_fraction = static_cast<double>(count) / mask.total();
  sum.outliers = static_cast<long>(mask.total()) - count;
  sum.median_modulation_dn = MedianOf(bs);
  out.sigma_phase = PhaseSigma(fine.modulation, n, sum.sigma_intensity_dn);
  sum.harmonic_ratios = MeasureHarmonicRatios(ps_frames[0], sample);
  sum.gamma_from_harmonics = sum.harmonic_ratios.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                         : GammaFromSecondHarmonic(sum.harmonic_ratios[0]);

  // Projector nonlinearity: ripple of N*phi' in the unwrapped phase.
  if (options.correct_nonlinearity && count > 0) {
    const double to_rad = 2 * CV_PI / sum.period_px;
    cv::Mat phase;
    coord.convertTo(phase, CV_32F, to_rad);
    phase.setTo(0, mask == 0);
    sum.nonlinearity = CorrectPhaseNonlinearityReference(phase, fine.wrapped, mask, n, options.nonlinearity);
    phase.convertTo(coord, CV_32F, 1.0 / to_rad);
    sum.iterations = sum.nonlinearity.passes;
    sum.initial_cost = sum.nonlinearity.residual_rms_before_rad;
    sum.final_cost = sum.nonlinearity.residual_rms_after_rad;
  }
  if (!Report(options, "nonlinearity", 3, 4)) {
    sum.termination = Termination::kCancelled;
    sum.message = "cancelled";
    return out;
  }

  const long sample_count = sigma_rule ? cv::countNonZero(sample) : count;
  const double ripple = detail::PhaseRipple(options, coord, sample, n, sum.period_px, sample_count);
  sum.phase_ripple_rad = ripple;
  sum.median_sigma_phase_rad = FinishSigmaMaps(mask, ripple, sum.period_px, coord, &out);
  out.coordinate = coord;
  out.wrapped = fine.wrapped;
  out.background = fine.background;
  out.modulation = fine.modulation;
  out.mask = mask;
  Report(options, "done", 4, 4);
  return out;
}

}  // namespace ramtk::vision::detail
