// Screening (§3.2, Tables 5-1/5-2) against the simulator's drifting set; λ and ACF closed forms.
#include "ramtk/thermal/screening.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using testing::Kr150;
using testing::Thesis;

TEST(ThermalAcf, ClosedForms) {
  // Alternating ±1: r_k = (−1)^k (n − k)/n.
  Eigen::VectorXd alt(40);
  for (int i = 0; i < 40; ++i) alt[i] = (i % 2 == 0) ? 1.0 : -1.0;
  AcfOptions o;
  o.max_lag = 3;
  const AcfResult r = AutocorrelationTest(alt, o);
  ASSERT_EQ(r.acf.size(), 3u);
  EXPECT_NEAR(r.acf[0], -39.0 / 40.0, 1e-12);
  EXPECT_NEAR(r.acf[1], 38.0 / 40.0, 1e-12);
  EXPECT_NEAR(r.band, 1.96 / std::sqrt(40.0), 1e-12);
  EXPECT_FALSE(r.steady);
  // A linear trend stays correlated: drifting.
  Eigen::VectorXd trend = Eigen::VectorXd::LinSpaced(90, 0.0, 1.0);
  EXPECT_FALSE(AutocorrelationTest(trend).steady);
  // White noise: at most a few lags outside the 95 % band in 20 series of 90.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01(0, 1);
  int steady = 0;
  for (int s = 0; s < 20; ++s) {
    Eigen::VectorXd w(90);
    for (int i = 0; i < 90; ++i) w[i] = n01(rng);
    steady += AutocorrelationTest(w).steady ? 1 : 0;
  }
  EXPECT_GE(steady, 19);
}

TEST(ThermalLambda, CountsDirectionsBelowTheThreshold) {
  // 2 points = 6 directions, reference column + 2 warm cycles.
  Eigen::MatrixXd r(6, 3);
  r << 0, 0.05, 0.05,  // RMS 0.05: pass
      0, 0.2, 0.0,     // RMS 0.141: fail; max 0.2 fail
      0, 0.09, -0.09,  // RMS 0.09 pass, max 0.09 pass
      0, 0.13, 0.0,    // RMS 0.092 pass, max 0.13 fail
      0, 0.0, 0.0,     // pass
      0, 0.3, 0.3;     // fail
  LambdaOptions o;
  EXPECT_NEAR(Lambda(r, o), 100.0 * 4 / 6, 1e-12);
  o.statistic = LambdaStatistic::kMax;
  EXPECT_NEAR(Lambda(r, o), 100.0 * 3 / 6, 1e-12);
}

// The acceptance test over 3 runs (thesis Table 5-2 repeated the test 3 times):
// screening recovers the simulator's drifting set (lengths and angles α3, α4, β2) and λ(screened)
// ≥ 95 %, reported beside the traditional non-zero-length set and "all".
class ThermalScreening : public ::testing::TestWithParam<int> {};

TEST_P(ThermalScreening, RecoversTheDriftingSetAndBeatsTheTraditionalSet) {
  const auto& e = Thesis(GetParam());
  ScreeningOptions so;  // thesis: 24 candidates, keep 8, 20 poses, 0.1 mm
  so.keep = 8;
  const ScreeningSummary s = ScreenParameters(e.experiment, so);
  ASSERT_EQ(s.selected.size(), 8u);
  ASSERT_EQ(s.steps.size(), 17u);  // 24 → 8, one row per set size as in Table 5-1
  EXPECT_EQ(s.steps.front().card, 24);
  EXPECT_EQ(s.steps.back().card, 8);
  int hits = 0;
  for (int p : s.selected) {
    for (int t : e.sim.drifting_params) hits += (p == t) ? 1 : 0;
  }
  const double precision = static_cast<double>(hits) / s.selected.size();
  const double recall = static_cast<double>(hits) / e.sim.drifting_params.size();
  ::testing::Test::RecordProperty("precision", std::to_string(precision));
  ::testing::Test::RecordProperty("recall", std::to_string(recall));
  EXPECT_GE(precision, 7.0 / 8.0) << ParamListToString(s.selected);
  EXPECT_GE(recall, 7.0 / 8.0) << ParamListToString(s.selected);
  // Angles are selected, not only lengths: at least two of the thesis's α3, α4, β2 (α4's wrist
  // tilt is the smallest drift at the ball and trades places with α5 in some runs).
  int angles = 0;
  for (int p : s.selected) {
    const std::string name = kinematics::ParamName(p);
    angles += (name == "alpha3" || name == "alpha4" || name == "beta2") ? 1 : 0;
  }
  EXPECT_GE(angles, 2) << ParamListToString(s.selected);
  const auto rows = CompareParameterSets(
      e.experiment,
      {{"traditional", TraditionalParams(Kr150())}, {"screened", s.selected}, {"all", Kr150().FreeParams()}}, {},
      so.lambda);
  ASSERT_EQ(rows.size(), 4u);
  const double before = rows[0].lambda, traditional = rows[1].lambda, screened = rows[2].lambda;
  ::testing::Test::RecordProperty("lambda_before", std::to_string(before));
  ::testing::Test::RecordProperty("lambda_traditional", std::to_string(traditional));
  ::testing::Test::RecordProperty("lambda_screened", std::to_string(screened));
  std::cout << "seed " << GetParam() << ": " << s.BriefReport() << "\n" << FormatComparisonTable(rows);
  // Issue: λ(screened) ≥ 95 %; thesis Table 5-2: screened > traditional > before.
  EXPECT_GE(screened, 95.0);
  EXPECT_GT(screened, traditional);
  EXPECT_GT(traditional, before);
  EXPECT_NEAR(screened, s.final_lambda, 1e-9);
  // The monitoring residual with the screened set is at the measurement-noise floor: with the
  // true drift it would be √2·√(σ_tool² + σ_rep²) per coordinate, plus identification noise.
  const double floor =
      std::sqrt(2.0 * (std::pow(e.options.tool_sensor_noise_mm, 2) + std::pow(e.options.repeatability_mm, 2)));
  EXPECT_LT(rows[2].rms_residual_mm, 1.6 * floor);
  EXPECT_GT(rows[1].rms_residual_mm, rows[2].rms_residual_mm);
}

