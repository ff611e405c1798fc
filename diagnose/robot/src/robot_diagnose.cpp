#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/diagnose/engine/model_selection.h"
#include "ramtk/diagnose/robot/robot.h"
#include "ramtk/diagnose/engine/statistics.h"
#include "ramtk/thermal/monitoring.h"
#include "robot_candidates.h"
#include "robot_plots.h"

namespace ramtk::diagnose {
namespace {

using robot_detail::Row;

// A named cause must remove at least this share of the excess, or leave no structure behind.
constexpr double kExplainedShare = 0.9;
// Absorbed share at which a candidate counts as not observable with the data at hand.
constexpr double kNotObservableShare = 0.99;
// Two candidates are separated when their held-out errors differ by this many standard errors.
constexpr double kSeparationZ = 2.0;
// Two candidates look alike when their fitted corrections are this parallel (|cos| of the angle).
constexpr double kLookAlikeCos = 0.8;
// A candidate whose columns lie this much in another's span is nested in it.
constexpr double kNestedShare = 0.98;
// A contender with more than this many times the chosen candidate's parameters is not a look-alike.
constexpr int kOccamFactor = 2;

std::string Num(double v, int digits = 4) {
  std::ostringstream o;
  o.precision(digits);
  o << v;
  return o.str();
}

struct NamedTest {
  TestResult test;
  std::string variable;  // what it is tested against
};

// Structure tests of the current model's (in-sample) residual against the noise σ_eff.
std::vector<NamedTest> StructureTests(const robot_detail::RowSet& rs, const std::vector<Eigen::Vector3d>& res,
                                      double sigma_eff, bool cycle_means) {
  std::vector<NamedTest> tests;
  const int n = static_cast<int>(res.size());
  static const char* axis[3] = {"x", "y", "z"};
  std::vector<double> all;
  for (const auto& r : res) all.insert(all.end(), {r.x(), r.y(), r.z()});
  tests.push_back({VarianceTest(all, {sigma_eff}), "level"});
  // Means per pose (over cycles) and per cycle (over poses): χ² of the standardised means.
  auto group_means = [&](bool by_pose, const std::string& name) {
    std::map<int, std::pair<Eigen::Vector3d, int>> g;
    for (int i = 0; i < n; ++i) {
      auto& e = g[by_pose ? rs.rows[i].pose : rs.rows[i].cycle_pos];
      if (e.second == 0) e.first.setZero();
      e.first += res[i], ++e.second;
    }
    TestResult t;
    t.name = name;
    for (const auto& [k, e] : g) t.statistic += (e.first / e.second).squaredNorm() * e.second / (sigma_eff * sigma_eff);
    t.dof = 3.0 * g.size();
    t.p_value = g.size() > 1 ? ChiSquareUpperTail(t.statistic, t.dof) : 1.0;
    tests.push_back({t, by_pose ? "pose" : "cycle"});
  };
  if (rs.num_cycles >= 2) group_means(true, "pose_means");
  if (cycle_means && rs.pose_ids.size() >= 2) group_means(false, "cycle_means");
  std::vector<std::pair<std::string, std::vector<double>>> vars;
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i) t[i] = rs.rows[i].time_h;
  vars.emplace_back("time", t);
  for (int j = 0; j < 6; ++j) {
    std::vector<double> q(n);
    for (int i = 0; i < n; ++i) q[i] = rs.rows[i].q[j];
    vars.emplace_back("q" + std::to_string(j + 1), q);
  }
  for (const std::string& c : rs.extra_columns) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) {
      const auto it = rs.rows[i].extra.find(c);
      v[i] = it == rs.rows[i].extra.end() ? 0.0 : it->second;
    }
    vars.emplace_back(c, v);
  }
  for (const auto& [name, v] : vars) {
    // Joint angles: sin/cos of q and 2q (periodic in the angle); other variables: a quadratic.
    const bool angle = name.size() == 2 && name[0] == 'q';
    for (int a = 0; a < 3; ++a) {
      std::vector<double> comp(n);
      for (int i = 0; i < n; ++i) comp[i] = res[i][a];
      const std::string label = std::string(axis[a]) + " vs " + name;
      tests.push_back(
          {angle ? HarmonicTrendTest(comp, {sigma_eff}, v, 2, label) : TrendTest(comp, {sigma_eff}, v, 2, label),
           name});
    }
  }
  // Ljung–Box in time order only for a static model: per-cycle fits leave residuals whose
  // correlation (I − H) repeats with the pose order of every cycle, which the test would report
  // as structure (thesis preset, length drift only, seed 6: p = 6e-6 with nothing missing).
  if (!cycle_means) return tests;
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return t[a] < t[b]; });
  for (int a = 0; a < 3; ++a) {
    std::vector<double> s;
    for (int i : order) s.push_back(res[i][a]);
    tests.push_back({LjungBoxTest(s, 0, std::string(axis[a]) + " in time order"), "time order"});
  }
  return tests;
}

