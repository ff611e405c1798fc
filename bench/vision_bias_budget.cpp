// Bias budget of the scanned sphere centre against the simulator's truth, per rig, over noise
// seeds: the noise-free radiance is rendered once per rig and only the sensor noise is redrawn
// per seed; each seed's set is decoded and scanned with the scan's defaults. Per rig and axis:
// the mean centre error and its standard error (sd / sqrt(n)), the radius bias and its standard
// error, RMS(error / predicted sigma), and the efficiency: the observed seed-to-seed scatter over
// the Cramér–Rao bound (SphereResult::crlb_centre_sigma_mm, the scan's correlation factor
// included). Prints a Markdown table; a rig/axis whose |mean error| exceeds 0.5 standard errors
// is marked. --noise-free scans the noise-free render (the sensor's quantisation only): the
// part of the error that is not from the noise.
// --kernel: the calibration the scan reads states no sampling kernel (unstated, the default), the
// kernel the render used (stated; the matcher then applies its kernel and interpolation terms),
// or a given one, F,S = fill factor, PSF sigma px (a wrong kernel); auto: no kernel stated and the
// matcher estimates it from the data (StereoMatchOptions::kernel_estimate; "unstated" turns the
// estimate off). The estimated kernel variance per seed goes to stderr, its mean and sd per rig
// below the table.
//   vision_bias_budget [--seeds N] [--first-seed S (1000)] [--noise-free] [--no-noise-term]
//   [--kernel unstated|stated|auto|F,S] [--rigs
//   small,small-offaxis,small-4step,small-half,thesis-roi,2048-4step,slmaster]
// --no-noise-term: the matcher without its noise term (StereoMatchOptions::noise_bias_term).
// Rigs: small = the README demo rig (`ramtk simulate fringe --preset small`, 640x512 windows of
// the thesis cameras, ball at (0, 0, 700)); small-offaxis = the same with the ball at
// (-20, 10, 720); small-4step = 4-step phase shift instead of 12; small-half = the windows
// resampled to half the resolution (ScaleCameraWindows 0.5, 320x256, 2x larger pixels);
// thesis-roi = the whole 3312x2488 thesis frames scanned with `--roi auto` windows (slow);
// 2048-4step = datasets/scan_default's calibration at 2048x1536, f = 2400 px, 4-step + 6-bit
// complementary Gray, point-sampled, saturation 0.5 (docs/scan.md's 2048 rig), auto windows;
// slmaster = the small preset's scene and sequence around SLMaster's real calibration
// (RAMTK_SHARED_DIR/data/slmaster-binocular/caliInfo.yml), auto windows.
// Each rig name takes modifiers (MakeRig): 2048-4step+steps=12, slmaster+ss=1+bits=16, ...;
// +psf=S / +fill=F render with that lens PSF σ (px) / fill factor (applied in order: +ss first).
// A noise-free render quantised to 8 bits is not dithered: its error carries the quantisation's
// pattern (µm on the larger-pixel rigs); +bits=16 separates the model's own error.
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/sim/fringe_simulator.h"
#include "scan_sim.h"

using namespace ramtk;
using namespace ramtk::vision;

