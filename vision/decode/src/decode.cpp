// The decode pipeline: phase, quality mask, noise, unwrapping, nonlinearity correction, output.
#include "ramtk/vision/decode/decode.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/vision/decode/detail/decode_internal.h"
#include "ramtk/vision/decode/detail/test_hooks.h"
#include "ramtk/vision/decode/phase_preview.h"
#include "ramtk/vision/fringe/codec.h"
#include "ramtk/vision/fringe/image_io.h"

namespace ramtk::vision {
namespace detail {
namespace {
std::mutex g_hooks_mutex;
DecodeTestHooks g_hooks;
}  // namespace

DecodeTestHooks CurrentDecodeTestHooks() {
  std::lock_guard<std::mutex> lock(g_hooks_mutex);
  return g_hooks;
}

void SetDecodeTestHooks(const DecodeTestHooks& hooks) {
  std::lock_guard<std::mutex> lock(g_hooks_mutex);
  g_hooks = hooks;
}
}  // namespace detail
std::string DecodeOptions::Validate() const {
  for (const auto& [v, field] :
       {std::pair{min_modulation_fraction, "min_modulation_fraction"},
        std::pair{saturation_fraction, "saturation_fraction"}, std::pair{dark_fraction, "dark_fraction"}})
    if (!(v >= 0 && v <= 1)) return std::string(field) + ": expected a fraction in [0, 1]";
  if (!std::isfinite(intensity_sigma_dn)) return "intensity_sigma_dn: must be finite";
  if (!(max_order_error_probability > 0 && max_order_error_probability < 1))
    return "max_order_error_probability: expected a probability in (0, 1)";
  if (!(noise_floor_factor >= 0 && noise_floor_factor <= 100))
    return "noise_floor_factor: expected a factor in [0, 100]";
  if (!(max_order_residual > 0 && max_order_residual < 0.5)) return "max_order_residual: expected a value in (0, 0.5)";
  if (correct_nonlinearity)
    if (const std::string p = nonlinearity.Validate(); !p.empty()) return "nonlinearity." + p;
  if (harmonic_stride < 1) return "harmonic_stride: must be >= 1";
  if (noise_stride < 1) return "noise_stride: must be >= 1";
  if (estimate_max_samples < 0) return "estimate_max_samples: must be >= 0 (0 = the strides alone)";
  if (const std::string p = coordinate_filter.Validate(); !p.empty()) return "coordinate_filter." + p;
  return "";
}

std::string DecodeSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << "decode " << (camera.empty() ? "" : camera + " ") << message << ": " << width << "x" << height << ", N=" << steps
    << ", period " << period_px << " px, valid " << 100.0 * valid_fraction << "% (" << valid_pixels
    << " px; masked: " << low_modulation << " low modulation, " << saturated << " saturated, " << dark << " dark, "
    << unwrap_rejected << " unwrap; " << modulation_rule << " rule, B >= " << modulation_threshold_dn << " DN), "
    << edge_corrections << " edge orders corrected, fit residual RMS "
    << fit_residual_rms_dn << " DN (phase " << phase_residual_rms_rad << " rad), ";
  if (sigma_intensity_random_dn > 0)
    s << "of it random " << sigma_intensity_random_dn << " DN and systematic " << sigma_intensity_systematic_dn
      << " DN, ";
  s << "sigma_I " << sigma_intensity_dn << " DN, ";
  if (phase_ripple_rad > 0) s << "phase ripple " << phase_ripple_rad << " rad, ";
  s << "median B " << median_modulation_dn << " DN, median sigma_phi " << median_sigma_phase_rad << " rad; ";
  if (!harmonic_ratios.empty()) {
    s << "harmonics B_h/B_1 (h=2..):";
    for (double r : harmonic_ratios) s << " " << r;
    s << " (power-law gamma " << gamma_from_harmonics << "); ";
  }
  s << nonlinearity.BriefReport();
  if (coordinate_filter.radius_px > 0)
    s << "; phase filter R=" << coordinate_filter.radius_px << ": " << coordinate_filter.filtered << " px filtered ("
      << coordinate_filter.kept_sparse << " sparse, " << coordinate_filter.kept_departure
      << " departed kept), median sigma x" << coordinate_filter.median_sigma_ratio;
  return s.str();
}