// The measured variable whose tests explain the most: Σ (χ² − dof) over its trend / group-mean
// tests (x, y, z together). p-values cannot rank here: strong structure drives them all to 0.
// A measured variable (time, a joint angle, an extra column) is preferred to the pose index when one
// carries at least a third of the pose means' excess: "pose" only says that the error is static.
std::string ExplainingVariable(const std::vector<NamedTest>& tests) {
  std::map<std::string, double> excess;
  for (const NamedTest& t : tests) {
    if (t.variable == "level" || t.variable == "time order") continue;
    excess[t.variable] += t.test.statistic - t.test.dof;
  }
  std::string best, best_measured;
  double top = -INFINITY, top_measured = -INFINITY;
  for (const auto& [v, e] : excess) {
    if (e > top) top = e, best = v;
    if (v != "pose" && v != "cycle" && e > top_measured) top_measured = e, best_measured = v;
  }
  if (best == "pose" && !best_measured.empty() && top_measured >= top / 3.0 && top_measured > 0) return best_measured;
  return best;
}

// λ (thesis §3.2) of the monitoring points with a per-cycle parameter set (empty: uncompensated).
double LambdaWith(const RobotDiagnoseInput& in, const thermal::ThermalExperiment& exp, const std::vector<int>& params) {
  const thermal::MonitoringModel mm(in.model, in.setup, exp.monitoring);
  if (params.empty()) return thermal::Lambda(mm.Uncompensated(), {});
  const thermal::DriftModel dm(in.model, in.setup, exp.ball.taught);
  thermal::IdentificationOptions id;
  id.params = params;
  std::sort(id.params.begin(), id.params.end());
  return thermal::Lambda(mm.Residuals(thermal::IdentifyForMonitoring(exp, dm, id)), {});
}

// One robot diagnosis in progress: the rows, the cross-validation set-up and what each step finds
// for the next.
struct Analysis {
  Analysis(const RobotDiagnoseInput& input, const DiagnoseOptions& opts, robot_detail::RowSet rows)
      : in(input), options(opts), rs(std::move(rows)), n(static_cast<int>(rs.rows.size())) {}
  const RobotDiagnoseInput& in;
  const DiagnoseOptions& options;
  const robot_detail::RowSet rs;
  const int n;
  double sigma = 0.0;                             // noise per coordinate, mm
  robot_detail::Context ctx;                      // rows, folds and the current model
  std::vector<Eigen::Vector3d> before;            // residual of the current model
  std::vector<NamedTest> tests;                   // structure tests of `before`
  std::vector<robot_detail::Evaluated> evaluated;
  robot_detail::PlausibilityBounds bounds;
  CandidateFit none;                              // the current model as a candidate
  const robot_detail::Evaluated* chosen_eval = nullptr;
  robot_detail::Evaluated combined;               // several causes together (when `multi`)
  bool multi = false;
};

