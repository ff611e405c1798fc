// `ramtk diagnose` for fringe sets: residual of the ideal model against the noise floor, structure
// tests, candidate extensions cross-validated over image tiles, the named cause and its gain.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <sstream>

#include "fringe_internal.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/diagnose/fringe/fringe.h"
#include "ramtk/diagnose/engine/model_selection.h"
#include "ramtk/diagnose/engine/statistics.h"
#include "ramtk/vision/fringe/image_io.h"

namespace ramtk::diagnose {
namespace {

// A contender is a look-alike unless the named candidate beats it by this many standard errors.
constexpr double kSeparationZ = 2.0;
// A contender with more than this many times the named candidate's parameters is not a look-alike.
constexpr int kOccamFactor = 2;

// Paired comparison over tiles of two candidates' held-out SSR: sum(a - b) over its standard
// error from the tile-to-tile scatter (negative: a is better). 0 when fewer than 3 tiles.
double PairedTileZ(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return 0.0;
  std::vector<double> d;
  for (size_t t = 0; t < a.size(); ++t)
    if (a[t] != 0.0 || b[t] != 0.0) d.push_back(a[t] - b[t]);
  const int g = static_cast<int>(d.size());
  if (g < 3) return 0.0;
  double sum = 0;
  for (double v : d) sum += v;
  const double mean = sum / g;
  double ss = 0;
  for (double v : d) ss += (v - mean) * (v - mean);
  const double se = std::sqrt(ss * g / (g - 1.0));
  return se > 0 ? sum / se : 0.0;
}

// What would tell two fringe look-alikes apart.
std::string SeparatingData(const std::string& a, const std::string& b) {
  const auto pair = [&](const char* x, const char* y) { return (a == x && b == y) || (a == y && b == x); };
  if (pair("camera_defocus", "defocus"))
    return "a surface whose fringe density varies across the image (tilted or curved: the camera's blur "
           "spreads the code edges in camera pixels, the projector's in projector pixels), or a capture of "
           "a sharp albedo edge";
  if (pair("camera_defocus", "sampling_kernel"))
    return "the camera's response is wider than the stated kernel either way (a blur is a PSF); the kernel's "
           "fit says by how much — state it (--with fill_factor=F --with psf_sigma_px=S) if the camera is at its "
           "best focus, else refocus";
  if (pair("soft_knee_response", "projector_nonlinearity"))
    return "samples over the whole intensity range (surfaces of different albedo or two exposures): a sensor "
           "knee bends only samples above its level, a projector response every fringe alike";
  return "more image regions, or a second capture with the suspected cause changed";
}

constexpr double kPi = 3.14159265358979323846;
// A cause is named only when its held-out gain is at least this share of the noise variance and
// removes at least kMinShare of the excess: below that the data hold no effect worth a model.
// (0.1: a 0.2 px blur on a clean independent set gained 4 % of the noise variance — real, but no
// effect worth a model.)
constexpr double kMaterialGain = 0.1;
// Structure no candidate explains is reported when its excess is at least this share of the noise
// variance.
constexpr double kUnexplainedExcess = 0.3;
constexpr double kMinShare = 0.2;
// Residuals drawn for the structure tests (the full set would make any trace of structure
// "significant"; a fixed-size sample keeps the p-values about effects of practical size).
constexpr int kTestSample = 20000;

std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

void Report(const DiagnoseOptions& o, const std::string& stage, int done, int total) {
  if (o.progress) o.progress(Progress{stage, static_cast<size_t>(done), static_cast<size_t>(total)});
}

// σ(I) of residual sample k: from the noise-level function at its model intensity, or --noise.
struct SampleSigma {
  const fringe::FringeFit* fit;
  const fringe::NoiseLevel* nlf;
  double given;  // --noise (> 0 replaces the noise-level function)
  double operator()(size_t k) const {
    const int nf = fit->frames;
    const fringe::PixelFit& p = fit->pixels[k / nf];
    const double level = static_cast<double>(fit->images[k % nf].at<float>(p.y, p.x) - fit->residual[k]);
    return given > 0 ? given
                     : std::sqrt(nlf->Variance(level) * fringe::ResidualVarianceFactor(*fit, static_cast<int>(k % nf)));
  }
};

// Residual sums of the fit: their number into `used`, the RMS.
double ResidualRms(const fringe::FringeFit& fit, long* used) {
  double ss = 0;
  *used = 0;
  for (float r : fit.residual)
    if (std::isfinite(r)) ss += static_cast<double>(r) * r, ++*used;
  return std::sqrt(ss / *used);
}

// The noise floor: every sample's σ(I) from the noise-level function of the data (its RMS is the
// floor, the samples are weighted by floor/σ), or one σ for all from --noise.
fringe::NoiseLevel ModelNoise(fringe::FringeFit* fit, double full_scale, const DiagnoseOptions& options,
                              Diagnosis* out) {
  using namespace fringe;
  Diagnosis& d = *out;
  const int nf = fit->frames;
  long used = 0;
  d.residual_rms = ResidualRms(*fit, &used);
  d.num_residuals = static_cast<int>(used);
  long pairs = 0;
  const double estimated = NoiseFloor(*fit, &pairs);
  const NoiseLevel nlf = EstimateNoiseLevel(*fit);
  if (options.noise <= 0) {
    // The sensor clamps noisy values at 0: near black the expected value bends.
    ModelSensorRange(nlf, fit);
    d.residual_rms = ResidualRms(*fit, &used);
  }
  const SampleSigma sigma_of{fit, &nlf, options.noise};
  double var_sum = 0;
  for (size_t k = 0; k < fit->residual.size(); ++k)
    if (std::isfinite(fit->residual[k])) var_sum += sigma_of(k) * sigma_of(k);
  d.noise_floor_rms = std::sqrt(var_sum / used);
  const double floor = d.noise_floor_rms;
  if (options.noise <= 0) {
    fit->weight.assign(fit->residual.size(), 1.0f);
    for (size_t k = 0; k < fit->residual.size(); ++k)
      if (std::isfinite(fit->residual[k])) fit->weight[k] = static_cast<float>(floor / sigma_of(k));
    d.noise_model = {{"a_DN2", nlf.a}, {"b_DN", nlf.b}, {"c", nlf.c}};
    d.noise_model_sigmas = {{"a_DN2", nlf.sigma_a}, {"b_DN", nlf.sigma_b}};
    if (nlf.super_poisson) d.noise_model_sigmas["c"] = nlf.sigma_c;
  }
  const FringeFit& fitted = *fit;
  d.findings.push_back(std::to_string(fitted.pixels.size()) + " pixels x " + std::to_string(nf) + " frames analysed (" +
                       std::to_string(fitted.steps) + "-step phase shift + " + std::to_string(fitted.gray_bits) +
                       " Gray-code images), " + std::to_string(fitted.width) + "x" + std::to_string(fitted.height) +
                       " camera, full scale " + Fixed(full_scale, 0) + " DN");
  d.findings.push_back("noise floor " + Fixed(estimated, 3) +
                       " DN: RMS of residual differences between neighbouring pixels along the fringes / sqrt(2) (" +
                       std::to_string(pairs) + " pairs)" +
                       (options.noise > 0 ? "; replaced by --noise " + Fixed(options.noise, 3) + " DN" : ""));
  d.findings.push_back(
      "noise-level function (variance vs model intensity I, " + std::to_string(nlf.bins) + " level bins, " +
      std::to_string(nlf.pairs) + " neighbour differences): a + b*I with a = " + Fixed(nlf.a, 3) + " +- " +
      Fixed(nlf.sigma_a, 3) + " DN^2 (read noise), b = " + Fixed(nlf.b, 4) + " +- " + Fixed(nlf.sigma_b, 4) +
      " DN (shot noise, DN per electron)" +
      (nlf.super_poisson ? ", c = " + Fixed(nlf.c, 6) + " +- " + Fixed(nlf.sigma_c, 6) + " per DN (I^2)" : "") +
      "; I^2 term of a quadratic fit " + Fixed(nlf.quadratic_c, 6) + " +- " + Fixed(nlf.sigma_c, 6) + " (" +
      Fixed(100 * nlf.quadratic_share, 1) + "% of the variance at I = " + Fixed(nlf.top_level, 0) +
      " DN); noise floor (RMS of sigma(I)) " + Fixed(floor, 3) + " DN" +
      (options.noise > 0 ? " (not used: --noise)" : ""));
  if (fitted.censored)
    d.findings.push_back(std::to_string(fitted.range_refitted) +
                         " pixels come within 4 sigma(I) of 0: fitted against the mean of the noisy value clamped "
                         "at 0 (the sensor's black end), not the raw intensity");
  return nlf;
}

// Residual by frame class and Gray-code levels in units of B.
void DescribeResidual(const fringe::FringeFit& fit, long used, Diagnosis* out) {
  using namespace fringe;
  Diagnosis& d = *out;
  const int nf = fit.frames;
  double ps_ss = 0, gc_ss = 0, white = 0, black = 0;
  long ps_n = 0, gc_n = 0, nw = 0, nb = 0;
  std::vector<double> black_level;
  for (size_t i = 0; i < fit.pixels.size(); ++i) {
    const PixelFit& p = fit.pixels[i];
    black_level.push_back((p.a - p.b) / p.b);
    for (int f : fit.phase_frame) ps_ss += std::pow(fit.residual[i * nf + f], 2), ++ps_n;
    double w, sp;
    Footprint(fit.kernel, p, &w, &sp);
    for (int j = 0; j < fit.gray_bits; ++j) {
      const double r = fit.residual[i * nf + fit.gray_frame[j]];
      if (!std::isfinite(r)) continue;
      gc_ss += r * r, ++gc_n;
      const double q = GrayPattern(fit, j, p.u, w, sp);
      if (q > 0.999) white += r / p.b, ++nw;
      if (q < 0.001) black += r / p.b, ++nb;
    }
  }
  d.findings.push_back("camera sampling kernel: box of fill factor " + Fixed(fit.kernel.fill_factor, 2) +
                       " px x Gaussian PSF sigma " + Fixed(fit.kernel.psf_sigma_px, 2) +
                       " px (--with fill_factor=F, psf_sigma_px=S); code edges at the cell boundaries" +
                       (fit.edge_offset != 0 ? " - " + Fixed(-fit.edge_offset, 1) + " projector px" : "") +
                       " (their 50% crossing at " + Fixed(fit.edge_offset_estimate, 3) + " px); " +
                       std::to_string(fit.residual.size() - used) +
                       " Gray-code samples within the kernel's box support plus half a projector pixel of a code "
                       "edge left out");
  d.findings.push_back("residual RMS " + Fixed(std::sqrt(ps_ss / ps_n), 2) + " DN on phase-shift frames, " +
                       Fixed(std::sqrt(gc_ss / gc_n), 2) + " DN on Gray-code frames");
  if (nw > 0 && nb > 0)
    d.findings.push_back("Gray-code levels against A +- B: white " + Fixed(white / nw, 3) + " B, black " +
                         Fixed(black / nb, 3) + " B (mean residual over B away from code edges)");
  std::nth_element(black_level.begin(), black_level.begin() + black_level.size() / 2, black_level.end());
  d.findings.push_back("median black level (A - B)/B = " + Fixed(black_level[black_level.size() / 2], 3) +
                       " (ambient light or projector black; the per-pixel A absorbs it, so it leaves no residual)");

}

// Structure tests on a fixed-size random sample of residuals; returns the name of the most
// significant one.
std::string TestStructure(const fringe::FringeFit& fit, const SampleSigma& sigma_of, double full_scale,
                          const DiagnoseOptions& options, Diagnosis* out) {
  using namespace fringe;
  Diagnosis& d = *out;
  const int nf = fit.frames;
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, fit.residual.size() - 1);
  std::vector<double> r, sig, fidx, level, xs, ys, pr, ph, psig;
  for (int s = 0; s < kTestSample; ++s) {
    const size_t k = pick(rng);
    if (!std::isfinite(fit.residual[k])) {
      --s;
      continue;
    }
    const size_t i = k / nf;
    const int f = static_cast<int>(k % nf);
    const PixelFit& p = fit.pixels[i];
    r.push_back(fit.residual[k]);
    sig.push_back(sigma_of(k));
    fidx.push_back(f);
    level.push_back(IdealIntensity(fit, p, f) / full_scale);
    xs.push_back(static_cast<double>(p.x) / fit.width);
    ys.push_back(static_cast<double>(p.y) / fit.height);
    for (int kk = 0; kk < fit.steps; ++kk)
      if (fit.phase_frame[kk] == f) {
        pr.push_back(fit.residual[k]);
        psig.push_back(sig.back());
        ph.push_back(std::remainder(p.phi + StepShift(kk, fit.steps), 2 * kPi));
      }
  }
  std::vector<TestResult> tests;
  tests.push_back(VarianceTest(r, sig));
  tests.push_back(TrendTest(r, sig, fidx, 2, "frame index"));
  tests.push_back(TrendTest(r, sig, level, 3, "intensity level"));
  tests.push_back(TrendTest(r, sig, xs, 2, "image x"));
  tests.push_back(TrendTest(r, sig, ys, 2, "image y"));
  if (pr.size() > 20) tests.push_back(TrendTest(pr, psig, ph, 4, "phase"));
  std::vector<double> pv;
  for (const TestResult& t : tests) pv.push_back(t.p_value);
  const std::vector<double> holm = HolmCorrection(pv);
  int worst = 0;
  for (size_t i = 0; i < tests.size(); ++i) {
    const size_t sampled = tests[i].name == "phase" ? pr.size() : r.size();
    d.findings.push_back(tests[i].Describe() + " (Holm " + Fixed(holm[i], 6) + ", " + std::to_string(sampled) +
                         " sampled residuals)");
    if (holm[i] < holm[worst]) worst = static_cast<int>(i);
  }
  d.structure_p_value = holm[worst];
  d.structure_found = d.structure_p_value < options.alpha;
  return tests[worst].name;
}

// Look-alikes of the named cause `best`: `out` becomes ambiguous when one is not separated.
void FindLookAlike(const CandidateFit& best, double floor, Diagnosis* out) {
  Diagnosis& d = *out;
  // Look-alikes: a contender that removes a material share of the excess too, with at most
  // kOccamFactor times the parameters, whose held-out error per image tile is not worse than the
  // named one's by kSeparationZ standard errors of the tile-to-tile scatter (paired over tiles).
  std::string closest;
  double closest_z = -INFINITY;
  for (const CandidateFit& c : d.candidates) {
    if (c.effect == best.effect || c.effect == kNoEffect || !c.implausible.empty()) continue;
    // A kernel wider than stated is a camera blur: the kernel is the camera blur's look-alike only
    // (any edge spread fits it, so against other causes it would only hide the camera blur).
    if (c.effect == "sampling_kernel" && best.effect != "camera_defocus") continue;
    if (ExcessRemoved(d.rms_before, c.heldout_rms, floor) < kMinShare) continue;
    if (c.num_parameters > kOccamFactor * best.num_parameters) continue;
    const double z = PairedTileZ(best.heldout_group_ssr, c.heldout_group_ssr);
    d.findings.push_back("held-out difference '" + best.effect + "' - '" + c.effect + "': " + Fixed(z, 2) +
                         " standard errors (tile-to-tile scatter)");
    if (z > -kSeparationZ && z > closest_z) closest_z = z, closest = c.effect;
  }
  if (!closest.empty()) {
    d.cause = kAmbiguous;
    d.look_alikes = {best.effect, closest};
    d.separate_with = SeparatingData(best.effect, closest);
    d.findings.push_back("these data do not separate the look-alikes; to separate them: " + d.separate_with);
  }
}

// Candidates, cross-validated over image tiles, and the cause they name.
void NameCause(const fringe::FringeFit& fit, const fringe::NoiseLevel& nlf, const std::string& worst_test,
               const DiagnoseOptions& options, Diagnosis* out) {
  using namespace fringe;
  Diagnosis& d = *out;
  const double floor = d.noise_floor_rms;
  Report(options, "candidates", 2, 4);
  d.candidates = FitCandidates(fit, options.folds, floor);
  SelectCandidate(&d.candidates);
  const CandidateFit* base = nullptr;
  for (const CandidateFit& c : d.candidates)
    if (c.effect == kNoEffect) base = &c;
  const CandidateFit& best = d.candidates.front();
  d.rms_before = base->heldout_rms;
  const double gain = d.rms_before * d.rms_before - best.heldout_rms * best.heldout_rms;
  const double share = ExcessRemoved(d.rms_before, best.heldout_rms, floor);
  const double excess = d.rms_before * d.rms_before - floor * floor;
  for (const CandidateFit& c : d.candidates)
    d.findings.push_back("candidate " + c.effect + ": held-out RMS " + Fixed(c.heldout_rms, 3) + " DN (" +
                         std::to_string(c.num_parameters) + " parameters), " +
                         Fixed(100.0 * ExcessRemoved(d.rms_before, c.heldout_rms, floor), 1) +
                         "% of the excess removed");
  for (const CandidateFit& c : d.candidates)
    if (c.effect == "sampling_kernel")
      d.findings.push_back("sampling kernel that fits the Gray-code edges: fill factor " +
                           Fixed(c.parameters.at("fill_factor"), 2) + " +- " + Fixed(c.sigmas.at("fill_factor"), 2) +
                           ", PSF sigma " + Fixed(c.parameters.at("psf_sigma_px"), 3) + " +- " +
                           Fixed(c.sigmas.at("psf_sigma_px"), 3) + " camera px (stated " +
                           Fixed(fit.kernel.fill_factor, 2) + ", " + Fixed(fit.kernel.psf_sigma_px, 2) +
                           "; parts narrower than half a projector pixel are not seen, and the projector's own "
                           "blur at its code edges is included, so an upper bound" +
                           (ExcessRemoved(d.rms_before, c.heldout_rms, floor) < kMinShare
                                ? "; on held-out pixels it fits no better than the stated kernel)"
                                : ")"));
  if (best.effect != kNoEffect && gain >= kMaterialGain * floor * floor && share >= kMinShare) {
    d.cause = best.effect;
    d.parameters = best.parameters;
    d.sigmas = best.sigmas;
    d.confidence = best.weight;
    d.rms_after = best.heldout_rms;
    FindLookAlike(best, floor, &d);
  } else {
    d.rms_after = d.rms_before;
    if (d.structure_found && excess >= kUnexplainedExcess * floor * floor) {
      d.cause = kUnexplained;
      d.explaining_variable = worst_test;
    } else if (nlf.super_poisson && options.noise <= 0) {
      // The mean model holds; the noise does not follow read + shot noise (a + b·I).
      d.cause = "signal_dependent_noise";
      d.parameters = {{"a_DN2", nlf.a}, {"b_DN", nlf.b}, {"c", nlf.c}};
      d.sigmas = {{"a_DN2", nlf.sigma_a}, {"b_DN", nlf.sigma_b}, {"c", nlf.sigma_c}};
    } else {
      d.cause = kNoEffect;
    }
    d.confidence = base->weight;
  }
  d.excess_removed = ExcessRemoved(d.rms_before, d.rms_after, floor);
}

// The camera's sampling kernel stated by `--with fill_factor=F` and `--with psf_sigma_px=S`
// (default: box of fill 1, no PSF). Throws InputError on a value out of range.
fringe::SamplingKernel StatedKernel(const DiagnoseOptions& options) {
  fringe::SamplingKernel k;
  for (const std::string& w : options.with) {
    const size_t eq = w.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = w.substr(0, eq), value = w.substr(eq + 1);
    if (key != "fill_factor" && key != "psf_sigma_px") continue;
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v))
      throw InputError({"", 0, "--with " + key}, "expected a number, got '" + value + "'");
    if (key == "fill_factor") {
      if (v < 0 || v > 1) throw InputError({"", 0, "--with fill_factor"}, "must be in [0, 1] (0: point sampling)");
      k.fill_factor = v;
    } else {
      if (v < 0 || v > 10) throw InputError({"", 0, "--with psf_sigma_px"}, "must be in [0, 10] camera px");
      k.psf_sigma_px = v;
    }
  }
  return k;
}