DecodedCamera DecodeFrames(const FringeManifest& m, const std::vector<cv::Mat>& frames, double full_scale,
                           const DecodeOptions& options, const std::string& camera) {
  ThrowIfInvalid(options.Validate(), "DecodeOptions");
  m.Check();
  const std::string where = m.path.empty() ? camera : m.path;
  if (static_cast<int>(frames.size()) != m.ImageCount())
    throw InputError({where, 0, "cameras." + camera}, "the sequence needs " + std::to_string(m.ImageCount()) +
                                                          " images, got " + std::to_string(frames.size()));
  // One sample type and size for the whole set (else everything as float).
  bool uniform = true;
  for (const cv::Mat& f : frames) {
    if (f.size() != frames[0].size()) throw InputError({where, 0, "cameras." + camera}, "the images differ in size");
    uniform = uniform && f.type() == frames[0].type() && f.channels() == 1 &&
              (f.depth() == CV_8U || f.depth() == CV_16U || f.depth() == CV_32F);
  }
  const bool reference = detail::CurrentDecodeTestHooks().reference_path;
  DecodedCamera out;
  const PatternCodec& codec = CodecOf(m.sequence[0]);  // an absolute block is the whole sequence (Check)
  if (codec.decode) {
    out = detail::DecodeFramesWithCodec(m, frames, full_scale, options, camera);
  } else if (!reference && uniform) {
    out = detail::DecodeFramesFast(m, frames, full_scale, options, camera);
  } else if (uniform && frames[0].depth() == CV_32F) {
    out = reference ? detail::DecodeFramesReference(m, frames, full_scale, options, camera)
                    : detail::DecodeFramesFast(m, frames, full_scale, options, camera);
  } else {
    std::vector<cv::Mat> as_float(frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) frames[i].convertTo(as_float[i], CV_32F);
    out = reference ? detail::DecodeFramesReference(m, as_float, full_scale, options, camera)
                    : detail::DecodeFramesFast(m, as_float, full_scale, options, camera);
  }
  if (options.coordinate_filter.radius_px > 0 && out.summary.termination == Termination::kSuccess) {
    out.summary.coordinate_filter = FilterCoordinate(
        options.coordinate_filter, out.summary.phase_ripple_rad * out.summary.period_px / (2 * CV_PI), &out);
  }
  if (!options.keep_diagnostic_maps) {
    out.wrapped.release();
    out.background.release();
    out.sigma_phase.release();
    out.fit_residual.release();
  }
  return out;
}

DecodedCamera DecodeCamera(const FringeManifest& manifest, const std::string& camera, const DecodeOptions& options) {
  ThrowIfInvalid(options.Validate(), "DecodeOptions");
  const auto it = manifest.cameras.find(camera);
  if (it == manifest.cameras.end()) {
    std::string names;
    for (const auto& [name, files] : manifest.cameras) names += (names.empty() ? "" : ", ") + name;
    throw InputError({manifest.path, 0, "cameras"}, "no camera '" + camera + "' (the manifest has: " + names + ")");
  }
  std::vector<std::string> paths;
  for (const std::string& f : it->second) paths.push_back(manifest.Resolve(f));
  // The fast path reads 8/16-bit grey files as stored; the reference path as float.
  const ImageStack stack = LoadImageStack(paths, options.dark_fraction, !detail::CurrentDecodeTestHooks().reference_path);
  return DecodeFrames(manifest, stack.frames, stack.full_scale, options, camera);
}

