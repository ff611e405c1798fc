// Hidden-effect generator for the robot diagnosis: from a seed, draws one robot effect of the
// catalogue (or none, probability ~1/3) with a random realistic magnitude, hides it in ball
// measurements simulated like the thesis experiment (thermal::SimulateThermal, smaller), and
// records the truth. The diagnosis then gets the nominal model and the true set-up, as after
// `ramtk simulate thermal`.
// A simulator, public on purpose: the tests use it to require that the diagnosis finds what was
// hidden, and users use it to check the diagnosis on their own model and set-up before trusting it
// on measured data (docs/diagnose.md, "Hidden-effect simulators").
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ramtk/diagnose/robot/robot.h"

namespace ramtk::diagnose {

struct HiddenRobotOptions {
  int cycles = 16;                // measurement cycles
  int poses = 15;                 // ball poses per cycle
  double cycle_period_s = 300.0;  // 16 × 5 min: the first 80 min of the thesis's warm-up
  double none_probability = 1.0 / 3.0;
  std::string effect;  // "": drawn (none with none_probability, else a drawn cause); else this cause
                       // is planted (a table row that plants itself, or a registered cause)
  std::string Validate() const;  // empty if valid
};

struct HiddenRobotDraw {
  std::uint64_t seed = 0;
  std::string effect;                   // catalogue name or kNoEffect
  std::string description;              // one line: what was hidden, with its magnitude
  std::map<std::string, double> truth;  // the hidden parameters (units in the key)
  RobotDiagnoseInput input;             // data + current (nominal) model + set-up
};

// The causes DrawHiddenRobotEffect draws from (besides none): the robot cause table's rows that
// plant themselves, in table order.
std::vector<std::string> DrawnRobotEffects();

// `model` is the nominal robot (KR150-like: base Z up). InputError on invalid options.
HiddenRobotDraw DrawHiddenRobotEffect(const kinematics::RobotModel& model, std::uint64_t seed,
                                      const HiddenRobotOptions& options = {});

// Three static errors at once, as on a real robot: one joint zero (θ2..θ5, 0.01–0.03°), one link
// length (a1 a2 a3 d4, 0.3–1 mm) and one axis twist (α2..α4, 0.01–0.03°), measured by a tracker
// over the workspace (`poses` random joint sets within ±150°, 10 µm noise, one cycle; the set-up
// is the simulator's). `effect` lists the three catalogue names joined by '+', `truth` their values.
HiddenRobotDraw DrawHiddenGeometricErrors(const kinematics::RobotModel& model, std::uint64_t seed, int poses = 120);

}  // namespace ramtk::diagnose