INSTANTIATE_TEST_SUITE_P(ThreeRuns, ThermalScreening, ::testing::Values(1, 2, 3));

// The same screened set at the production budget of 6 D-optimal poses (§5.1: "only 6 poses").
TEST(ThermalScreeningBudget, SixPosesKeepLambdaHigh) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  IdentificationOptions id;
  id.poses = SelectPoses(dm, e.sim.drifting_params, 6);
  const auto rows = CompareParameterSets(e.experiment, {{"screened", e.sim.drifting_params}}, id, LambdaOptions{});
  EXPECT_EQ(rows[1].num_poses, 6);
  EXPECT_GE(rows[1].lambda, 95.0);
}

TEST(ThermalScreening, EliminationTableHasTheThesisColumns) {
  const auto& e = Thesis(1);
  ScreeningOptions so;
  so.keep = 20;
  const ScreeningSummary s = ScreenParameters(e.experiment, so);
  const std::string table = FormatEliminationTable(s);
  EXPECT_NE(table.find("card(dX0)  removed   lambda(%)  steady set S"), std::string::npos);
  EXPECT_EQ(s.steps.size(), 5u);
  EXPECT_EQ(s.selected.size(), 20u);
  // Every removed parameter came from the steady set S of the row before (thesis step 4).
  for (std::size_t i = 1; i < s.steps.size(); ++i) {
    const auto& prev = s.steps[i - 1];
    bool in_s = false;
    for (int p : prev.steady) in_s |= p == s.steps[i].removed;
    EXPECT_TRUE(in_s || prev.steady_fallback);
  }
}

// Kept count chosen by held-out error (keep = 0, the default), issue 15's parsimony. Rates over
// 20 seeds of two drift truths: the thesis preset (8 drifting: 5 lengths and 3 angles) and the
// same experiment with only its 5 lengths drifting (the case where a fixed count of 8 must keep 3
// parameters that do not drift).
const testing::SimulatedExperiment& LengthOnly(std::uint64_t seed) {
  static std::map<std::uint64_t, std::unique_ptr<testing::SimulatedExperiment>> cache;
  auto& slot = cache[seed];
  if (!slot) {
    auto e = std::make_unique<testing::SimulatedExperiment>();
    e->options = ThesisPreset(seed);
    std::vector<ParamDrift> lengths;
    for (const ParamDrift& d : e->options.drifts) {
      if (!kinematics::IsAngleParam(d.param)) lengths.push_back(d);
    }
    e->options.drifts = lengths;
    e->sim = SimulateThermal(Kr150(), e->options);
    e->experiment = MakeExperiment(Kr150(), e->sim.setup, GroupCycles(e->sim.ball, "ball.csv"),
                                   GroupCycles(e->sim.monitoring, "monitoring.csv"));
    slot = std::move(e);
  }
  return *slot;
}

struct SweepFigures {
  double precision = 0;      // mean share of kept parameters that drift
  double recall = 0;         // mean share of drifting parameters kept
  double rms_over_truth = 0;  // mean monitoring RMS with the kept set / with the true set
  int lambda_95 = 0;         // seeds with λ(kept) ≥ 95 %
  int seeds = 0;
};

SweepFigures Sweep(bool length_only, int keep) {
  SweepFigures f;
  for (int seed = 1; seed <= 20; ++seed) {
    const auto& e = length_only ? LengthOnly(seed) : Thesis(seed);
    ScreeningOptions so;
    so.keep = keep;
    const ScreeningSummary s = ScreenParameters(e.experiment, so);
    EXPECT_EQ(s.count_from_heldout, keep == 0);
    int hits = 0;
    for (int p : s.selected) {
      for (int t : e.sim.drifting_params) hits += p == t ? 1 : 0;
    }
    const auto rows =
        CompareParameterSets(e.experiment, {{"kept", s.selected}, {"truth", e.sim.drifting_params}}, {}, so.lambda);
    f.precision += static_cast<double>(hits) / static_cast<double>(s.selected.size());
    f.recall += static_cast<double>(hits) / static_cast<double>(e.sim.drifting_params.size());
    f.rms_over_truth += rows[1].rms_residual_mm / rows[2].rms_residual_mm;
    f.lambda_95 += rows[1].lambda >= 95.0 ? 1 : 0;
    ++f.seeds;
  }
  f.precision /= f.seeds, f.recall /= f.seeds, f.rms_over_truth /= f.seeds;
  std::cout << (length_only ? "length-only" : "thesis preset") << ", keep " << (keep == 0 ? "auto" : std::to_string(keep))
            << ": precision " << f.precision << ", recall " << f.recall << ", monitoring RMS / true set's "
            << f.rms_over_truth << ", lambda >= 95 % in " << f.lambda_95 << "/" << f.seeds << "\n";
  return f;
}

