// Hidden-effect generator for the laser diagnosis: from a seed, one observable laser effect of the
// catalogue (or none, probability 1/3) with a realistic random magnitude, hidden in a log built by
// the TCF device simulator, with the truth recorded.
//
// Drawn: beam_non_perpendicular, beam_offset, beam_width, trigger_latency, speed_variation (scale
// error only; the simulator's speed ripple is switched off because the diagnosis does not model it).
// Not drawn: sensor_plane_tilt (a 0.1–0.5° tilt of the beam plane moves the crossings by a few µm
// with the ~3° tool tilt of the programme — below the robot's 0.03 mm repeatability, so the
// diagnosis answers "none" by design) and tool_axis_rotation (a rotationally symmetric tool
// turned about its own axis changes no event at all).
// A simulator, public on purpose: the tests use it to require that the diagnosis finds what was
// hidden, and users use it to check the diagnosis on their own model and set-up before trusting it
// on measured data (docs/diagnose.md, "Hidden-effect simulators").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/tcf/simulator.h"

namespace ramtk::diagnose {

struct HiddenLaserEffect {
  std::string effect;     // catalogue name or "none"
  std::string parameter;  // what `magnitude` is, with its unit ("beta_deg", "latency_ms"...)
  double magnitude = 0.0;
  tcf::TcfSimulationOptions options;  // what was simulated (seed, tool, effects)
  tcf::TcfSimulation simulation;      // the log, the programme, the calibrated frame, the truth
};

// The effects the generator draws from (besides "none"): the rows of the laser cause table
// (ramtk/diagnose/engine/laser_causes.def) marked drawn, in table order.
std::vector<std::string> DrawnLaserEffects();

HiddenLaserEffect DrawHiddenLaserEffect(std::uint64_t seed);

}  // namespace ramtk::diagnose
