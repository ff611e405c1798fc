#include "ramtk/diagnose/engine/model_selection.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace ramtk::diagnose {

int SelectCandidate(std::vector<CandidateFit>* candidates, const SelectionOptions& options) {
  if (candidates->empty()) throw std::invalid_argument("no candidates to select from");
  for (CandidateFit& c : *candidates) {
    const double ms = std::max(c.heldout_rms * c.heldout_rms, 1e-300);
    c.score = c.heldout_count * std::log(ms) + options.penalty_per_parameter * c.num_parameters;
  }
  auto none =
      std::find_if(candidates->begin(), candidates->end(), [](const CandidateFit& c) { return c.effect == kNoEffect; });
  if (none == candidates->end()) throw std::invalid_argument("the current model (cause 'none') must be a candidate");
  const double none_score = none->score;
  std::stable_sort(candidates->begin(), candidates->end(),
                   [](const CandidateFit& a, const CandidateFit& b) { return a.score < b.score; });
  // Implausible candidates (fitted values outside their bounds) keep their scores for the report but
  // go last with no evidence weight: they are never chosen.
  std::stable_partition(candidates->begin(), candidates->end(),
                        [](const CandidateFit& c) { return c.implausible.empty(); });
  const double best = candidates->front().score;
  double total = 0.0;
  for (CandidateFit& c : *candidates)
    total += (c.weight = c.implausible.empty() ? std::exp(-0.5 * (c.score - best)) : 0.0);
  for (CandidateFit& c : *candidates) c.weight /= total;
  if (candidates->front().effect != kNoEffect && none_score - best < options.min_improvement) {
    // Not enough evidence for an extension: the current model stays, with its own weight.
    std::stable_partition(candidates->begin(), candidates->end(),
                          [](const CandidateFit& c) { return c.effect == kNoEffect; });
  }
  return 0;
}

std::vector<int> FoldOfGroup(int num_groups, int num_folds) {
  if (num_folds < 2) throw std::invalid_argument("cross-validation needs at least 2 folds");
  int stride = 1;
  // A stride near the golden ratio of k, coprime to k, spreads neighbouring groups over folds.
  for (int s = std::max(1, static_cast<int>(num_folds * 0.618)); s >= 1; --s)
    if (std::gcd(s, num_folds) == 1) {
      stride = s;
      break;
    }
  std::vector<int> fold(num_groups);
  for (int g = 0; g < num_groups; ++g) fold[g] = (g * stride) % num_folds;
  return fold;
}

}  // namespace ramtk::diagnose