// The noise floor: given, estimated from successive cycles of the same pose, or the default.
void SetNoiseFloor(Analysis* run, Diagnosis* out) {
  Diagnosis& d = *out;
  const DiagnoseOptions& options = run->options;
  const robot_detail::RowSet& rs = run->rs;
  const int n = run->n;
  int pairs = 0;
  double sigma = options.noise;
  std::string noise_note;
  if (sigma > 0) {
    noise_note = "noise σ = " + Num(sigma) + " mm per coordinate (given)";
  } else if ((sigma = robot_detail::EstimateNoiseFromCycles(rs.rows, &pairs)) > 0) {
    noise_note = "noise σ = " + Num(sigma) + " mm per coordinate, estimated from " + std::to_string(pairs) +
                 " successive-cycle pairs of the same pose";
  } else {
    sigma = 0.025;
    noise_note =
        "noise σ = 0.025 mm per coordinate (default: sensor 0.02 mm and repeatability 0.015 mm; one "
        "cycle only, nothing to estimate it from)";
  }
  d.noise_floor_rms = sigma;
  d.findings.push_back(noise_note);
  d.findings.push_back(std::to_string(n) + " ball measurements, " + std::to_string(rs.num_cycles) + " cycles, " +
                       std::to_string(rs.pose_ids.size()) + " poses");
  run->sigma = sigma;
}

void SetUpFolds(Analysis* run) {
  const RobotDiagnoseInput& in = run->in;
  const DiagnoseOptions& options = run->options;
  const robot_detail::RowSet& rs = run->rs;
  robot_detail::Context& ctx = run->ctx;
  // Folds over poses and cycles (a Latin square): cycle c holds out the poses of fold (k − c) mod K,
  // so every cycle keeps most of its poses (per-cycle drift stays fittable) and every pose stays in
  // the training set through the other cycles (no pose is predicted from a geometry that lacks it).
  ctx.input = &in;
  ctx.rows = &rs;
  ctx.sigma = run->sigma;
  ctx.progress = options.progress;
  ctx.folds = std::min<int>(options.folds, static_cast<int>(rs.pose_ids.size()));
  if (ctx.folds < 2) throw InputError({in.ball_path, 0, "pose"}, "cross-validation over poses needs at least 2 poses");
  const std::vector<int> fold_of_pose = FoldOfGroup(static_cast<int>(rs.pose_ids.size()), ctx.folds);
  for (const Row& r : rs.rows) {
    const int g =
        static_cast<int>(std::lower_bound(rs.pose_ids.begin(), rs.pose_ids.end(), r.pose) - rs.pose_ids.begin());
    ctx.fold_of_row.push_back((fold_of_pose[g] + r.cycle_pos) % ctx.folds);
  }
  ctx.base = robot_detail::CurrentModelDesign(in, rs);
  ctx.base_cv = robot_detail::CrossValidate(rs.rows, ctx.base, ctx.fold_of_row, ctx.folds, rs.num_cycles);
}

// Steps 1–2: residual of the current model and its structure.
void TestStructure(Analysis* run, Diagnosis* out) {
  Diagnosis& d = *out;
  const DiagnoseOptions& options = run->options;
  const robot_detail::RowSet& rs = run->rs;
  const robot_detail::Context& ctx = run->ctx;
  const int n = run->n;
  std::vector<Eigen::Vector3d>& before = run->before;
  before.resize(n);
  for (int i = 0; i < n; ++i) before[i] = robot_detail::FitResidual(rs.rows, ctx.base, ctx.base_cv.full, i);
  d.residual_rms = ctx.base_cv.TrainRms();
  const double fitted = ctx.base.ns + static_cast<double>(ctx.base.np) * rs.num_cycles;
  const double sigma_eff = run->sigma * std::sqrt(std::max(0.05, 1.0 - fitted / (3.0 * n)));
  run->tests = StructureTests(rs, before, sigma_eff, ctx.base.np == 0);
  const std::vector<NamedTest>& tests = run->tests;
  std::vector<double> p;
  for (const NamedTest& t : tests) p.push_back(t.test.p_value);
  const std::vector<double> corrected = HolmCorrection(p);
  int best_test = 0;
  for (size_t i = 0; i < tests.size(); ++i)
    if (corrected[i] < corrected[best_test]) best_test = static_cast<int>(i);
  d.structure_p_value = corrected[best_test];
  d.structure_found = d.structure_p_value < options.alpha;
  std::vector<int> order(tests.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return corrected[a] < corrected[b]; });
  for (size_t k = 0; k < order.size() && k < 8; ++k) {
    const int i = order[k];
    if (k > 0 && corrected[i] >= options.alpha) break;
    d.findings.push_back(tests[i].test.Describe() + " (Holm-corrected p = " + Num(corrected[i], 3) + ")");
  }
}

