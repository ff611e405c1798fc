// The fast path of DecodeFrames (decode_internal.h DecodeFramesFast): the fused pass over the rows
// (decode_fused.cpp), then the heterodyne unwrap, the summary's noise figures, the nonlinearity
// correction on the mask's bounding box and the sigma maps. Its results equal the reference path's
// (decode_reference.cpp) within float rounding (tests/vision/decode_fast_test.cpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/detail/decode_avx2.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/decode/nonlinearity.h"
#include "ramtk/vision/fringe/unwrap.h"
#include "ramtk/vision/kernels/rank_select.h"

namespace ramtk::vision::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace

// One row of the sigma maps (decode_internal.h): sigma_phi = sqrt(k^2 / B^2 + ripple^2) (+inf where B <= 0) into
// `sp` (if not null) and sigma_phi * to_px into `sc`; where the mask is 0, NaN in both and in the
// coordinate `c`. Eight pixels at a time on two double lanes: division and square root are
// correctly rounded there as in scalar code, so the maps are the same bit for bit.
void SigmaRow(const uchar* mk, const float* b, int width, double k_sigma, double ripple, double to_px, float* c,
              float* sp, float* sc) {
  int x = Avx2Kernels() ? SigmaRowAvx2(mk, b, width, k_sigma, ripple, to_px, c, sp, sc) : 0;
#if CV_SIMD128_64F
  const cv::v_float64x2 k2 = cv::v_setall_f64(k_sigma * k_sigma), r2 = cv::v_setall_f64(ripple * ripple);
  const cv::v_float64x2 px = cv::v_setall_f64(to_px);
  const cv::v_float32x4 nan = cv::v_setall_f32(kNaN), inf = cv::v_setall_f32(std::numeric_limits<float>::infinity());
  const cv::v_float32x4 zero = cv::v_setzero_f32();
  for (; x + 8 <= width; x += 8) {
    if (EightZero(mk + x)) {  // eight masked pixels (most of a frame outside the object): NaN, no arithmetic
      for (float* out : {c, sp, sc})
        if (out) std::fill_n(out + x, 8, kNaN);
      continue;
    }
    cv::v_uint32x4 m32[2];
    cv::v_expand(cv::v_load_expand(mk + x), m32[0], m32[1]);
    for (int h = 0; h < 2; ++h) {
      const int i = x + 4 * h;
      const cv::v_float32x4 valid = cv::v_reinterpret_as_f32(m32[h] != cv::v_setzero_u32());
      const cv::v_float32x4 bf = cv::v_load(b + i);
      const cv::v_float64x2 b0 = cv::v_cvt_f64(bf), b1 = cv::v_cvt_f64_high(bf);
      const cv::v_float32x4 root = cv::v_cvt_f32(cv::v_sqrt(k2 / (b0 * b0) + r2), cv::v_sqrt(k2 / (b1 * b1) + r2));
      const cv::v_float32x4 sigma = cv::v_select(bf > zero, root, inf);
      const cv::v_float32x4 coord_sigma = cv::v_cvt_f32(cv::v_cvt_f64(sigma) * px, cv::v_cvt_f64_high(sigma) * px);
      cv::v_store(c + i, cv::v_select(valid, cv::v_load(c + i), nan));
      if (sp) cv::v_store(sp + i, cv::v_select(valid, sigma, nan));
      cv::v_store(sc + i, cv::v_select(valid, coord_sigma, nan));
    }
  }
#endif
  for (; x < width; ++x) {
    if (!mk[x]) {
      c[x] = sc[x] = kNaN;
      if (sp) sp[x] = kNaN;
      continue;
    }
    const float s = b[x] > 0
                        ? static_cast<float>(std::sqrt(k_sigma * k_sigma / (double(b[x]) * b[x]) + ripple * ripple))
                        : std::numeric_limits<float>::infinity();
    if (sp) sp[x] = s;
    sc[x] = static_cast<float>(s * to_px);
  }
}

