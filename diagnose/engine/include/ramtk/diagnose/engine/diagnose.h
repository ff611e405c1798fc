// Entry point of `ramtk diagnose`: the options every data kind shares, and the detection of the
// kind from the file. Each kind's analysis lives in its own header with the fixed signature
//   Diagnosis Diagnose<Kind>(const DiagnoseOptions& options);
// (robot.h: DiagnoseRobot, fringe.h: DiagnoseFringe, laser.h: DiagnoseLaser).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/diagnose/engine/diagnosis.h"

namespace ramtk::diagnose {

struct DiagnoseOptions {
  // The measured data: a fringe-set manifest (JSON), robot measurements (CSV with q1..q6,x,y,z),
  // a laser device log (CSV time_s,beam,state) or sensor-frame calibration points (label,x,y,z).
  std::string data;
  // The current model: a robot model YAML, a stereo calibration, a sensor-frame JSON... Empty: the
  // kind's default (documented by each kind).
  std::string model;
  // Further inputs a kind needs, e.g. the programmed-motion JSON of a laser log or the thermal
  // set-up JSON of ball measurements. Each kind documents which it reads.
  std::vector<std::string> with;
  // Folder for the report, the JSON and the pictures (created). Empty: no files written.
  std::string output_folder;
  // Cross-validation folds over the kind's natural groups (cycles, poses, image regions, circles).
  int folds = 5;
  // Expected noise standard deviation of one residual in the data's unit; 0 = the kind's default
  // or an estimate from the data (the report says which).
  double noise = 0.0;
  // Significance level of the structure tests after the Holm correction.
  double alpha = 1e-3;
  // Seed of anything random (simulated re-draws, region sampling); recorded in the report.
  uint64_t seed = 1;
  ProgressCallback progress;

  // "" when usable, else the first problem as `field: what is wrong`.
  std::string Validate() const;
};

// Which kind of data a file holds, from its extension and header; throws InputError naming the
// file when it is none of them.
DataKind DetectKind(const std::string& path);

}  // namespace ramtk::diagnose
