// Hidden-effect draws for the fringe diagnosis, rendered with the vision simulator.
#include "ramtk/diagnose/fringe/fringe_hidden.h"

#include <cmath>
#include <random>

#include "fringe_internal.h"
#include "ramtk/camera/stereo_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/diagnose/fringe/extra_cause.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::diagnose {
namespace {

struct EffectRange {
  const char* name;
  double lo, hi;     // magnitude range (simulator units)
  bool either_sign;  // draw ± magnitude
  bool visible;      // the ideal intensity model can see it
};

// The drawn effects: the rows of the fringe cause table with a magnitude range (fringe_causes.def).
// Realistic magnitudes: a projector gamma of a consumer DLP, phase-step errors of a few degrees,
// a few percent lamp/exposure drift over the sequence, 50–120 % over-exposure (the brightest
// surface, albedo 0.8 at exposure 0.9, reaches full scale only beyond ×1.39), 0.8–2.5 px camera
// defocus at 320×256, a projector defocus of 0.5–1.4 projector px (~1–2.6 camera px here), a sensor knee at 20–35 % of
// full scale (the scene's brightest samples reach ~70 %; a knee above ~40 % bends them by less than the per-pixel fit
// leaves visible), ambient light 5–20 % of projector white, an extra k1 of a poorly calibrated lens.
std::vector<EffectRange> DrawnEffects() {
  std::vector<EffectRange> out;
  static const EffectRange kRows[] = {
#define RAMTK_FRINGE_CAUSE(name, fit, lo, hi, either_sign, visible, parameters, plausible, help) \
  {#name, lo, hi, either_sign, visible},
#include "ramtk/diagnose/engine/fringe_causes.def"
  };
  for (const EffectRange& e : kRows)
    if (e.hi > 0) out.push_back(e);
  return out;
}

}  // namespace

std::vector<std::string> DrawnFringeEffects() {
  std::vector<std::string> out;
  for (const EffectRange& e : DrawnEffects()) out.push_back(e.name);
  return out;
}

HiddenFringeDraw DrawHiddenFringeEffect(std::uint64_t seed) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), 0xF81E6Eu};
  std::mt19937_64 rng(seq);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  HiddenFringeDraw d;
  d.seed = seed;
  if (unit(rng) < 1.0 / 3.0) return d;
  const std::vector<EffectRange> drawn = DrawnEffects();
  const int n = static_cast<int>(drawn.size());
  const EffectRange& e = drawn[std::min(n - 1, static_cast<int>(unit(rng) * n))];
  d.effect = e.name;
  d.magnitude = e.lo + (e.hi - e.lo) * unit(rng);
  if (e.either_sign && unit(rng) < 0.5) d.magnitude = -d.magnitude;
  d.expected = e.visible ? e.name : "none";
  return d;
}

HiddenFringeSet SimulateHiddenFringe(const HiddenFringeDraw& draw) {
  vision::FringeSimulationConfig config = vision::MakeFringePreset("small");
  // Half resolution: the same view on a 320×256 sensor (pixel centres at integers).
  camera::CameraIntrinsics& cam = config.cameras.left;
  cam.fx *= 0.5, cam.fy *= 0.5;
  cam.cx = (cam.cx + 0.5) * 0.5 - 0.5, cam.cy = (cam.cy + 0.5) * 0.5 - 0.5;
  cam.width /= 2, cam.height /= 2;
  config.cameras.right = cam;  // unused: only the left camera is rendered
  config.supersampling = draw.supersampling;
  config.seed = draw.seed;
  config.sensor.full_well_electrons /= draw.camera_gain;
  const FringeLinearCause* registered = nullptr;
  for (const FringeLinearCause& c : RegisteredFringeCauses())
    if (draw.effect == c.info.name) registered = &c;
  if (draw.effect != "none" && registered == nullptr) config.effects.Set(draw.effect, draw.magnitude, "hidden draw");
  // The PSF is the camera's Gaussian blur; with a camera_defocus draw the two add in quadrature.
  if (draw.psf_sigma_px > 0)
    config.effects.Set("camera_defocus", std::hypot(config.effects.camera_defocus, draw.psf_sigma_px), "hidden draw PSF");
  const vision::SimulatedCamera sim = vision::SimulateCamera(config, 0);

  HiddenFringeSet out;
  out.draw = draw;
  out.full_scale = config.sensor.MaxValue();
  vision::FringeManifest& m = out.manifest;
  m.projector_width = config.projector.intrinsics.width;
  m.projector_height = config.projector.intrinsics.height;
  m.direction = vision::FringeDirection::kVertical;
  m.sequence = {config.sequence[0], config.sequence[1]};
  const vision::EffectRealisation truth = vision::RealiseEffects(config, vision::ExpandSequence(config.sequence));
  for (double e : truth.shift_errors_rad) out.shift_errors_deg.push_back(e * 180.0 / 3.14159265358979323846);
  out.gains = truth.gains;
  for (size_t i = 0; i < sim.images.size(); ++i) {
    m.cameras["left"].push_back(std::to_string(i) + ".png");
    cv::Mat f;
    sim.images[i].convertTo(f, CV_32F);
    out.frames.push_back(f);
  }
  if (registered != nullptr) {
    if (!registered->plant)
      throw InputError({"", 0, "HiddenFringeDraw.effect"}, "cause '" + draw.effect + "' cannot be planted");
    FringeSequenceView seq;
    seq.frames = static_cast<int>(out.frames.size());
    const int steps = m.sequence[0].steps;
    for (int k = 0; k < steps; ++k)
      seq.phase_frame.push_back(k), seq.step_shift_rad.push_back(fringe::StepShift(k, steps));
    for (int f = steps; f < seq.frames; ++f) seq.gray_frame.push_back(f);
    registered->plant(seq, draw.magnitude, &out.frames);
  }
  return out;
}

}  // namespace ramtk::diagnose
