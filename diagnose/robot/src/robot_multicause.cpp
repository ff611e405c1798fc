// Several causes at once (forward selection), static causes before drifts, and plausibility bounds
// of the robot candidates.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "ramtk/core/units.h"
#include "ramtk/diagnose/engine/model_selection.h"
#include "robot_causes.h"

namespace ramtk::diagnose::robot_detail {
namespace {

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool Contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string Num(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// Whether a fitted value lies within its cause's physical bounds; "" when it does.
std::string Bound(const std::string& key, double value, double sigma, const PlausibilityBounds& b) {
  const double a = std::abs(value);
  auto outside = [&](double limit, const char* unit) {
    return "'" + key + "' = " + Num(value) + " is beyond ±" + Num(limit) + " " + unit;
  };
  if (Contains(key, "_drift_range_mm")) return a > b.drift_mm ? outside(b.drift_mm, "mm") : "";
  if (Contains(key, "_drift_range_deg")) return a > b.drift_deg ? outside(b.drift_deg, "deg") : "";
  if (Contains(key, "amplitude") && EndsWith(key, "_deg")) return a > b.cyclic_deg ? outside(b.cyclic_deg, "deg") : "";
  if (Contains(key, "_compliance_")) {
    // A joint yields to its load: a compliance below zero by more than 3σ is not physical.
    if (value < -3.0 * sigma && value < 0) return "'" + key + "' = " + Num(value) + " is negative (a joint that pushes back harder than its load)";
    return "";
  }
  if (key == "dx_mm" || key == "dy_mm" || key == "dz_mm") return a > b.tool_mm ? outside(b.tool_mm, "mm") : "";
  if (EndsWith(key, "_error_mm")) return a > b.length_mm ? outside(b.length_mm, "mm") : "";
  if (EndsWith(key, "_offset_deg") || EndsWith(key, "_twist_deg") || EndsWith(key, "_error_deg")) {
    return a > b.angle_deg ? outside(b.angle_deg, "deg") : "";
  }
  return "";
}

// Moves `effect` to the front; it takes over the evidence weight of the candidate it displaces.
void MoveToFront(const std::string& effect, std::vector<CandidateFit>* candidates) {
  const double front_weight = candidates->front().weight;
  std::stable_partition(candidates->begin(), candidates->end(),
                        [&](const CandidateFit& c) { return c.effect == effect; });
  for (CandidateFit& c : *candidates) {
    if (c.effect != effect && c.weight == front_weight) {
      c.weight = candidates->front().weight;
      break;
    }
  }
  candidates->front().weight = front_weight;
}

CauseStep StepOf(const CandidateFit& f, double before, double rms_none, double sigma) {
  CauseStep s;
  s.effect = f.effect;
  s.num_parameters = f.num_parameters;
  s.rms_before = before;
  s.rms_after = f.heldout_rms;
  s.excess_removed = ExcessRemoved(rms_none, f.heldout_rms, sigma) - ExcessRemoved(rms_none, before, sigma);
  s.parameters = f.parameters;
  s.sigmas = f.sigmas;
  return s;
}

}  // namespace

PlausibilityBounds BoundsFor(const kinematics::RobotModel& model) {
  double reach = 0.0;
  for (const kinematics::LinkParams& l : model.links) reach += std::abs(l.a) + std::abs(l.d);
  PlausibilityBounds b;
  b.length_mm = std::max(2.0, 0.005 * reach);
  b.drift_mm = std::max(1.0, 0.001 * reach);
  b.tool_mm = std::max(20.0, 0.05 * reach);
  return b;
}

void CheckPlausibility(const PlausibilityBounds& bounds, CandidateFit* fit) {
  for (const auto& [key, value] : fit->parameters) {
    const auto s = fit->sigmas.find(key);
    const std::string why = Bound(key, value, s == fit->sigmas.end() ? 0.0 : s->second, bounds);
    if (!why.empty()) fit->implausible += (fit->implausible.empty() ? "" : "; ") + why;
  }
}

bool IsDriftEffect(const std::string& effect) {
  const RobotCauseCode* code = FindRobotCause(effect);
  return code != nullptr && code->drift;
}

std::string PreferStatic(const RowSet& rs, const std::vector<Evaluated>& evaluated,
                         std::vector<CandidateFit>* candidates) {
  if (candidates->empty() || !IsDriftEffect(candidates->front().effect)) return "";
  const Evaluated* drift = nullptr;
  const Evaluated* best_static = nullptr;
  for (const Evaluated& e : evaluated) {
    if (e.fit.effect == candidates->front().effect) drift = &e;
  }
  for (const CandidateFit& c : *candidates) {
    if (c.effect == kNoEffect || IsDriftEffect(c.effect) || !c.implausible.empty()) continue;
    for (const Evaluated& e : evaluated) {
      if (e.fit.effect == c.effect) best_static = &e;
    }
    break;  // candidates are sorted by score: the first static one is the best
  }
  if (drift == nullptr || best_static == nullptr) return "";
  const double z = HeldoutDifferenceZ(rs, drift->cv.heldout_residual, best_static->cv.heldout_residual);
  if (z < -2.0) return "";  // the drift predicts better by more than two standard errors
  const std::string moved = best_static->fit.effect;
  MoveToFront(moved, candidates);
  return "'" + drift->fit.effect + "' is not claimed: the static '" + moved +
         "' predicts the held-out poses as well (difference " + Num(z) +
         " standard errors); a drift is named only beyond the best static model";
}

// Share of the excess left above the noise floor (mean square) a further cause must remove.
constexpr double kMinStepShare = 0.05;

std::string PreferSpecific(std::vector<CandidateFit>* candidates, double min_improvement) {
  if (candidates->empty() || candidates->front().effect != "geometric") return "";
  double none_score = 0.0;
  for (const CandidateFit& c : *candidates) {
    if (c.effect == kNoEffect) none_score = c.score;
  }
  // The best-scoring other candidate (they are sorted by score) that pays on its own.
  for (const CandidateFit& c : *candidates) {
    if (c.effect == "geometric" || c.effect == kNoEffect || !c.implausible.empty()) continue;
    if (none_score - c.score < min_improvement) return "";

    const std::string moved = c.effect;
    MoveToFront(moved, candidates);
    return "'" + moved + "' pays on its own and is named before the whole 'geometric' calibration, which is "
           "added after it only if it still pays";
  }
  return "";
}

std::vector<CauseStep> ForwardSelect(const Context& ctx, const Evaluated& first, double rms_none, double sigma,
                                     double explained_share, const PlausibilityBounds& bounds,
                                     std::vector<std::string>* findings, Evaluated* last) {
  std::vector<CauseStep> steps = {StepOf(first.fit, rms_none, rms_none, sigma)};
  *last = first;
  Context next = ctx;
  for (int k = 1; k < 6; ++k) {
    if (ExcessRemoved(rms_none, last->fit.heldout_rms, sigma) >= explained_share) break;
    if (last->fit.heldout_rms <= 1.05 * sigma) break;  // at the noise floor: nothing left to name
    next.base = last->design;
    next.base_cv = last->cv;
    std::vector<std::string> notes;
    std::vector<Evaluated> evaluated = EvaluateCandidates(next, &notes);
    std::vector<CandidateFit> fits;
    CandidateFit none;
    none.effect = kNoEffect;
    none.train_rms = next.base_cv.TrainRms();
    none.heldout_rms = next.base_cv.HeldoutRms();
    none.heldout_count = next.base_cv.heldout_n;
    fits.push_back(none);
    for (Evaluated& e : evaluated) {
      CheckPlausibility(bounds, &e.fit);
      fits.push_back(e.fit);
    }
    SelectCandidate(&fits);
    PreferStatic(*ctx.rows, evaluated, &fits);
    PreferSpecific(&fits, 10.0);
    // The first candidate in this order that beats the current model by the score margin and
    // removes kMinStepShare of the excess left above the noise floor.
    double none_score = 0.0;
    for (const CandidateFit& c : fits) {
      if (c.effect == kNoEffect) none_score = c.score;
    }
    const CandidateFit* pick = nullptr;
    for (const CandidateFit& c : fits) {
      if (c.effect == kNoEffect) {
        if (pick == nullptr && &c == &fits.front()) break;  // nothing beats the current model
        continue;
      }
      if (!c.implausible.empty() || none_score - c.score < 10.0) continue;
      if (ExcessRemoved(last->fit.heldout_rms, c.heldout_rms, sigma) < kMinStepShare) continue;
      pick = &c;
      break;
    }
    if (pick == nullptr) break;
    const CandidateFit best = *pick;
    const Evaluated* chosen = nullptr;
    for (const Evaluated& e : evaluated) {
      if (e.fit.effect == best.effect) chosen = &e;
    }
    if (chosen == nullptr) break;
    // The same effect again (cyclic terms on further joints): one cause, its gains summed.
    CauseStep step = StepOf(best, last->fit.heldout_rms, rms_none, sigma);
    auto same = std::find_if(steps.begin(), steps.end(), [&](const CauseStep& c) { return c.effect == best.effect; });
    if (same != steps.end()) {
      same->rms_after = step.rms_after;
      same->excess_removed += step.excess_removed;
      same->num_parameters += step.num_parameters;
      for (const auto& [key, v] : step.parameters) same->parameters[key] = v;
      for (const auto& [key, v] : step.sigmas) same->sigmas[key] = v;
    } else {
      steps.push_back(step);
    }
    findings->push_back("step " + std::to_string(k + 1) + ": '" + best.effect + "' added on top of the causes kept, " +
                        "held-out RMS " + Num(last->fit.heldout_rms) + " -> " + Num(best.heldout_rms) + " mm");
    *last = *chosen;
    last->fit = best;
  }
  return steps;
}

}  // namespace ramtk::diagnose::robot_detail
