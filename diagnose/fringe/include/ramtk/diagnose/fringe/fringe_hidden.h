// Hidden-effect draws for testing the fringe diagnosis: from a seed, one catalogue fringe effect
// (or none) with a random realistic magnitude, rendered by the vision simulator into a small
// (320×256, left camera) fringe set whose truth is recorded.
// A simulator, public on purpose: the tests use it to require that the diagnosis finds what was
// hidden, and users use it to check the diagnosis on their own model and set-up before trusting it
// on measured data (docs/diagnose.md, "Hidden-effect simulators").
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::diagnose {

struct HiddenFringeDraw {
  std::uint64_t seed = 1;
  std::string effect = "none";    // catalogue name or "none"
  double magnitude = 0.0;         // in the simulator's unit of that effect (fringe_simulator.h)
  std::string expected = "none";  // the cause a correct diagnosis names: the effect, or "none" for
                                  // effects the ideal intensity model cannot see (ambient light,
                                  // unmodelled lens distortion)
  double camera_gain = 1.0;       // DN per photo-electron relative to the default sensor (the full
                                  // well is divided by it): shot-noise variance b·I grows with it
  int supersampling = 2;          // n×n rays per camera pixel: 1 point sampling, n > 1 a box of fill 1
  double psf_sigma_px = 0.0;      // camera PSF (Gaussian std dev, camera px) rendered on top of the
                                  // pixel's sampling, in addition to any camera_defocus draw
};

// Draw for `seed`: "none" with probability 1/3, else uniformly one of the fringe cause table's rows
// that carry a magnitude range (ramtk/diagnose/engine/fringe_causes.def).
HiddenFringeDraw DrawHiddenFringeEffect(std::uint64_t seed);
// The names DrawHiddenFringeEffect draws from, in table order.
std::vector<std::string> DrawnFringeEffects();

struct HiddenFringeSet {
  HiddenFringeDraw draw;
  vision::FringeManifest manifest;  // in memory (path "")
  std::vector<cv::Mat> frames;      // CV_32FC1, DN
  double full_scale = 255.0;
  std::vector<double> shift_errors_deg;  // truth: phase-step error of each frame (0 for Gray code)
  std::vector<double> gains;             // truth: camera gain of each frame (intensity drift)
};

// Renders the draw: the simulator's "small" rig at half resolution (320×256), 8-bit, SLMaster
// sequence (12-step phase shift, 64 periods, 7-bit complementary Gray code), the draw's supersampling
// (default 2) and PSF.
// A cause registered with RegisterFringeCause (extra_cause.h) is rendered without it and then
// planted into the frames by its plant function.
HiddenFringeSet SimulateHiddenFringe(const HiddenFringeDraw& draw);

}  // namespace ramtk::diagnose