// Step 3: every candidate, the chosen one first.
void FitCandidates(Analysis* run, Diagnosis* out) {
  Diagnosis& d = *out;
  const robot_detail::RowSet& rs = run->rs;
  std::vector<robot_detail::Evaluated>& evaluated = run->evaluated;
  std::vector<std::string> notes;
  evaluated = robot_detail::EvaluateCandidates(run->ctx, &notes);
  run->bounds = robot_detail::BoundsFor(run->in.model);
  for (auto& e : evaluated) {
    e.fit.absorbed_share = robot_detail::AbsorbedShare(run->ctx.base, e.design);
    robot_detail::CheckPlausibility(run->bounds, &e.fit);
    if (!e.fit.implausible.empty()) {
      notes.push_back(e.fit.effect + " is implausible, never named: " + e.fit.implausible);
    }
  }
  CandidateFit& none = run->none;
  none.effect = kNoEffect;
  none.train_rms = run->ctx.base_cv.TrainRms();
  none.heldout_rms = run->ctx.base_cv.HeldoutRms();
  none.heldout_count = run->ctx.base_cv.heldout_n;
  d.candidates.push_back(none);
  for (const auto& e : evaluated) {
    d.candidates.push_back(e.fit);
    if (!e.note.empty()) notes.push_back(e.note);
  }
  SelectCandidate(&d.candidates);
  const std::string static_first = robot_detail::PreferStatic(rs, evaluated, &d.candidates);
  if (!static_first.empty()) notes.push_back(static_first);
  const std::string specific_first = robot_detail::PreferSpecific(&d.candidates, SelectionOptions{}.min_improvement);
  if (!specific_first.empty()) notes.push_back(specific_first);
  for (const std::string& note : notes) d.findings.push_back("candidate " + note);
  const CandidateFit& chosen = d.candidates[0];
  for (const auto& e : evaluated)
    if (e.fit.effect == chosen.effect) run->chosen_eval = &e;
}

// Step 4: the gain on held-out data, and how alike each candidate's fitted correction is to the
// chosen one's.
void MeasureGain(const Analysis& run, Diagnosis* out) {
  Diagnosis& d = *out;
  const robot_detail::RowSet& rs = run.rs;
  const robot_detail::Context& ctx = run.ctx;
  const robot_detail::Evaluated* chosen_eval = run.chosen_eval;
  const std::vector<robot_detail::Evaluated>& evaluated = run.evaluated;
  const CandidateFit& chosen = d.candidates[0];
  d.rms_before = run.none.heldout_rms;
  d.rms_after = chosen.heldout_rms;
  d.excess_removed = ExcessRemoved(d.rms_before, d.rms_after, run.sigma);
  d.confidence = chosen.weight;
  Eigen::VectorXd sig_chosen;
  if (chosen_eval != nullptr) {
    sig_chosen =
        robot_detail::Signature(rs.rows, ctx.base, ctx.base_cv.full, chosen_eval->design, chosen_eval->cv.full);
    for (CandidateFit& c : d.candidates)
      for (const auto& e : evaluated)
        if (e.fit.effect == c.effect) {
          const Eigen::VectorXd sc = robot_detail::Signature(rs.rows, ctx.base, ctx.base_cv.full, e.design, e.cv.full);
          const double den = sc.norm() * sig_chosen.norm();
          c.signature_cos = den > 0 ? std::abs(sc.dot(sig_chosen)) / den : 0.0;
        }
  }
}