// The sampling kernel the set's stereo calibration states for `camera` ("left" or "right"), added
// to options->with unless `--with fill_factor` or `--with psf_sigma_px` already states one; returns
// the note for the report ("" when the calibration states none or is not a stereo file).
std::string KernelFromCalibration(const vision::FringeManifest& manifest, const std::string& camera,
                                  DiagnoseOptions* options) {
  if (manifest.calibration.empty() || (camera != "left" && camera != "right")) return "";
  for (const std::string& w : options->with)
    if (w.rfind("fill_factor=", 0) == 0 || w.rfind("psf_sigma_px=", 0) == 0) return "";
  const camera::StereoCalibration calibration = camera::ReadStereoCalibration(manifest.Resolve(manifest.calibration));
  const camera::CameraIntrinsics& c = camera == "left" ? calibration.left : calibration.right;
  if (!c.sampling_kernel) return "";
  std::ostringstream with_fill, with_psf, note;
  with_fill.precision(17);
  with_psf.precision(17);
  with_fill << "fill_factor=" << c.sampling_kernel->fill_factor;
  with_psf << "psf_sigma_px=" << c.sampling_kernel->psf_sigma_px;
  options->with.push_back(with_fill.str());
  options->with.push_back(with_psf.str());
  note << "; sampling kernel stated by the calibration: fill " << c.sampling_kernel->fill_factor << ", PSF "
       << c.sampling_kernel->psf_sigma_px << " px";
  return note.str();
}

}  // namespace

