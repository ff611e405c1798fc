#pragma once
// Screening of the drift parameters (thesis §3.2, Fig. 3-5, Table 5-1).
//
// Start with every candidate parameter. Repeat until `keep` remain (or, when the count is chosen
// from the data, down to `min_keep`):
//  (2) identify the current set for every cycle (eq. 3-8) and score it with λ;
//  (3) test each parameter's series over the cycles with the sample autocorrelation function:
//      a series whose autocorrelations stay inside ±z/√N is steady (noise around zero, Fig. 3-4),
//      one that stays correlated drifts (Fig. 3-3). The steady ones form S;
//  (4) try removing each s in S; the first removal that does not lower λ is taken (thesis), or,
//      if every removal lowers λ, the one with the highest λ.
// If S is empty the step falls back to trying every current parameter (reported).
//
// Kept count (keep = 0, the default): every set on the elimination path is scored by its held-out
// error over the ball poses (leave one pose out: identify ΔX per cycle from the other poses and
// predict the left-out pose's centre differences). The smallest set whose held-out error is not
// worse than the best set's by more than `heldout_z` standard errors of the paired per-pose
// differences is kept: the same rule `ramtk diagnose` uses to tell candidates apart. A set that
// keeps a parameter which does not drift only adds identification noise to the prediction; a set
// that drops one which drifts leaves its drift in the held-out error.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/core/termination.h"
#include "ramtk/thermal/monitoring.h"

namespace ramtk::thermal {

struct AcfOptions {
  // Largest lag tested; 0: min(20, N/4).
  int max_lag = 0;
  // Half-width of the white-noise band in units of 1/√N (1.96: 95 %).
  double z = 1.96;
  // A series is steady when at most this share of the lags 1..max_lag fall outside the band.
  double max_fraction_outside = 0.3;
  std::string Validate() const;
};

struct AcfResult {
  std::vector<double> acf;  // r_1 .. r_max_lag
  double band = 0.0;        // z/√N
  int outside = 0;          // lags with |r_k| > band
  bool steady = false;
};

// Sample autocorrelation r_k = Σ (x_t − x̄)(x_{t+k} − x̄) / Σ (x_t − x̄)² and the band test.
AcfResult AutocorrelationTest(const Eigen::VectorXd& series, const AcfOptions& options = {});

struct ScreeningOptions {
  // Parameters left at the end. 0: chosen by held-out error along the elimination path (see
  // above). The thesis fixed it at 8.
  int keep = 0;
  // With keep = 0: the smallest set tried (the path runs down to it).
  int min_keep = 1;
  // With keep = 0: a smaller set is preferred while its mean per-pose held-out squared error
  // exceeds the best set's by at most this many standard errors of the paired differences.
  double heldout_z = 1.0;
  std::vector<int> candidates;           // initial set; empty: every free parameter (24 for the KR150)
  IdentificationOptions identification;  // poses (all 20 in the thesis) and SVD settings; params ignored
  LambdaOptions lambda;
  AcfOptions acf;
  // Thesis step (4): take the first removal whose λ does not drop. false: try every removal and
  // take the highest λ, ties broken by the lower RMS monitoring residual (λ moves in steps of one
  // direction, so ties are common once it saturates).
  bool first_improvement = true;
  ProgressCallback progress;  // called once per elimination step
  // The guard (CheckIdentifiability) every set on the path is scored with. The kept count chosen
  // by held-out error only considers identifiable sets; the selected set must pass (with
  // identifiability.reduce, the parameters of its unobservable combinations are dropped),
  // otherwise the screening ends with kNoResult.
  IdentifiabilityOptions identifiability;
  std::string Validate() const;
};

// One row of Table 5-1.
struct ScreeningStep {
  int card = 0;                  // parameters in the set
  int removed = -1;              // parameter removed to reach this set (-1 for the first row)
  double lambda = 0.0;           // % for this set
  std::vector<int> steady;       // the steady set S found for this set
  bool steady_fallback = false;  // S was empty; every parameter was tried
  // Leave-one-pose-out error of this set (mm, RMS per coordinate over poses and warm ball
  // cycles); 0 when not computed (fixed keep) or too few poses to leave one out.
  double heldout_rms_mm = 0.0;
  // (mean paired per-pose squared-error difference to the best set) / its standard error; 0 for
  // the best set itself.
  double heldout_z = 0.0;
  // Condition number of this set's column-scaled identification matrix, and whether it is at or
  // under the guard's limit.
  double condition_number = 0.0;
  bool identifiable = false;
};

struct ScreeningSummary {
  // kSuccess, kPartial (the selected set was reduced by the guard), kNoResult (the selected set is
  // not identifiable; nothing to use) or kCancelled
  Termination termination = Termination::kNotRun;
  std::string message = "not run";  // "kept n", "kept n (held-out)", "cancelled", the guard's refusal
  int iterations = 0;                              // elimination steps
  int lambda_evaluations = 0;
  double initial_lambda = 0.0;  // % with every candidate
  double final_lambda = 0.0;    // % with the selected set
  std::vector<ScreeningStep> steps;
  std::vector<int> selected;
  bool count_from_heldout = false;   // the kept count was chosen by held-out error (keep = 0)
  int best_heldout_card = 0;         // size of the set with the lowest held-out error
  Eigen::MatrixXd selected_delta_x;  // 30 × monitoring cycles, identified with `selected`
  // 30 × ball cycles identified with every candidate: the per-parameter curves of Figs. 3-3/3-4
  // that the first autocorrelation test looks at.
  Eigen::MatrixXd initial_delta_x;
  // The guard on the selected set (with the screening's poses).
  IdentifiabilitySummary identifiability;
  std::string BriefReport() const;
};

ScreeningSummary ScreenParameters(const ThermalExperiment& experiment, const ScreeningOptions& options);

// Leave-one-pose-out squared error per pose (mean over the warm ball cycles and 3 coordinates,
// mm²) of identifying `options.params` from `options.poses` (empty: all). NaN entries when fewer
// than enough poses remain to identify the set without the left-out one.
Eigen::VectorXd HeldoutPoseErrors(const ThermalExperiment& experiment, const IdentificationOptions& options);

// Table 5-1 as text: card, removed parameter, λ, steady set S (and held-out error when chosen by it).
std::string FormatEliminationTable(const ScreeningSummary& summary);

// One row of Table 5-2: λ before compensation and with several parameter sets.
struct ComparisonRow {
  std::string label;               // "before", "traditional", "screened", "all"
  std::vector<int> params;         // empty for "before"
  int num_poses = 0;               // ball poses used
  double lambda = 0.0;             // %
  double rms_residual_mm = 0.0;    // RMS of all monitoring residuals (warm cycles)
  double worst_residual_mm = 0.0;  // largest |residual|
};
std::vector<ComparisonRow> CompareParameterSets(const ThermalExperiment& experiment,
                                                const std::vector<std::pair<std::string, std::vector<int>>>& sets,
                                                const IdentificationOptions& id, const LambdaOptions& lambda);
std::string FormatComparisonTable(const std::vector<ComparisonRow>& rows);

}  // namespace ramtk::thermal