namespace {

struct Rig {
  std::string name;
  FringeSimulationConfig config;
  bool roi = false;  // whole frames scanned with auto windows
};

Rig MakeBaseRig(const std::string& name);

// A rig with modifiers after its name, each "+key=value": +steps=N (the phase-shift steps),
// +cycles=C (fringe periods across the projector; the Gray bits follow), +ss=S (supersampling;
// 1 = point sampling), +exposure=X (the saturation effect's exposure factor),
// +bits=B (the sensor's bit depth, 8..16), +psf=S / +fill=F (both cameras' kernel: that PSF σ px / fill
// factor, the rest as rendered). E.g. 2048-4step+steps=12.
Rig MakeRig(const std::string& spec) {
  std::stringstream parts(spec);
  std::string base;
  std::getline(parts, base, '+');
  Rig rig = MakeBaseRig(base);
  rig.name = spec;
  for (std::string mod; std::getline(parts, mod, '+');) {
    const size_t eq = mod.find('=');
    const std::string key = mod.substr(0, eq);
    const double value = eq == std::string::npos ? 0 : std::atof(mod.c_str() + eq + 1);
    SequenceBlock* ps = nullptr;
    SequenceBlock* gray = nullptr;
    for (SequenceBlock& b : rig.config.sequence) {
      if (b.type == BlockType::kPhaseShift && !ps) ps = &b;
      if (b.type == BlockType::kGrayCode && !gray) gray = &b;
    }
    if (key == "steps" && ps && value >= 3) {
      ps->steps = static_cast<int>(value);
    } else if (key == "cycles" && ps && gray && value > 0) {
      const double ratio = value / ps->cycles.at(0);
      ps->cycles = {value};
      gray->bits += static_cast<int>(std::lround(std::log2(ratio)));
    } else if (key == "ss" && value >= 1) {
      rig.config.supersampling = static_cast<int>(value);
    } else if (key == "bits" && value >= 8 && value <= 16) {
      rig.config.sensor.bits = static_cast<int>(value);
    } else if ((key == "psf" || key == "fill") && value >= 0) {
      for (int cam = 0; cam < 2; ++cam) {  // the rendered kernel with its PSF σ or fill factor replaced
        camera::SamplingKernel k = RenderedKernel(rig.config, cam);
        (key == "psf" ? k.psf_sigma_px : k.fill_factor) = value;
        (cam ? rig.config.cameras.right : rig.config.cameras.left).sampling_kernel = k;
      }
    } else if (key == "exposure" && value > 0) {
      rig.config.effects.Set("saturation", value);
    } else {
      std::fprintf(stderr, "rig %s: unknown or invalid modifier %s\n", spec.c_str(), mod.c_str());
      std::exit(2);
    }
  }
  return rig;
}

Rig MakeBaseRig(const std::string& name) {
  Rig rig{name, MakeFringePreset("small"), false};
  if (name == "small") return rig;
  if (name == "small-offaxis") {
    rig.config = MakeFringePreset("small", Vec3(-20, 10, 720));
  } else if (name == "small-4step") {
    rig.config.sequence = {PhaseShiftBlock(4, 64.0), GrayCodeBlock(7, true)};
  } else if (name == "small-half") {
    rig.config = ScaleCameraWindows(rig.config, 0.5);
  } else if (name == "thesis-roi") {
    rig.config = MakeFringePreset("thesis");
    rig.roi = true;
  } else if (name == "2048-4step") {
    // The bundled default set's calibration with 2048x1536 images and f = 2400 px (the ball
    // ~130 px across), 4-step + 6-bit complementary Gray, point sampling, half exposure.
    StereoCalibration cal = ReadStereoCalibration(std::string(RAMTK_DATASETS_DIR) + "/scan_default/calibration.yml");
    for (CameraIntrinsics* cam : {&cal.left, &cal.right}) {
      cam->fx = cam->fy = 2400;
      cam->cx = 1023.5;
      cam->cy = 767.5;
      cam->width = 2048;
      cam->height = 1536;
    }
    rig.config = MakeFringeConfigForCalibration(cal);
    rig.config.sequence = {PhaseShiftBlock(4, 32.0), GrayCodeBlock(6, true)};
    rig.config.supersampling = 1;
    rig.config.effects.Set("saturation", 0.5);
    rig.roi = true;
  } else if (name == "slmaster") {
    // SLMaster's real stereo calibration (1280x1024) around the small preset's ball and sequence.
    const char* shared = std::getenv("RAMTK_SHARED_DIR");
    const std::string dir = shared ? shared : RAMTK_SHARED_DIR;
    rig.config = MakeFringeConfigForCalibration(ReadStereoCalibration(dir + "/data/slmaster-binocular/caliInfo.yml"));
    rig.roi = true;
  } else {
    std::fprintf(stderr, "unknown rig %s\n", name.c_str());
    std::exit(2);
  }
  return rig;
}

// The scanned sphere of each seed.
struct Draw {
  Eigen::Vector3d error, sigma, crlb;
  double radius_error;
  double kernel_px2;  // the matcher's kernel variance estimate (NaN: none)
  std::string kernel_status;
};

struct RigResult {
  int seeds = 0, misses = 0;
  std::vector<Draw> draws;
};

// The calibration the scan reads: the render's own (no kernel stated), its kernel stated
// ("stated", StateRenderedKernel), or a kernel "F,S" stated for both cameras (fill factor, PSF σ px).
StereoCalibration ScanCalibration(const FringeSimulationConfig& c, const std::string& kernel) {
  if (kernel == "stated") return WrittenCalibration(StateRenderedKernel(c));
  StereoCalibration calib = WrittenCalibration(c);
  calib.left.sampling_kernel = calib.right.sampling_kernel = std::nullopt;  // a +psf / +fill render's too
  if (kernel == "unstated" || kernel == "auto") return calib;
  camera::SamplingKernel k;
  if (std::sscanf(kernel.c_str(), "%lf,%lf", &k.fill_factor, &k.psf_sigma_px) != 2 || !k.Validate().empty()) {
    std::fprintf(stderr, "--kernel: expected unstated, stated or F,S (fill factor, PSF sigma px), got %s\n",
                 kernel.c_str());
    std::exit(2);
  }
  calib.left.sampling_kernel = calib.right.sampling_kernel = k;
  return calib;
}

RigResult RunRig(const Rig& rig, int seeds, int first_seed, bool noise, const std::string& kernel, bool noise_term) {
  FringeSimulationConfig c = rig.config;
  const Vec3 ball = c.scene.spheres[0].centre_in_left;
  const double radius = c.scene.spheres[0].radius;
  c.sensor.noise = false;
  const SimulatedCamera l0 = SimulateCamera(c, 0), r0 = SimulateCamera(c, 1);
  c.sensor.noise = noise;
  const StereoCalibration calib = ScanCalibration(c, kernel);
  RigResult out;
  out.seeds = seeds;
  for (int s = 0; s < seeds; ++s) {
    c.seed = first_seed + s;
    const SimulatedCamera l = ResenseCamera(c, l0, 0), r = ResenseCamera(c, r0, 1);
    ScanOptions options;
    options.match.kernel_estimate =
        kernel == "auto" ? StereoMatchOptions::KernelEstimate::kAuto : StereoMatchOptions::KernelEstimate::kOff;
    options.match.noise_bias_term = noise_term;
    ScanResult res;
    if (rig.roi) {
      options.roi.mode = ScanRoiOptions::Mode::kAuto;
      res = ScanFrames(testing::ManifestForConfig(c), calib, l.images, r.images, (1 << c.sensor.bits) - 1.0, options);
    } else {
      const DecodedCamera dl = testing::DecodeSimulated(c, l), dr = testing::DecodeSimulated(c, r);
      res = ScanDecoded(calib, dl, dr, dl.summary.period_px, options);
    }
    if (res.summary.spheres.spheres.empty()) {
      std::fprintf(stderr, "%s seed %d: %s\n", rig.name.c_str(), s, res.summary.BriefReport().c_str());
      ++out.misses;
      continue;
    }
    const SphereResult& b = res.summary.spheres.spheres[0];
    const KernelVarianceEstimate& k = res.summary.match.kernel;
    out.draws.push_back({b.centre_mm - ball, b.CentreSigma(), b.crlb_centre_sigma_mm, b.radius_mm - radius,
                         k.variance_px2, k.status});
    std::fprintf(stderr,
                 "%s seed %d: error (%+.2f, %+.2f, %+.2f) um, sigma (%.2f, %.2f, %.2f) um; kernel %s k = %.4f +- %.4f "
                 "px^2 (%ld px)\n",
                 rig.name.c_str(), s, 1e3 * out.draws.back().error.x(), 1e3 * out.draws.back().error.y(),
                 1e3 * out.draws.back().error.z(), 1e3 * b.CentreSigma().x(), 1e3 * b.CentreSigma().y(),
                 1e3 * b.CentreSigma().z(), k.status.c_str(), k.variance_px2, k.sigma_px2, k.pixels);
  }
  return out;
}

// Mean and standard error of the mean of v.
void MeanSe(const std::vector<double>& v, double* mean, double* se) {
  const double n = static_cast<double>(v.size());
  double m = 0, ss = 0;
  for (double x : v) m += x / n;
  for (double x : v) ss += (x - m) * (x - m);
  *mean = m;
  *se = n > 1 ? std::sqrt(ss / (n - 1) / n) : NAN;
}

void PrintRig(const Rig& rig, const RigResult& r, std::vector<std::string>* flagged) {
  const char* axes = "xyz";
  const double n = static_cast<double>(r.draws.size());
  if (r.draws.size() < 2) {
    std::printf("| %s | — | %zu of %d seeds fitted | | | | | |\n", rig.name.c_str(), r.draws.size(), r.seeds);
    return;
  }
  std::vector<double> radius;
  for (const Draw& d : r.draws) radius.push_back(d.radius_error);
  double rb, rse;
  MeanSe(radius, &rb, &rse);
  for (int a = 0; a < 3; ++a) {
    std::vector<double> e;
    double z2 = 0, crlb = 0;
    for (const Draw& d : r.draws) {
      e.push_back(d.error[a]);
      z2 += std::pow(d.error[a] / d.sigma[a], 2) / n;
      crlb += d.crlb[a] / n;
    }
    double mean, se;
    MeanSe(e, &mean, &se);
    const double sd = se * std::sqrt(n);
    const bool over = std::abs(mean) > 0.5 * se;
    if (over) flagged->push_back(rig.name + " " + axes[a]);
    std::printf("| %s | %c | %zu/%d | %+.2f ± %.2f%s | %+.2f | %.2f | %.2f / %.2f = %.2f |", rig.name.c_str(), axes[a],
                r.draws.size(), r.seeds, 1e3 * mean, 1e3 * se, over ? " *" : "", mean / se, std::sqrt(z2), 1e3 * sd,
                1e3 * crlb, sd / crlb);
    if (a == 0)
      std::printf(" %+.2f ± %.2f |\n", 1e3 * rb, 1e3 * rse);
    else
      std::printf(" |\n");
  }
}

// The matcher's kernel variance estimates of a rig's seeds: mean, sd, how many were applied.
std::string KernelLine(const Rig& rig, const RigResult& r) {
  std::vector<double> k;
  int applied = 0;
  for (const Draw& d : r.draws) {
    if (std::isfinite(d.kernel_px2)) k.push_back(d.kernel_px2);
    applied += d.kernel_status == "applied";
  }
  double mean = NAN, se = NAN;
  if (!k.empty()) MeanSe(k, &mean, &se);
  char line[256];
  std::snprintf(line, sizeof line, "%s: estimated kernel variance %.4f px^2, sd %.4f over %zu seeds, applied in %d",
                rig.name.c_str(), mean, se * std::sqrt(static_cast<double>(k.size())), k.size(), applied);
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 20;
  int first_seed = 1000;
  bool noise = true;
  bool noise_term = true;
  std::string rigs = "small,small-offaxis,small-4step,small-half";
  std::string kernel = "unstated";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--first-seed") && i + 1 < argc) {
      first_seed = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--no-noise-term")) {
      noise_term = false;
    } else if (!std::strcmp(argv[i], "--noise-free")) {
      noise = false;
    } else if (!std::strcmp(argv[i], "--rigs") && i + 1 < argc) {
      rigs = argv[++i];
    } else if (!std::strcmp(argv[i], "--kernel") && i + 1 < argc) {
      kernel = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: %s [--seeds N] [--first-seed S] [--noise-free] [--no-noise-term] "
                   "[--kernel unstated|stated|auto|F,S] [--rigs "
                   "small,small-offaxis,small-4step,small-half,thesis-roi,2048-4step,slmaster]\n",
                   argv[0]);
      return 2;
    }
  }
  std::vector<std::string> flagged;
  std::printf(
      "| rig | axis | seeds | mean centre error ± s.e. (um) | mean/s.e. | RMS(error/sigma) | "
      "efficiency: sd / CRLB (um) | radius bias ± s.e. (um) |\n|---|---|---|---|---|---|---|---|\n");
  std::stringstream names(rigs);
  bool any = false;
  std::vector<std::string> kernel_lines;
  for (std::string name; std::getline(names, name, ',');) {
    const Rig rig = MakeRig(name);
    const RigResult r = RunRig(rig, seeds, first_seed, noise, kernel, noise_term);
    PrintRig(rig, r, &flagged);
    if (kernel == "auto") kernel_lines.push_back(KernelLine(rig, r));
    any = any || !r.draws.empty();
    std::fflush(stdout);
  }
  std::printf("\n|mean| > 0.5 s.e. (marked *):");
  for (const std::string& f : flagged) std::printf(" %s;", f.c_str());
  std::printf("%s\n", flagged.empty() ? " none" : "");
  for (const std::string& line : kernel_lines) std::printf("%s\n", line.c_str());
  return any ? 0 : 1;
}