Diagnosis DiagnoseFringeFrames(const vision::FringeManifest& manifest, const std::vector<cv::Mat>& frames,
                               double full_scale, const DiagnoseOptions& options, const std::string& label) {
  Report(options, "fit ideal model", 0, 4);
  fringe::FringeFit fit = fringe::FitIdealModel(manifest, frames, full_scale, StatedKernel(options));
  Diagnosis d;
  d.kind = DataKind::kFringe;
  d.data = label;
  d.unit = "DN";
  d.model = "ideal fringe model I = A + B cos(phi + delta_k) per pixel";
  const fringe::NoiseLevel nlf = ModelNoise(&fit, full_scale, options, &d);
  DescribeResidual(fit, d.num_residuals, &d);
  Report(options, "structure tests", 1, 4);
  const std::string worst_test = TestStructure(fit, SampleSigma{&fit, &nlf, options.noise}, full_scale, options, &d);
  Report(options, "candidates", 2, 4);
  NameCause(fit, nlf, worst_test, options, &d);
  if (!options.output_folder.empty()) {
    Report(options, "pictures", 3, 4);
    d.pictures = fringe::WriteFringePictures(fit, d.noise_floor_rms, options.output_folder, options.seed);
  }
  Report(options, "done", 4, 4);
  return d;
}

