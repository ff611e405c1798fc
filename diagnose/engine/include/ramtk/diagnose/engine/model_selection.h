// Choosing among candidate extensions by held-out error with a penalty for extra parameters.
#pragma once

#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"

namespace ramtk::diagnose {

struct SelectionOptions {
  // Penalty per extra parameter, in units of the score (Akaike-like: 2 per parameter on the
  // −2·log-likelihood scale of the held-out residuals).
  double penalty_per_parameter = 2.0;
  // A candidate other than kNoEffect is chosen only if its score beats kNoEffect's by at least
  // this margin (a guard against false alarms on clean data).
  double min_improvement = 10.0;
};

// Scores every candidate: score = n·ln(heldout_rms²) + penalty·k, with n = heldout_count and k =
// num_parameters; weight = exp(−Δscore/2) normalised over the candidates. Sorts best first and
// returns the index (after sorting, i.e. 0) of the chosen candidate; the candidate named kNoEffect
// must be present and wins unless another beats it by `min_improvement`.
int SelectCandidate(std::vector<CandidateFit>* candidates, const SelectionOptions& options = {});

// K-fold assignment of `num_groups` groups (cycles, poses, image regions) to folds, deterministic:
// group g goes to fold (g · stride) mod k with a stride coprime to k so neighbours are spread.
std::vector<int> FoldOfGroup(int num_groups, int num_folds);

}  // namespace ramtk::diagnose
