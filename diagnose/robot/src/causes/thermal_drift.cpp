// Thermal drift of the kinematic parameters: the lengths, then angles added greedily by held-out
// score on top of them; each in two forms, free per cycle (thesis eq. 3-8) and smooth in time
// (a + b·τ + c·τ², τ = time / span), the better score kept. Both causes are fitted together
// (the angle candidate extends the length one).
#include <algorithm>
#include <cmath>

#include "../robot_fit_kit.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::diagnose::robot_detail {
namespace {

using kinematics::ParamIndex;
using kinematics::ParamKind;

// A model being extended greedily: its design, score and drift terms.
struct Greedy {
  Design design;
  CvResult cv;
  ThermalTerms terms;
  int k = 0;
  double score = 0;
};

// Adds angle drifts to `current` one at a time while each pays min_improvement; returns the chosen.
std::vector<int> AddAnglesGreedily(const Context& ctx, bool per_cycle, int start_k, Greedy* current) {
  std::vector<int> pool = Identifiable(ctx.rows->rows, current->design, AngleParams(ctx.input->model));
  std::vector<int> chosen;
  const int n = current->cv.heldout_n;
  while (!pool.empty() && chosen.size() < 6) {
    double best = INFINITY;
    int best_k = -1, best_count = 0;
    CvResult best_cv;
    Design best_design;
    ThermalTerms best_terms;
    for (size_t k = 0; k < pool.size(); ++k) {
      Design d = current->design;
      ThermalTerms t = current->terms;
      const int added = AddDrift(ctx, {pool[k]}, per_cycle, &d, &t);
      if (added == 0) continue;
      CvResult cv = Cv(ctx, d);
      const double sc = Score(cv.heldout_ss, n, added + current->k - start_k);
      if (sc < best)
        best = sc, best_k = static_cast<int>(k), best_cv = std::move(cv), best_design = std::move(d),
        best_terms = std::move(t), best_count = added;
    }
    if (best_k < 0 || !(best < current->score - ctx.min_improvement)) break;
    chosen.push_back(pool[best_k]);
    current->design = std::move(best_design);
    current->cv = std::move(best_cv);
    current->terms = std::move(best_terms);
    current->k += best_count;
    current->score = best;
    pool.erase(pool.begin() + best_k);
  }
  return chosen;
}

// One form (per cycle or smooth in time): the length candidate, then the angle candidate on top.
std::vector<Evaluated> FitForm(const Context& ctx, const std::vector<int>& new_lengths, bool per_cycle) {
  std::vector<Evaluated> out;
  const char* form = per_cycle ? "per cycle" : "smooth in time";
  Greedy g{ctx.base, ctx.base_cv, {}, 0, 0};
  std::vector<int> lengths_used;
  if (!new_lengths.empty()) {
    lengths_used = new_lengths;
    Evaluated e;
    e.design = ctx.base;
    const int k = AddDrift(ctx, new_lengths, per_cycle, &e.design, &g.terms);
    if (k > 0) {
      e.cv = Cv(ctx, e.design);
      e.fit = MakeFit("thermal_length_drift", k, e.cv);
      e.added_cycle_params = new_lengths;
      ReportDrift(ctx, e.cv, g.terms, new_lengths, &e);
      e.note = std::string("thermal_length_drift (") + form + "): " + thermal::ParamListToString(new_lengths);
      g.design = e.design, g.cv = e.cv, g.k = k;
      out.push_back(std::move(e));
    } else {
      lengths_used.clear();
    }
  }
  const int start_k = g.k;
  g.score = Score(g.cv.heldout_ss, g.cv.heldout_n, 0);
  const std::vector<int> chosen = AddAnglesGreedily(ctx, per_cycle, start_k, &g);
  if (!chosen.empty()) {
    Evaluated e;
    e.design = g.design;
    e.cv = g.cv;
    std::vector<int> all_added = lengths_used;
    all_added.insert(all_added.end(), chosen.begin(), chosen.end());
    e.added_cycle_params = all_added;
    e.fit = MakeFit("thermal_angle_drift", g.k, e.cv);
    ReportDrift(ctx, e.cv, g.terms, all_added, &e);
    e.note = std::string("thermal_angle_drift (") + form + "): add " + thermal::ParamListToString(chosen) +
             (lengths_used.empty() ? "" : " to the drifting lengths " + thermal::ParamListToString(lengths_used));
    out.push_back(std::move(e));
  }
  return out;
}

// A drift must change with time: a thermal candidate whose held-out score a static error of the
// same parameters matches (within min_improvement) is a static effect (joint compliance, a zero or
// length error) seen through constant drift terms, and is dropped.
void DropStaticLookalikes(const Context& ctx, std::vector<Evaluated>* list, std::vector<std::string>* notes) {
  for (auto it = list->begin(); it != list->end();) {
    const std::vector<int> params = Identifiable(ctx.rows->rows, ctx.base, it->added_cycle_params);
    bool is_static = false;
    if (!params.empty()) {
      const CvResult st = Cv(ctx, WithParams(ctx, ctx.base, params, false));
      const double static_score = Score(st.heldout_ss, st.heldout_n, static_cast<int>(params.size()));
      const double drift_score = Score(it->cv.heldout_ss, it->cv.heldout_n, it->fit.num_parameters);
      is_static = !(drift_score < static_score - ctx.min_improvement);
      if (is_static)
        notes->push_back(it->fit.effect + ": dropped, a static error of " + thermal::ParamListToString(params) +
                         " explains as much (held-out score " + std::to_string(static_score) + " vs " +
                         std::to_string(drift_score) + ")");
    }
    it = is_static ? list->erase(it) : it + 1;
  }
}

void FitThermalDrift(const Context& ctx, CauseOutput out) {
  std::vector<int> new_lengths;
  const std::vector<int>& current = ctx.input->thermal_params;
  for (int p : thermal::TraditionalParams(ctx.input->model))
    if (std::find(current.begin(), current.end(), p) == current.end()) new_lengths.push_back(p);
  if (new_lengths.empty())
    out.notes->push_back("thermal_length_drift: already in the current model (" + ctx.input->thermal_label + ")");
  std::vector<Evaluated> forms[2] = {FitForm(ctx, new_lengths, true), FitForm(ctx, new_lengths, false)};
  for (auto& list : forms) DropStaticLookalikes(ctx, &list, out.notes);
  for (const char* effect : {"thermal_length_drift", "thermal_angle_drift"}) {
    Evaluated* best = nullptr;
    for (auto& list : forms)
      for (Evaluated& e : list)
        if (e.fit.effect == effect &&
            (best == nullptr || Score(e.cv.heldout_ss, e.cv.heldout_n, e.fit.num_parameters) <
                                    Score(best->cv.heldout_ss, best->cv.heldout_n, best->fit.num_parameters)))
          best = &e;
    if (best != nullptr)
      out.evaluated->push_back(std::move(*best));
    else if (std::string(effect) == "thermal_angle_drift")
      out.notes->push_back("thermal_angle_drift: no angle parameter improves the held-out score");
  }
}

// The thesis preset's length drifts, scaled; with `angles` also one or two angle drifts heated by
// joint 2, 3 or 4.
void PlantThermal(PlantContext* p, bool angles) {
  for (const auto& d : p->preset_drifts) {
    if (kinematics::IsAngleParam(d.param)) continue;
    thermal::ParamDrift scaled = d;
    const double f = angles ? p->random.Uniform(0.5, 1.5) : p->random.Uniform(0.5, 2.0);
    for (double& k : scaled.per_kelvin) k *= f;
    p->sim->drifts.push_back(scaled);
  }
  std::string& what = p->draw->description;
  what = "length drift (thesis d4 d6 a1 a2 a3, scaled)";
  if (!angles) return;
  static const int pool[10] = {ParamIndex(ParamKind::kTheta, 1), ParamIndex(ParamKind::kTheta, 2),
                               ParamIndex(ParamKind::kTheta, 3), ParamIndex(ParamKind::kTheta, 4),
                               ParamIndex(ParamKind::kAlpha, 0), ParamIndex(ParamKind::kAlpha, 1),
                               ParamIndex(ParamKind::kAlpha, 2), ParamIndex(ParamKind::kAlpha, 3),
                               ParamIndex(ParamKind::kAlpha, 4), ParamIndex(ParamKind::kBeta, 1)};
  const int count = 1 + p->random.Pick(2);
  std::vector<int> chosen;
  while (static_cast<int>(chosen.size()) < count) {
    const int k = pool[p->random.Pick(10)];
    if (std::find(chosen.begin(), chosen.end(), k) == chosen.end()) chosen.push_back(k);
  }
  for (int k : chosen) {
    thermal::ParamDrift d;
    d.param = k;
    d.per_kelvin.assign(6, 0.0);
    const int joint = 1 + p->random.Pick(3);
    const double c = p->random.Sign() * p->random.Uniform(4e-6, 15e-6);
    d.per_kelvin[joint] = c;
    p->sim->drifts.push_back(d);
    p->draw->truth[kinematics::ParamName(k) + "_urad_per_K"] = c * 1e6;
    what += " + " + kinematics::ParamName(k) + " " + Fmt(c * 1e6) + " µrad/K of joint " + std::to_string(joint + 1);
  }
}

void PlantLengthDrift(PlantContext* p) { PlantThermal(p, false); }
void PlantAngleDrift(PlantContext* p) { PlantThermal(p, true); }

}  // namespace

const RobotCauseCode kThermalLengthDrift{3, "thermal candidates need at least 3 cycles", true, FitThermalDrift,
                                         PlantLengthDrift, nullptr};
const RobotCauseCode kThermalAngleDrift{3, "", true, nullptr, PlantAngleDrift, nullptr};

}  // namespace ramtk::diagnose::robot_detail
