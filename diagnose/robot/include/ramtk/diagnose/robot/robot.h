// `ramtk diagnose` for robot/ball measurements (DESIGN.md "Robot measurements"): the ball centre
// measured by a fixed sensor against eq. (3-1) with the current model
//   ball_in_sensor = sensor_from_base · base_from_flange(q; X0 [+ ΔX_cycle]) · ball_in_flange.
// The current model is the robot model file, the cell set-up (sensor_from_base, ball_in_flange; a
// JSON from `ramtk simulate thermal`, or calibrated from the first cycle when absent, and always
// refitted as a nuisance) and optionally a per-cycle thermal drift of a parameter set
// ("thermal=traditional": the thesis's length-only model). The candidates of the effect catalogue
// are linear extensions of that model (docs/diagnose_robot.md), scored by cross-validation over
// the poses (every cycle stays in the training set so per-cycle drift can be fitted).
//
// Inputs through DiagnoseOptions:
//   data     ball measurements CSV (cycle,time_s,pose,q1..q6,x,y,z[,extra...])
//   model    robot YAML path, or a bundled name: kr150, bx200l, ur10 (default kr150)
//   with     *.json: thermal set-up; *.csv: monitoring points (λ of thesis §3.2 is then reported);
//            thermal=traditional | thermal=<comma list of parameters>: per-cycle drift in the current model
//   noise    σ per coordinate (mm); 0: estimated from successive cycles of the same pose, or 0.025 mm
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnose.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/measurements_io.h"
#include "ramtk/kinematics/robot_model.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::diagnose {

// Everything the robot diagnosis reads, in memory (the hidden-effect generator fills it directly).
struct RobotDiagnoseInput {
  kinematics::RobotModel model;  // current (cold) model
  // The same robot file with its optional gravity-load data (link masses, centres of mass,
  // payload): the compliance candidate's torques come from it when it has masses.
  kinematics::RobotChain chain;
  std::string model_label;       // for the report
  thermal::ThermalSetup setup;   // used when has_setup; otherwise calibrated from the first cycle
  bool has_setup = false;
  kinematics::RobotMeasurementSet ball;        // kind kBall
  std::string ball_path;                       // for messages and the report
  kinematics::RobotMeasurementSet monitoring;  // kind kMonitoring; used when has_monitoring
  bool has_monitoring = false;
  std::string monitoring_path;
  // Parameters whose drift the current model fits per cycle (ParamVector indices; empty: a static
  // model) and how the user named them ("traditional").
  std::vector<int> thermal_params;
  std::string thermal_label;
};

// Parses options.model / options.with and reads the files. InputError names the file or option.
RobotDiagnoseInput ReadRobotDiagnoseInput(const DiagnoseOptions& options);

// Resolves a bundled robot name (kr150, bx200l, ur10) or returns the path unchanged.
std::string ResolveRobotModelPath(const std::string& name_or_path);

// The analysis on in-memory data (writes pictures into options.output_folder when set).
Diagnosis DiagnoseRobotData(const RobotDiagnoseInput& input, const DiagnoseOptions& options);

// The entry point of `ramtk diagnose` for robot data.
Diagnosis DiagnoseRobot(const DiagnoseOptions& options);

}  // namespace ramtk::diagnose