// Out-of-catalogue honesty: after fitting the chosen extension, the structure tests that still find
// dependence on a measured variable (then the name would claim too much).
std::vector<NamedTest> RemainingStructure(const Analysis& run) {
  const robot_detail::RowSet& rs = run.rs;
  const robot_detail::Evaluated* chosen_eval = run.chosen_eval;
  const int n = run.n;
  const double sigma = run.sigma;
  const DiagnoseOptions& options = run.options;
  std::vector<Eigen::Vector3d> after(n);
  for (int i = 0; i < n; ++i)
    after[i] = robot_detail::FitResidual(rs.rows, chosen_eval->design, chosen_eval->cv.full, i);
  const double fitted_after = chosen_eval->design.ns + static_cast<double>(chosen_eval->design.np) * rs.num_cycles;
  const double sigma_after = sigma * std::sqrt(std::max(0.05, 1.0 - fitted_after / (3.0 * n)));
  std::vector<NamedTest> rest = StructureTests(rs, after, sigma_after, chosen_eval->design.np == 0);
  std::vector<double> rp;
  for (const NamedTest& t : rest) rp.push_back(t.test.p_value);
  const std::vector<double> rc = HolmCorrection(rp);
  std::vector<NamedTest> remaining;
  for (size_t i = 0; i < rest.size(); ++i)
    if (rc[i] < options.alpha && rest[i].variable != "level" && rest[i].variable != "time order")
      remaining.push_back(rest[i]);
  return remaining;
}

// The verdict when structure remains: unexplained, with the variable that carries it.
void DescribeUnexplained(const std::vector<NamedTest>& remaining, Diagnosis* out) {
  Diagnosis& d = *out;
  const CandidateFit& chosen = d.candidates[0];
  d.explaining_variable = ExplainingVariable(remaining);
  d.partial = {chosen.effect};
  // Quote the strongest test of the variable named, not the strongest test overall.
  const NamedTest* quoted = &remaining.front();
  for (const NamedTest& t : remaining) {
    if (t.variable == d.explaining_variable &&
        (quoted->variable != d.explaining_variable || t.test.statistic - t.test.dof > quoted->test.statistic - quoted->test.dof)) {
      quoted = &t;
    }
  }
  d.findings.push_back("after fitting '" + chosen.effect + "' (" + Num(100 * d.excess_removed, 3) +
                       "% of the excess) the residual still depends on " + d.explaining_variable + " (" +
                       quoted->test.Describe() + "): structure outside the catalogue, '" + chosen.effect +
                       "' explains it only in part");
}

// Look-alikes of the chosen candidate; true (and the pair with what would separate them in `out`)
// when these data do not separate it from one.
bool FindLookAlikes(const Analysis& run, Diagnosis* out) {
  Diagnosis& d = *out;
  const robot_detail::RowSet& rs = run.rs;
  const robot_detail::Context& ctx = run.ctx;
  const robot_detail::Evaluated* chosen_eval = run.chosen_eval;
  const CandidateFit& chosen = d.candidates[0];
  const double sigma = run.sigma;
  const std::vector<robot_detail::Evaluated>& evaluated = run.evaluated;
  // Look-alikes: candidates with a material gain whose held-out error is not worse than the
  // chosen one's by more than kSeparationZ standard errors of the per-pose scatter.
  // Look-alikes predict nearly the same correction (|cos| of their signatures ≥ kLookAlikeCos);
  // the closest one (highest z) forms the reported pair, further ones are listed in the findings.
  // Nested pairs are not look-alikes: the held-out score with its parameter penalty already
  // decided between a model and its own special case.
  std::vector<std::string> alike{chosen.effect};
  Eigen::VectorXd difference;
  double closest = -INFINITY;
  std::string closest_effect;
  for (const auto& e : evaluated) {
    if (e.fit.effect == chosen.effect) continue;
    if (ExcessRemoved(d.rms_before, e.fit.heldout_rms, sigma) < 0.25) continue;
    // Nested: one candidate's columns lie in the other's span (beyond the common base), so the
    // richer one only adds parameters and the penalised held-out score has chosen between them.
    // (Not judged on the fitted corrections: a rich model reproduces many signals it does not
    // contain, e.g. a sensor drift quadratic in time and a temperature rising with time.)
    const double nested =
        std::max(robot_detail::NestedShare(chosen_eval->design, e.design, ctx.base.ns, ctx.base.np),
                 robot_detail::NestedShare(e.design, chosen_eval->design, ctx.base.ns, ctx.base.np));
    if (e.fit.num_parameters > kOccamFactor * chosen.num_parameters) {
      d.findings.push_back("'" + e.fit.effect + "' (" + std::to_string(e.fit.num_parameters) +
                           " parameters) matches '" + chosen.effect + "' (" +
                           std::to_string(chosen.num_parameters) +
                           ") only with many more parameters: not a look-alike (parsimony)");
      continue;
    }
    if (nested >= kNestedShare) {
      d.findings.push_back("'" + e.fit.effect + "' and '" + chosen.effect + "' are nested (" +
                           Num(100 * nested, 3) +
                           "% of the smaller one's columns lie in the larger one): the penalised held-out score "
                           "decides");
      continue;
    }
    const double z = robot_detail::HeldoutDifferenceZ(rs, chosen_eval->cv.heldout_residual, e.cv.heldout_residual);
    double cos = 0;
    for (const CandidateFit& c : d.candidates)
      if (c.effect == e.fit.effect) cos = c.signature_cos;
    d.findings.push_back("held-out difference '" + chosen.effect + "' - '" + e.fit.effect + "': " + Num(z, 3) +
                         " standard errors (per-pose scatter); signatures |cos| " + Num(cos, 3));
    if (z > -kSeparationZ && cos >= kLookAlikeCos && z > closest) {
      closest = z, closest_effect = e.fit.effect;
      difference = robot_detail::Signature(rs.rows, e.design, e.cv.full, chosen_eval->design, chosen_eval->cv.full);
    }
  }
  if (!closest_effect.empty()) alike.push_back(closest_effect);
  if (alike.size() <= 1) return false;
  d.look_alikes = alike;
  d.separate_with = robot_detail::SeparatingData(rs, difference, alike);
  d.findings.push_back("these data do not separate the look-alikes; to separate them: " + d.separate_with);
  return true;
}

