// Private to the robot diagnosis: the catalogue's robot effects as linear extensions of the current
// model, each fitted and cross-validated (robot_candidates.cpp).
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"
#include "ramtk/diagnose/robot/detail/robot_linear.h"

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

// Every applicable cause of the robot cause table and the registered ones, in table order
// (skipped ones are left out, with a note line in `notes`); one progress step per cause fitted.
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

// ---- several causes, static before drift, plausibility (robot_multicause.cpp) ----

// Physical bounds of fitted values, scaled by the robot (reach = Σ|a| + |d|).
struct PlausibilityBounds {
  double length_mm = 5.0;    // static length error: max(2 mm, 0.5% of the reach)
  double angle_deg = 1.0;    // static joint offset or axis twist
  double cyclic_deg = 0.5;   // amplitude of a joint's cyclic error
  double drift_mm = 1.0;     // range of a length's thermal drift: max(1 mm, 0.1% of the reach)
  double drift_deg = 0.1;    // range of an angle's thermal drift
  double tool_mm = 20.0;     // a ball that moved on the flange: max(20 mm, 5% of the reach)
};
PlausibilityBounds BoundsFor(const kinematics::RobotModel& model);
// Appends to fit->implausible every fitted value outside its bounds (a negative compliance beyond 3σ too).
void CheckPlausibility(const PlausibilityBounds& bounds, CandidateFit* fit);

// Drift causes (their RobotCauseCode::drift): thermal, temperature-driven, sensor frame drift, a ball that moved.
bool IsDriftEffect(const std::string& effect);
// When the best candidate (front, after SelectCandidate) is a drift and the best static candidate
// predicts the held-out poses as well (within 2 standard errors), moves the static one to the front
// and returns the finding that says so; "" otherwise.
std::string PreferStatic(const RowSet& rs, const std::vector<Evaluated>& evaluated, std::vector<CandidateFit>* candidates);

// When the whole static calibration ('geometric') is in front and the best-scoring other candidate
// pays on its own (beats 'none' by min_improvement), moves that one to the front: a specific name
// comes first, 'geometric' mops up what remains.
std::string PreferSpecific(std::vector<CandidateFit>* candidates, double min_improvement);

// Forward selection from a first cause: each step refits the candidates on top of the causes kept,
// adds the best plausible one (static before drift) while it beats the current model by the score
// margin and removes a tenth of the excess left above the noise floor, until `explained_share` of
// the excess is removed, the residual reaches the floor or nothing pays. `last` receives the final
// model. The steps carry their own held-out gains.
std::vector<CauseStep> ForwardSelect(const Context& ctx, const Evaluated& first, double rms_none, double sigma,
                                     double explained_share, const PlausibilityBounds& bounds,
                                     std::vector<std::string>* findings, Evaluated* last);

}  // namespace ramtk::diagnose::robot_detail
