// Private to the robot diagnosis: the code behind each row of the robot cause table
// (ramtk/diagnose/engine/robot_causes.def): how it is fitted as a linear extension of the current
// model and how the hidden-effect generator plants it. One RobotCauseCode per row, defined in
// causes/*.cpp; RobotCauses() joins the table's rows with their code, then the causes registered at
// run time (ramtk/diagnose/robot/extra_cause.h).
#pragma once

#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "ramtk/diagnose/robot/extra_cause.h"
#include "ramtk/diagnose/robot/robot_hidden.h"
#include "ramtk/thermal/simulator.h"
#include "robot_candidates.h"

namespace ramtk::diagnose::robot_detail {

// A parameter value in the findings' text (%.4g).
inline std::string Fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}

// Where a cause's fit puts what it finds.
struct CauseOutput {
  std::vector<Evaluated>* evaluated;  // one entry per candidate it offers (none when not testable)
  std::vector<std::string>* notes;    // why it was skipped or what it left out
};

// The hidden-effect generator's random draws, in the order the generator has always used them.
struct HiddenRandom {
  std::mt19937_64* rng;
  double U01();                     // uniform in [0, 1)
  double Uniform(double a, double b);
  double Sign();                    // ±1
  int Pick(int n);                  // uniform in 0..n-1
  Eigen::Vector3d Unit();           // uniform direction
};

// What a cause sees while it is planted: before the simulation it changes the true robot or the
// simulator's drifts; after it, the simulated measurements.
struct PlantContext {
  HiddenRandom random;
  const HiddenRobotOptions* options = nullptr;
  const kinematics::RobotModel* model = nullptr;         // the nominal robot the diagnosis gets
  kinematics::RobotModel* truth = nullptr;               // before: the robot that is simulated
  thermal::ThermalSimOptions* sim = nullptr;             // before: the simulator's options
  std::vector<thermal::ParamDrift> preset_drifts;        // the thesis preset's drifts
  thermal::ThermalSimResult* result = nullptr;           // after: the simulated measurements
  HiddenRobotDraw* draw = nullptr;                       // truth and description to fill
};

struct RobotCauseCode {
  int min_cycles = 1;         // fitted only on data with at least this many cycles
  const char* skip_note = "";  // the note when skipped for too few cycles ("" none)
  bool drift = false;          // changes with time: a static cause that predicts as well is preferred
  // Fits the cause; nullptr when another row's function fits it together with its own.
  void (*fit)(const Context& ctx, CauseOutput out) = nullptr;
  // The hidden-effect generator plants it: before and after the simulation (nullptr: not drawn).
  void (*plant_before)(PlantContext* p) = nullptr;
  void (*plant_after)(PlantContext* p) = nullptr;
};

struct RobotCause {
  std::string name;  // catalogue name
  RobotCauseCode code;
  std::shared_ptr<const RobotColumnCause> extra;  // a registered cause (code then only carries `drift`)
};

// Fits a registered cause: its columns, the identifiable ones kept.
void FitExtraCause(const Context& ctx, CauseOutput out, const RobotColumnCause& cause);

// The table's rows in order, then the registered causes.
const std::vector<RobotCause>& RobotCauses();
// The code of a cause by name (nullptr when unknown).
const RobotCauseCode* FindRobotCause(const std::string& name);

// The code of every table row (causes/*.cpp), declared from the table.
#define RAMTK_ROBOT_CAUSE(name, code, parameters, plausible, help) extern const RobotCauseCode code;
#include "ramtk/diagnose/engine/robot_causes.def"

}  // namespace ramtk::diagnose::robot_detail