TEST(ThermalScreeningHeldout, LengthOnlyDriftKeepsOnlyDriftingParameters) {
  const SweepFigures fixed = Sweep(true, 8), chosen = Sweep(true, 0);
  // A fixed count of 8 with 5 drifting parameters has precision ≤ 5/8 by construction.
  EXPECT_LE(fixed.precision, 5.0 / 8.0 + 1e-12);
  // Held-out count: a parameter that does not drift is kept in at most one seed in 20 on average.
  EXPECT_GE(chosen.precision, 0.95);
  // Dropped parameters are the ones whose drift is under the noise: the monitoring residual stays
  // within 5 % of the true set's (its own identification noise is ~2 % at 20 poses).
  EXPECT_LE(chosen.rms_over_truth, 1.05);
  EXPECT_LT(chosen.rms_over_truth, fixed.rms_over_truth);
  EXPECT_EQ(chosen.lambda_95, chosen.seeds);
}

TEST(ThermalScreeningHeldout, ThesisPresetKeepsTheDriftingSet) {
  const SweepFigures chosen = Sweep(false, 0);
  EXPECT_GE(chosen.precision, 0.95);
  EXPECT_GE(chosen.recall, 0.75);  // α4/a3/β2 drift close to the noise at the ball in some seeds
  EXPECT_LE(chosen.rms_over_truth, 1.05);
  EXPECT_EQ(chosen.lambda_95, chosen.seeds);
}

TEST(ThermalScreeningHeldout, HeldoutErrorOfTheTrueSetMatchesItsClosedForm) {
  // With one drift per cycle (no motion within the cycle), the true set's leave-one-pose-out error
  // of pose k per coordinate has expectation σ_d²·(1 + tr(A_k (A_−kᵀA_−k)⁻¹ A_kᵀ)/3), σ_d² =
  // 2(σ_s² + σ_r²) for a difference of two noisy centres. Over 5 seeds the mean matches it within
  // ±15 % (the reference cycle's noise is shared by all 89 cycles of a pose: ≈ 9 % relative
  // scatter of one seed's mean, 4 % over 5, so ±15 % is beyond 3 standard errors).
  double measured = 0.0, expected = 0.0;
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    ThermalSimOptions o = ThesisPreset(seed);
    o.drift_changes_within_cycle = false;
    const ThermalSimResult sim = SimulateThermal(Kr150(), o);
    const ThermalExperiment e = MakeExperiment(Kr150(), sim.setup, GroupCycles(sim.ball, "ball.csv"),
                                               GroupCycles(sim.monitoring, "monitoring.csv"));
    IdentificationOptions id;
    id.params = sim.drifting_params;
    const Eigen::VectorXd err = HeldoutPoseErrors(e, id);
    ASSERT_EQ(err.size(), 20);
    measured += err.mean() / 5.0;
    const DriftModel dm(Kr150(), sim.setup, e.ball.taught);
    Eigen::MatrixXd a(dm.FullSensitivity().rows(), static_cast<Eigen::Index>(id.params.size()));
    for (std::size_t c = 0; c < id.params.size(); ++c) a.col(c) = dm.FullSensitivity().col(id.params[c]);
    const double var_d = 2.0 * (o.sensor_noise_mm * o.sensor_noise_mm + o.repeatability_mm * o.repeatability_mm);
    double factor = 0.0;
    for (int k = 0; k < 20; ++k) {
      Eigen::MatrixXd rest(a.rows() - 3, a.cols());
      rest << a.topRows(3 * k), a.bottomRows(a.rows() - 3 * (k + 1));
      const Eigen::MatrixXd ak = a.middleRows(3 * k, 3);
      factor += 1.0 + (ak * (rest.transpose() * rest).inverse() * ak.transpose()).trace() / 3.0;
    }
    expected += var_d * factor / 20.0 / 5.0;
  }
  std::cout << "held-out error of the true set " << measured << " mm^2, closed form " << expected << " mm^2\n";
  EXPECT_NEAR(measured / expected, 1.0, 0.15);
  // Too few poses to leave one out: NaN, not a throw.
  const auto& e = Thesis(1);
  IdentificationOptions few;
  few.params = e.sim.drifting_params;
  few.poses = {0, 1, 2};
  EXPECT_TRUE(std::isnan(HeldoutPoseErrors(e.experiment, few)[0]));
}

}  // namespace
}  // namespace ramtk::thermal