namespace {

bool Report(const DecodeOptions& o, const std::string& stage, std::size_t done, std::size_t total) {
  return !o.progress || o.progress(Progress{stage, done, total});
}

// The fused pass's input: the frames split by block, the step tables and the thresholds in DN.
// `ps_block` receives the phase-shift (or heterodyne) block.
FastDecodeInput MakeFastInput(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                              const DecodeOptions& options, const SequenceBlock** ps_block) {
  FastDecodeInput in;
  in.width = frames[0].cols;
  in.height = frames[0].rows;
  in.extent = m.Extent();
  const SequenceBlock* gc_block = nullptr;
  std::size_t next = 0;
  for (const SequenceBlock& b : m.sequence) {
    if (CodecOf(b).role == CodecRole::kOrder) {  // the period order of the phase block
      gc_block = &b;
      in.gray_frames.clear();
      for (int j = 0; j < b.bits; ++j) in.gray_frames.push_back(&frames[next + j]);
    } else {
      *ps_block = &b;
      for (std::size_t f = 0; f < b.cycles.size(); ++f) {
        std::vector<const cv::Mat*> block;
        for (int k = 0; k < b.steps; ++k) block.push_back(&frames[next + f * b.steps + k]);
        in.ps_frames.push_back(block);
        in.steps.push_back(b.steps);
        std::vector<float> sn(b.steps), cs(b.steps);
        for (int k = 0; k < b.steps; ++k) {
          sn[k] = static_cast<float>(std::sin(2.0 * CV_PI * k / b.steps));
          cs[k] = static_cast<float>(std::cos(2.0 * CV_PI * k / b.steps));
        }
        in.sin_table.push_back(sn);
        in.cos_table.push_back(cs);
      }
    }
    next += b.ImageCount();
  }
  in.heterodyne = (*ps_block)->type == BlockType::kHeterodyne;
  in.keep_diagnostic_maps = options.keep_diagnostic_maps;
  in.complementary = gc_block && gc_block->complementary;
  if (in.heterodyne || !gc_block) in.gray_frames.clear();
  in.phase_at_origin_rad = (*ps_block)->phase_at_origin_rad;
  in.period = in.extent / (*ps_block)->cycles[0];
  in.saturation = static_cast<float>(options.saturation_fraction * full_scale);
  if (options.modulation_rule == ModulationRule::kFixed) {
    in.b_min = static_cast<float>(options.min_modulation_fraction * full_scale);
    in.dark = static_cast<float>(options.dark_fraction * full_scale);
  } else {
    // The pass keeps every pixel above the noise floor of quantisation noise alone, the lowest
    // the sigma rule's threshold can be (SigmaModulationThreshold); the rule is applied once
    // sigma_I is known. No darkness test: a dark pixel is one with no fringes above the noise.
    in.b_min = static_cast<float>(SigmaModulationThreshold({}, in.steps[0], 0.0, options).floor_dn);
    in.dark = -std::numeric_limits<float>::infinity();
    in.b_sample = static_cast<float>(options.min_modulation_fraction * full_scale);
  }
  return in;
}

// InputError if every image is dark: the brightest sample of every frame below the dark level. The
// fused pass's brightest phase-shift sample settles it unless it is itself dark (one pass less over
// the set).
void ThrowIfAllDark(const std::vector<cv::Mat>& frames, double brightest_phase_sample, double dark_dn,
                    const std::string& where, const std::string& camera) {
  if (brightest_phase_sample >= dark_dn) return;
  std::vector<double> frame_max(frames.size(), 0.0);
  tbb::parallel_for(std::size_t{0}, frames.size(), [&](std::size_t i) { cv::minMaxLoc(frames[i], nullptr, &frame_max[i]); });
  const double brightest = *std::max_element(frame_max.begin(), frame_max.end());
  if (brightest < dark_dn)
    throw InputError({where, 0, "cameras." + camera}, "all images are dark: projector off or wrong exposure?");
}

// Heterodyne sets: the coordinate from every frequency's wrapped phase (UnwrapHeterodyne over the
// whole images), the mask and the valid pixels' counts.
void UnwrapHeterodyneInto(const SequenceBlock& ps_block, int extent, int n, const DecodeOptions& options,
                          FastDecodeOutput* fo, FastDecodeCounts* counts) {
  cv::Mat& mask = fo->mask;
  cv::Mat& coord = fo->coordinate;
  std::vector<cv::Mat> w{fo->wrapped};
  for (const cv::Mat& c : fo->coarse_wrapped) w.push_back(c);
  const UnwrapResult u =
      UnwrapHeterodyne(w, ps_block.cycles, ps_block.phase_at_origin_rad, extent, options.max_order_residual);
  for (int y = 0; y < mask.rows; ++y) {
    uchar* mk = mask.ptr<uchar>(y);
    const uchar* ok = u.valid.ptr<uchar>(y);
    const float* uc = u.coordinate.ptr<float>(y);
    float* c = coord.ptr<float>(y);
    const float* r = fo->fit_residual.ptr<float>(y);
    const float* b = fo->modulation.ptr<float>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (!mk[x]) continue;
      if (!ok[x]) {
        mk[x] = 0;
        c[x] = kNaN;
        ++counts->unwrap_rejected;
        continue;
      }
      c[x] = uc[x];
      ++counts->valid;
      if (b[x] < fo->b_sample_dn) continue;
      ++counts->sampled;
      counts->residual_ss += static_cast<double>(r[x]) * r[x] * std::max(0, n - 3);
      counts->phase_ss += 2.0 / n * r[x] * r[x] / (b[x] * b[x]);
      counts->worst_residual = std::max(counts->worst_residual, static_cast<double>(r[x]));
    }
  }
}