Diagnosis DiagnoseFringe(const DiagnoseOptions& options) {
  ThrowIfInvalid(options.Validate(), "DiagnoseOptions");
  const vision::FringeManifest manifest = vision::ReadFringeManifest(options.data);
  if (manifest.cameras.empty()) throw InputError({options.data, 0, "cameras"}, "the manifest lists no camera");
  std::string camera = manifest.cameras.count("left") ? "left" : manifest.cameras.begin()->first;
  for (const std::string& w : options.with)
    if (w.rfind("camera=", 0) == 0) camera = w.substr(7);
  if (!manifest.cameras.count(camera)) throw InputError({options.data, 0, "cameras"}, "no camera '" + camera + "'");
  std::vector<std::string> paths;
  for (const std::string& f : manifest.cameras.at(camera)) paths.push_back(manifest.Resolve(f));
  const vision::ImageStack stack = vision::LoadImageStack(paths);
  DiagnoseOptions stated = options;
  const std::string kernel_note = KernelFromCalibration(manifest, camera, &stated);
  Diagnosis d = DiagnoseFringeFrames(manifest, stack.frames, stack.full_scale, stated, options.data);
  d.findings.insert(d.findings.begin(), "camera '" + camera + "'" + kernel_note);
  return d;
}

}  // namespace ramtk::diagnose