// Private to the robot diagnosis: the catalogue's robot effects as linear extensions of the current
// model, each fitted and cross-validated (robot_candidates.cpp).
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/diagnosis.h"
#include "robot_linear.h"

namespace ramtk::diagnose::robot_detail {

struct Context {
  const RobotDiagnoseInput* input = nullptr;
  const RowSet* rows = nullptr;
  std::vector<int> fold_of_row;
  int folds = 5;
  double sigma = 0.025;         // noise per coordinate, mm
  double min_improvement = 10;  // score margin for adding a drift parameter (greedy selection)
  Design base;                  // the current model
  CvResult base_cv;
  ProgressCallback progress;
};

// One evaluated candidate: its fit summary plus what the report needs.
struct Evaluated {
  CandidateFit fit;
  Design design;
  CvResult cv;
  std::vector<int> added_cycle_params;  // ParamVector indices whose drift is fitted beyond the current model
  Eigen::MatrixXd added_series;         // their drift per cycle (rows; µrad for angles, mm for lengths)
  std::string note;                     // e.g. why skipped, which parameters were added
};

// The current model: nuisance set-up plus the input's per-cycle thermal parameters.
Design CurrentModelDesign(const RobotDiagnoseInput& in, const RowSet& rs);

// Every applicable candidate of the catalogue (skipped ones are left out, with a note line in
// `notes`).
std::vector<Evaluated> EvaluateCandidates(const Context& ctx, std::vector<std::string>* notes);

}  // namespace ramtk::diagnose::robot_detail