// The summary's residual figures and sigma_I (over the noise sample, NoiseSampleMask), the sigma
// rule's threshold applied to the mask (ModulationRule::kSigma), then the counts and medians of
// the valid pixels and the harmonic ratios over the sample. Returns k_sigma = sqrt(2/N) sigma_I;
// *sample is the noise sample within the final mask.
double SummariseFused(const FastDecodeInput& in, const OrderDecision& order, const DecodeOptions& options,
                      FastDecodeCounts* counts, FastDecodeOutput* fo, cv::Mat* sample, DecodeSummary* sum) {
  const int n = sum->steps;
  cv::Mat& mask = fo->mask;
  const bool sigma_rule = options.modulation_rule == ModulationRule::kSigma;
  *sample = sigma_rule ? NoiseSampleMask(mask, fo->modulation, in.b_sample) : mask;
  const long sampled = counts->sampled;
  sum->worst_residual_dn = counts->worst_residual;
  if (n > 3 && sampled > 0) {
    sum->fit_residual_rms_dn = std::sqrt(counts->residual_ss / (static_cast<double>(sampled) * (n - 3)));
    sum->phase_residual_rms_rad = std::sqrt(counts->phase_ss / sampled);
  }
  ChooseIntensitySigma(options, in.ps_frames[0], *sample, n, sampled, sum);
  const double k_sigma = std::sqrt(2.0 / n) * sum->sigma_intensity_dn;
  if (sigma_rule) {
    OrderDecision decision = order;
    if (decision.gray_bits > 0) {
      decision.gray_contrast = GrayContrastRatio(
          in.ps_frames[0], in.gray_frames, *sample, EstimateStride(options.noise_stride, sampled, options.estimate_max_samples));
      sum->gray_contrast_ratio = decision.gray_contrast;
    }
    const ModulationThreshold t = SigmaModulationThreshold(decision, n, sum->sigma_intensity_dn, options);
    counts->valid -=
        ApplyModulationThreshold(t, fo->modulation, mask, fo->coordinate, &counts->dark, &counts->low_modulation);
    sum->modulation_threshold_dn = t.threshold_dn;
    sum->noise_floor_dn = t.floor_dn;
    cv::bitwise_and(*sample, mask, *sample);
  } else {
    sum->modulation_rule = "fixed";
    sum->modulation_threshold_dn = in.b_min;
  }
  const long count = counts->valid;
  sum->valid_pixels = count;
  sum->valid_fraction = static_cast<double>(count) / mask.total();
  sum->outliers = static_cast<long>(mask.total()) - count;
  const std::size_t valid = static_cast<std::size_t>(count);
  if (valid > 0) {
    // sigma_phi = k / B falls with B: the reference's median sigma element is k over the
    // B element at the mirrored rank.
    const std::size_t mirrored = valid - 1 - valid / 2;
    const std::vector<float> at = ValuesAtRanks(fo->modulation, mask, {valid / 2, mirrored});
    sum->median_modulation_dn = at[0];
    sum->median_sigma_phase_rad = static_cast<float>(k_sigma / at[1]);
  }
  const long sample_count = sigma_rule ? cv::countNonZero(*sample) : count;
  sum->harmonic_ratios = MeasureHarmonicRatiosFast(
      in.ps_frames[0], *sample, EstimateStride(options.harmonic_stride, sample_count, options.estimate_max_samples));
  sum->gamma_from_harmonics = sum->harmonic_ratios.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                           : GammaFromSecondHarmonic(sum->harmonic_ratios[0]);
  return k_sigma;
}

