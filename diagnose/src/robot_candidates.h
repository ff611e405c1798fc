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

// ---- identifiability (robot_identify.cpp) ----

// Mean share of the columns `extended` adds to `base` that lies in the span of the base columns
// (pooled over rows, per-cycle columns pooled as static): 1 = the current model absorbs it.
double AbsorbedShare(const Design& base, const Design& extended);
// Is `extended` nested in `container`? The columns of `extended` from (first_stat, first_cycle) on,
// with their part in the common base (the columns before) removed: mean share of what remains
// that lies in the span of `container` (≈ 1: nested).
double NestedShare(const Design& container, const Design& extended, int first_stat, int first_cycle);

// A candidate's fitted correction (3n, pooled): base residual − candidate residual, full fits. It
// lies outside what the base absorbs, so the angle between two signatures says how alike two
// candidates look in these data.
Eigen::VectorXd Signature(const std::vector<Row>& rows, const Design& base, const Fit& base_fit, const Design& d,
                          const Fit& f);

// Held-out difference of two candidates in units of its cross-validation scatter: Σ(|a|² − |b|²)
// over rows, divided by the standard error from per-pose sums (poses are the independent units).
// Negative: `a` predicts better.
double HeldoutDifferenceZ(const RowSet& rs, const std::vector<Eigen::Vector3d>& a,
                          const std::vector<Eigen::Vector3d>& b);

// What data would separate candidates whose signatures differ by `difference` (3n): the joint
// along which they part most and where, plus a temperature column / payload change when relevant.
std::string SeparatingData(const RowSet& rs, const Eigen::VectorXd& difference, const std::vector<std::string>& effects);

}  // namespace ramtk::diagnose::robot_detail
