#include "ramtk/diagnose/engine/model_selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace ramtk::diagnose {
namespace {

CandidateFit Fit(const std::string& name, int k, double heldout_rms, int n) {
  CandidateFit c;
  c.effect = name;
  c.num_parameters = k;
  c.heldout_rms = heldout_rms;
  c.heldout_count = n;
  return c;
}

TEST(ModelSelection, ClearImprovementWinsAndWeightsSumToOne) {
  std::vector<CandidateFit> c = {Fit(kNoEffect, 0, 0.20, 400), Fit("joint_offset", 1, 0.05, 400),
                                 Fit("link_length_error", 1, 0.15, 400)};
  SelectCandidate(&c);
  EXPECT_EQ(c[0].effect, "joint_offset");
  // Score difference to 'none': 400·ln(0.2²/0.05²) − 2 ≈ 1107: weight of the winner ≈ 1.
  EXPECT_NEAR(c[0].score, 400 * std::log(0.05 * 0.05) + 2, 1e-9);
  double total = 0;
  for (const auto& f : c) total += f.weight;
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_GT(c[0].weight, 0.999);
}

TEST(ModelSelection, MarginalImprovementKeepsTheCurrentModel) {
  // 1% lower held-out RMS on 100 residuals: Δscore = 100·ln(1/0.99²) − 2 ≈ 0.01 < margin.
  std::vector<CandidateFit> c = {Fit("defocus", 1, 0.099, 100), Fit(kNoEffect, 0, 0.100, 100)};
  SelectCandidate(&c);
  EXPECT_EQ(c[0].effect, kNoEffect);
}

TEST(ModelSelection, MissingCurrentModelIsAnError) {
  std::vector<CandidateFit> c = {Fit("defocus", 1, 0.1, 100)};
  EXPECT_THROW(SelectCandidate(&c), std::invalid_argument);
}

TEST(ModelSelection, FoldsAreBalancedAndSpreadNeighbours) {
  const std::vector<int> fold = FoldOfGroup(90, 5);
  std::vector<int> count(5, 0);
  for (int f : fold) ++count[f];
  for (int n : count) EXPECT_EQ(n, 18);
  for (size_t g = 1; g < fold.size(); ++g) EXPECT_NE(fold[g], fold[g - 1]);
}

TEST(ModelSelection, ExcessRemovedClosedForm) {
  // before² − floor² = 0.25 − 0.01; after² − floor² = 0.0125 − 0.01 → removed = 0.2275 / 0.24.
  EXPECT_NEAR(ExcessRemoved(0.5, std::sqrt(0.0225), 0.1), (0.25 - 0.0225) / 0.24, 1e-12);
  EXPECT_EQ(ExcessRemoved(0.1, 0.1, 0.2), 0.0);
}

}  // namespace
}  // namespace ramtk::diagnose