// Projector nonlinearity, on the mask's bounding box (even origin: the same period samples as the
// reference path); corrects `coord` in place.
void CorrectNonlinearityOnBox(const DecodeOptions& options, const cv::Mat& mask, const cv::Mat& wrapped, int n,
                              cv::Mat& coord, DecodeSummary* sum) {
  const cv::Rect box = cv::boundingRect(mask);
  const cv::Rect even(box.x & ~1, box.y & ~1, box.br().x - (box.x & ~1), box.br().y - (box.y & ~1));
  const double to_rad = 2 * CV_PI / sum->period_px;
  cv::Mat roi_coord = coord(even);
  const cv::Mat roi_mask = mask(even);
  // The phase in radians (0 where masked) and back, as convertTo with a float scale does it
  // (one float product per pixel), in parallel.
  cv::Mat phase(roi_coord.size(), CV_32F);
  const float to_rad_f = static_cast<float>(to_rad), to_px_f = static_cast<float>(1.0 / to_rad);
  tbb::parallel_for(tbb::blocked_range<int>(0, phase.rows, 32), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* c = roi_coord.ptr<float>(y);
      const uchar* mk = roi_mask.ptr<uchar>(y);
      float* p = phase.ptr<float>(y);
      for (int x = 0; x < phase.cols; ++x) p[x] = mk[x] ? c[x] * to_rad_f : 0.0f;
    }
  });
  sum->nonlinearity = CorrectPhaseNonlinearity(phase, wrapped(even), roi_mask, n, options.nonlinearity);
  tbb::parallel_for(tbb::blocked_range<int>(0, phase.rows, 32), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {  // writes into coord
      const float* p = phase.ptr<float>(y);
      float* c = roi_coord.ptr<float>(y);
      for (int x = 0; x < phase.cols; ++x) c[x] = p[x] * to_px_f;
    }
  });
  sum->iterations = sum->nonlinearity.passes;
  sum->initial_cost = sum->nonlinearity.residual_rms_before_rad;
  sum->final_cost = sum->nonlinearity.residual_rms_after_rad;
}

