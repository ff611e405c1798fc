// Internal to the laser diagnosis: a residual model with named parameters, damped Gauss–Newton
// fits of any subset of them, and the cross-validated comparison of candidate extensions.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"

namespace ramtk::diagnose::laser_detail {

struct ResidualModel {
  // Parameter names carry their unit ("beta_deg"); `initial` holds the current model's values
  // (the effects' parameters at their ideal value); `step` the finite-difference step of each.
  std::vector<std::string> names;
  Eigen::VectorXd initial, step;
  // All residuals for a parameter vector (same length for every call).
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> residuals;
  // Plausibility bounds [lo, hi] of each parameter (absolute values; empty = none): a fitted value
  // outside them is evidence against the candidate, which is then never named.
  Eigen::VectorXd lower, upper;
  // Group (cross-validation unit) of each residual.
  std::vector<int> group;
  int num_groups = 0;
};

struct FitResult {
  Eigen::VectorXd params;
  Eigen::VectorXd sigma;  // 1-sigma of every parameter (0 for fixed ones)
  double rms = 0.0;       // over the rows fitted
  bool ok = false;
};

// Fits the parameters `free` (indices) on the rows with use[row] true, starting from `start`.
FitResult Fit(const ResidualModel& model, const std::vector<int>& free, const std::vector<bool>& use,
              const Eigen::VectorXd& start);

// One candidate: the base (nuisance) parameters plus the effect's own.
struct CandidateSpec {
  std::string effect;       // catalogue name or kNoEffect
  std::vector<int> params;  // the effect's parameter indices
};

struct CandidateOutcome {
  CandidateFit fit;
  FitResult full;                 // fitted on all data
  Eigen::VectorXd heldout_resid;  // each residual predicted with its group held out
};

// Fits the candidate on all data and cross-validates it over `num_folds` folds of groups
// (num_folds >= num_groups: leave one group out).
CandidateOutcome EvaluateCandidate(const ResidualModel& model, const std::vector<int>& base, const CandidateSpec& spec,
                                   int num_folds);

double Rms(const Eigen::VectorXd& v);

// Selects among the outcomes (one must be kNoEffect) and fills the diagnosis' cause, parameters,
// confidence, candidates, rms_before/after and excess_removed. The cause stays kNoEffect when no
// structure was found, and is kUnexplained when structure was found but no candidate earns its
// parameters. Returns the index of the chosen outcome in `outcomes`.
int Conclude(const std::vector<CandidateOutcome>& outcomes, double min_improvement, Diagnosis* diagnosis);

// Further effects on top of the named one (outcomes[chosen] of specs[chosen]): adds the remaining
// specs one at a time, each stage choosing by the same rule as the first (the previous stage plays
// kNoEffect), until none earns its parameters. Updates the diagnosis' parameters, sigmas,
// rms_after, excess_removed, findings and candidates (rows "a+b"); returns the final outcome.
// `label` names the held-out RMS in the findings ("leave-one-out RMS", "held-out RMS").
CandidateOutcome AddFurtherEffects(const ResidualModel& model, const std::vector<int>& base,
                                   const std::vector<CandidateSpec>& specs,
                                   const std::vector<CandidateOutcome>& outcomes, int chosen, int num_folds,
                                   double min_improvement, const std::string& label, Diagnosis* diagnosis);

}  // namespace ramtk::diagnose::laser_detail