std::string DecodeSummaryToJson(const DecodeSummary& s) {
  nlohmann::json j;
  j["camera"] = s.camera;
  j["termination"] = s.message;
  j["width"] = s.width;
  j["height"] = s.height;
  j["steps"] = s.steps;
  j["period_px"] = s.period_px;
  j["valid_pixels"] = s.valid_pixels;
  j["valid_fraction"] = s.valid_fraction;
  j["masked"] = {{"low_modulation", s.low_modulation},
                 {"saturated", s.saturated},
                 {"dark", s.dark},
                 {"unwrap_rejected", s.unwrap_rejected}};
  j["modulation_rule"] = {{"rule", s.modulation_rule},
                          {"threshold_dn", s.modulation_threshold_dn},
                          {"noise_floor_dn", s.noise_floor_dn},
                          {"gray_contrast_ratio", s.gray_contrast_ratio}};
  j["edge_corrections"] = s.edge_corrections;
  j["sigma_intensity_dn"] = s.sigma_intensity_dn;
  j["fit_residual_rms_dn"] = s.fit_residual_rms_dn;
  j["sigma_intensity_random_dn"] = s.sigma_intensity_random_dn;
  j["sigma_intensity_systematic_dn"] = s.sigma_intensity_systematic_dn;
  j["phase_ripple_rad"] = s.phase_ripple_rad;
  j["coordinate_filter"] = {{"radius_px", s.coordinate_filter.radius_px},
                            {"filtered", s.coordinate_filter.filtered},
                            {"kept_sparse", s.coordinate_filter.kept_sparse},
                            {"kept_departure", s.coordinate_filter.kept_departure},
                            {"median_sigma_ratio", s.coordinate_filter.median_sigma_ratio}};
  j["worst_residual_dn"] = s.worst_residual_dn;
  j["phase_residual_rms_rad"] = s.phase_residual_rms_rad;
  j["median_modulation_dn"] = s.median_modulation_dn;
  j["median_sigma_phase_rad"] = s.median_sigma_phase_rad;
  const NonlinearityEstimate& nl = s.nonlinearity;
  j["nonlinearity"] = {
      {"applied", nl.applied},
      {"ripple_sin_rad", nl.sin_rad},
      {"ripple_cos_rad", nl.cos_rad},
      {"ripple_rms_rad", nl.ripple_rms_rad},
      {"equivalent_gamma", std::isfinite(nl.equivalent_gamma) ? nlohmann::json(nl.equivalent_gamma) : nlohmann::json()},
      {"highpass_rms_before_rad", nl.residual_rms_before_rad},
      {"highpass_rms_after_rad", nl.residual_rms_after_rad},
      {"ripple_t2", nl.ripple_t2},
      {"window_px", nl.window_px},
      {"pixels_used", nl.pixels_used},
      {"row_subsample", nl.row_subsample}};
  j["harmonic_ratios"] = s.harmonic_ratios;
  j["gamma_from_harmonics"] =
      std::isfinite(s.gamma_from_harmonics) ? nlohmann::json(s.gamma_from_harmonics) : nlohmann::json();
  j["brief"] = s.BriefReport();
  return j.dump(2) + "\n";
}

void WriteDecodedCamera(const std::string& out_dir, const std::string& camera, const DecodedCamera& d,
                        const std::string& float_extension) {
  if (float_extension != "tiff" && float_extension != "exr")
    throw InputError({"", 0, "--format"}, "expected tiff or exr, got '" + float_extension + "'");
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError({out_dir, 0, "--out"}, "cannot create the output folder: " + ec.message());
  auto path = [&](const std::string& suffix) { return (std::filesystem::path(out_dir) / (camera + suffix)).string(); };
  const std::string ext = "." + float_extension;
  cv::Mat mask_float;
  d.mask.convertTo(mask_float, CV_32F, 1.0 / 255.0);
  WriteImage(path("_coordinate" + ext), d.coordinate);
  WriteImage(path("_modulation" + ext), d.modulation);
  WriteImage(path("_sigma_phase" + ext), d.sigma_phase);
  if (float_extension == "tiff") {
    WriteImage(path("_mask.tiff"), d.mask);  // uint8 0/255
  } else {
    WriteImage(path("_mask.exr"), mask_float);  // EXR has no 8-bit type: float 0/1
  }
  WriteImage(path("_coordinate.png"), CoordinatePreview(d.coordinate, d.mask));
  WriteImage(path("_wrapped.png"), WrappedPhasePreview(d.wrapped, d.mask));
  WriteImage(path("_modulation.png"), ScalarPreview(d.modulation, cv::Mat(d.mask.size(), CV_8U, cv::Scalar(255))));
  WriteImage(path("_mask.png"), d.mask);
  WriteFileAtomically(path("_summary.json"), DecodeSummaryToJson(d.summary));
}

}  // namespace ramtk::vision