// The sigma maps (SigmaRow over the rows, in parallel); NaN in the coordinate where masked.
void SigmaMaps(const cv::Mat& mask, const cv::Mat& modulation, double k_sigma, double ripple, double to_px,
               bool keep_sigma_phase, cv::Mat& coord, DecodedCamera* out) {
  if (keep_sigma_phase) out->sigma_phase.create(mask.size(), CV_32F);
  out->sigma_coordinate.create(mask.size(), CV_32F);
  tbb::parallel_for(tbb::blocked_range<int>(0, mask.rows, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const uchar* mk = mask.ptr<uchar>(y);
      const float* b = modulation.ptr<float>(y);
      float* c = coord.ptr<float>(y);
      float* sp = keep_sigma_phase ? out->sigma_phase.ptr<float>(y) : nullptr;
      float* sc = out->sigma_coordinate.ptr<float>(y);
      SigmaRow(mk, b, mask.cols, k_sigma, ripple, to_px, c, sp, sc);
    }
  });
}

bool Cancelled(DecodeSummary* sum) {
  sum->termination = Termination::kCancelled;
  sum->message = "cancelled";
  return true;
}

}  // namespace

DecodedCamera DecodeFramesFast(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                               const DecodeOptions& options, const std::string& camera) {
  DecodedCamera out;
  DecodeSummary& sum = out.summary;
  sum.camera = camera;
  sum.width = frames[0].cols;
  sum.height = frames[0].rows;
  const SequenceBlock* ps_block = nullptr;
  const FastDecodeInput in = MakeFastInput(m, frames, full_scale, options, &ps_block);
  sum.steps = in.steps[0];
  sum.period_px = in.period;
  const int n = sum.steps;

  FastDecodeOutput fo;
  fo.b_sample_dn = in.b_sample;
  FastDecodeCounts counts;
  DecodeFused(in, &fo, &counts);
  ThrowIfAllDark(frames, counts.brightest, options.dark_fraction * full_scale, m.path.empty() ? camera : m.path,
                 camera);
  cv::Mat& mask = fo.mask;
  cv::Mat& coord = fo.coordinate;
  if (in.heterodyne) UnwrapHeterodyneInto(*ps_block, in.extent, n, options, &fo, &counts);
  if (options.modulation_rule == ModulationRule::kSigma) {  // below the quantisation noise floor: no fringes
    counts.dark += counts.low_modulation;
    counts.low_modulation = 0;
  }
  auto copy_counts = [&] {
    sum.dark = counts.dark;
    sum.saturated = counts.saturated;
    sum.low_modulation = counts.low_modulation;
    sum.unwrap_rejected = counts.unwrap_rejected;
    sum.edge_corrections = counts.corrected;
  };
  copy_counts();
  if (!Report(options, "phase", 1, 4) || !Report(options, "unwrap", 2, 4)) {
    Cancelled(&sum);
    return out;
  }
  cv::Mat sample;
  const double k_sigma = SummariseFused(in, OrderDecisionOf(m), options, &counts, &fo, &sample, &sum);
  copy_counts();
  if (options.correct_nonlinearity && counts.valid > 0)
    CorrectNonlinearityOnBox(options, mask, fo.wrapped, n, coord, &sum);
  if (!Report(options, "nonlinearity", 3, 4)) {
    Cancelled(&sum);
    return out;
  }

  const long sample_count =
      options.modulation_rule == ModulationRule::kSigma ? cv::countNonZero(sample) : counts.valid;
  const double ripple = PhaseRipple(options, coord, sample, n, sum.period_px, sample_count);
  sum.phase_ripple_rad = ripple;
  sum.median_sigma_phase_rad = std::sqrt(sum.median_sigma_phase_rad * sum.median_sigma_phase_rad + ripple * ripple);
  SigmaMaps(mask, fo.modulation, k_sigma, ripple, sum.period_px / (2 * CV_PI), options.keep_diagnostic_maps, coord,
            &out);
  out.coordinate = coord;
  out.modulation = fo.modulation;
  if (options.keep_diagnostic_maps) {
    out.wrapped = fo.wrapped;
    out.background = fo.background;
    out.fit_residual = fo.fit_residual;
  }
  out.mask = mask;
  Report(options, "done", 4, 4);
  return out;
}

}  // namespace ramtk::vision::detail