// Step 3b: is the chosen candidate the whole story, and can these data tell it from the others?
std::string Verdict(const Analysis& run, Diagnosis* d) {
  const std::string chosen = d->candidates[0].effect;
  if (run.chosen_eval == nullptr || !d->structure_found || d->excess_removed < 0.25) return chosen;
  const std::vector<NamedTest> remaining = RemainingStructure(run);
  if (!remaining.empty() && d->excess_removed < kExplainedShare) {
    DescribeUnexplained(remaining, d);
    return kUnexplained;
  }
  return FindLookAlikes(run, d) ? kAmbiguous : chosen;
}

// The cause (or none, unexplained, not observable) from the verdict and the gain.
void Conclude(const Analysis& run, const std::string& verdict, Diagnosis* out) {
  Diagnosis& d = *out;
  const CandidateFit& chosen = d.candidates[0];
  const CandidateFit& none = run.none;
  const std::vector<NamedTest>& tests = run.tests;
  if (verdict != kUnexplained && chosen.effect != kNoEffect && d.structure_found && d.excess_removed >= 0.25) {
    d.cause = verdict;
    d.parameters = chosen.parameters;
    d.sigmas = chosen.sigmas;
  } else if (verdict == kUnexplained) {
    // The headline keeps what the partial cause removes (rms_after, excess_removed): it is part of
    // the answer, not nothing.
    d.cause = kUnexplained;
    d.confidence = none.weight;
  } else {
    d.cause = kNoEffect;
    for (const CandidateFit& c : d.candidates)
      if (c.absorbed_share >= kNotObservableShare)
        d.findings.push_back("'" + c.effect + "' is " + Num(100 * c.absorbed_share, 4) +
                             "% absorbed by the current model's set-up parameters: hardly observable with these poses");
    if (d.structure_found) {
      // Structure that no catalogued extension explains: say so, with the variable that carries it.
      d.explaining_variable = ExplainingVariable(tests);
      d.cause = kUnexplained;
      if (chosen.effect != kNoEffect && d.excess_removed > 0.05) d.partial = {chosen.effect};
      if (chosen.effect != kNoEffect && chosen.absorbed_share >= kNotObservableShare) {
        // The best candidate would be the cause, but the set-up parameters absorb almost all of it.
        d.cause = kNotObservable;
        d.look_alikes = {chosen.effect};
        d.partial.clear();
      }
      d.findings.push_back("structure best explained by " + d.explaining_variable + " (largest χ² above its dof); " +
                           (chosen.effect == kNoEffect ? "no catalogued extension pays on held-out data"
                                                       : "'" + chosen.effect + "' removes only " +
                                                             Num(100 * d.excess_removed, 3) + "% of the excess"));
    }
    if (d.cause != chosen.effect) {
      if (d.partial.empty()) {
        d.rms_after = d.rms_before;
        d.excess_removed = 0.0;
      }
      d.confidence = none.weight;
    }
  }
}

// Step 5: several causes at once. When the first cause explains part of the excess, the others
// are fitted on top of it, each kept with its own held-out gain.
void SeveralCauses(Analysis* run, Diagnosis* out) {
  Diagnosis& d = *out;
  const CandidateFit& chosen = d.candidates[0];
  const CandidateFit& none = run->none;
  const robot_detail::Evaluated* chosen_eval = run->chosen_eval;
  const double sigma = run->sigma;
  if (chosen_eval != nullptr && d.structure_found && chosen.effect != kNoEffect && chosen.implausible.empty() &&
      d.cause != kAmbiguous && d.cause != kNotObservable) {
    const double first_share = ExcessRemoved(none.heldout_rms, chosen.heldout_rms, sigma);
    if (first_share >= 0.05 && chosen.heldout_rms > 1.05 * sigma) {
      // Further causes are added while they pay (the score margin, a tenth of what is left) and the
      // residual is above the noise floor: a small third error is still a cause once the large
      // ones are in.
      std::vector<CauseStep> steps = robot_detail::ForwardSelect(run->ctx, *chosen_eval, none.heldout_rms, sigma, 1.0,
                                                                 run->bounds, &d.findings, &run->combined);
      if (steps.size() > 1) {
        run->multi = true;
        d.causes = steps;
        d.rms_after = run->combined.fit.heldout_rms;
        d.excess_removed = ExcessRemoved(d.rms_before, d.rms_after, sigma);
        d.confidence = chosen.weight;
        d.parameters.clear();
        d.sigmas.clear();
        d.partial.clear();
        for (const CauseStep& st : steps) {
          for (const auto& [k, v] : st.parameters) d.parameters[st.effect + ":" + k] = v;
          for (const auto& [k, v] : st.sigmas) d.sigmas[st.effect + ":" + k] = v;
        }
        std::string names;
        for (const CauseStep& st : steps) names += (names.empty() ? "'" : " + '") + st.effect + "'";
        if (d.excess_removed >= 0.5) {
          d.cause = steps.front().effect;
          d.explaining_variable.clear();
          d.findings.push_back("causes kept together: " + names + ", " + Num(100 * d.excess_removed, 3) +
                               "% of the excess over the noise floor removed on held-out data");
        } else {
          d.cause = kUnexplained;
          for (const CauseStep& st : steps) d.partial.push_back(st.effect);
          d.findings.push_back("causes " + names + " together remove " + Num(100 * d.excess_removed, 3) +
                               "% of the excess: the rest is outside the catalogue");
        }
      }
    }
  }
}

// λ of thesis §3.2 on the monitoring points, current vs extended per-cycle set.
void LambdaFinding(const Analysis& run, Diagnosis* out) {
  Diagnosis& d = *out;
  const RobotDiagnoseInput& in = run.in;
  const CandidateFit& chosen = d.candidates[0];
  const robot_detail::Evaluated* chosen_eval = run.chosen_eval;
  if (in.has_monitoring && in.has_setup && in.setup.has_tool_sensor && chosen_eval != nullptr &&
      !chosen_eval->added_cycle_params.empty() && (d.cause == chosen.effect || d.cause == kAmbiguous)) {
    try {
      const thermal::ThermalExperiment exp =
          thermal::MakeExperiment(in.model, in.setup, thermal::GroupCycles(in.ball, in.ball_path),
                                  thermal::GroupCycles(in.monitoring, in.monitoring_path));
      std::vector<int> extended = in.thermal_params;
      extended.insert(extended.end(), chosen_eval->added_cycle_params.begin(), chosen_eval->added_cycle_params.end());
      const double l0 = LambdaWith(in, exp, in.thermal_params), l1 = LambdaWith(in, exp, extended);
      d.findings.push_back(
          "λ (thesis §3.2, share of monitored directions within 0.1 mm): " + Num(l0) + "% with " +
          (in.thermal_params.empty() ? std::string("no compensation") : thermal::ParamListToString(in.thermal_params)) +
          " -> " + Num(l1) + "% with " + thermal::ParamListToString(extended));
    } catch (const InputError& e) {
      d.findings.push_back(std::string("λ not computed: ") + e.what());
    }
  }
}

// The residual pictures before and after the cause(s) into options.output_folder.
void WritePictures(const Analysis& run, Diagnosis* out) {
  Diagnosis& d = *out;
  const CandidateFit& chosen = d.candidates[0];
  const robot_detail::Evaluated* chosen_eval = run.chosen_eval;
  const robot_detail::Evaluated& combined = run.combined;
  const robot_detail::RowSet& rs = run.rs;
  const int n = run.n;
  std::filesystem::create_directories(run.options.output_folder);
  std::vector<Eigen::Vector3d> after = run.before;
  std::vector<Eigen::Vector3d> heldout_after = run.ctx.base_cv.heldout_residual;
  std::vector<std::string> added;
  Eigen::MatrixXd added_series;
  if (run.multi) {
    for (int i = 0; i < n; ++i) after[i] = robot_detail::FitResidual(rs.rows, combined.design, combined.cv.full, i);
    heldout_after = combined.cv.heldout_residual;
  } else if (chosen_eval != nullptr && (d.cause == chosen.effect || d.cause == kAmbiguous)) {
    for (int i = 0; i < n; ++i)
      after[i] = robot_detail::FitResidual(rs.rows, chosen_eval->design, chosen_eval->cv.full, i);
    heldout_after = chosen_eval->cv.heldout_residual;
    for (int param : chosen_eval->added_cycle_params) added.push_back(kinematics::ParamName(param));
    added_series = chosen_eval->added_series;
  }
  robot_detail::WriteRobotPictures(rs, run.before, after, run.ctx.base_cv.heldout_residual, heldout_after, run.sigma, added,
                                   added_series, d.cause, run.options.output_folder, &d.pictures);
}

}  // namespace

Diagnosis DiagnoseRobot(const DiagnoseOptions& options) {
  ThrowIfInvalid(options.Validate(), "DiagnoseOptions");
  return DiagnoseRobotData(ReadRobotDiagnoseInput(options), options);
}


Diagnosis DiagnoseRobotData(const RobotDiagnoseInput& in, const DiagnoseOptions& options) {
  DiagnoseOptions checked = options;  // in-memory data needs no file name
  if (checked.data.empty()) checked.data = in.ball_path.empty() ? "(in memory)" : in.ball_path;
  ThrowIfInvalid(checked.Validate(), "DiagnoseOptions");
  Analysis run(in, options, robot_detail::BuildRows(in));
  Diagnosis d;
  d.kind = DataKind::kRobot;
  d.data = in.ball_path;
  d.unit = "mm";
  d.model = (in.model_label.empty() ? in.model.name : in.model_label) +
            (in.thermal_params.empty()
                 ? std::string(", static")
                 : ", per-cycle drift of " + (in.thermal_label.empty() ? std::string("") : in.thermal_label + " = ") +
                       thermal::ParamListToString(in.thermal_params)) +
            "; " + run.rs.setup_note;
  d.num_residuals = 3 * run.n;
  SetNoiseFloor(&run, &d);
  SetUpFolds(&run);
  TestStructure(&run, &d);
  FitCandidates(&run, &d);
  MeasureGain(run, &d);
  Conclude(run, Verdict(run, &d), &d);
  SeveralCauses(&run, &d);
  LambdaFinding(run, &d);
  if (!options.output_folder.empty()) WritePictures(run, &d);
  return d;
}

}  // namespace ramtk::diagnose
