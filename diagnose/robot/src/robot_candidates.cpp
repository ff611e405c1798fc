#include "robot_candidates.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "ramtk/core/units.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::diagnose::robot_detail {
namespace {

using kinematics::kNumParams;
using kinematics::ParamKind;

// Pooled blocks of a design for the independence check: static and per-cycle columns side by side.
std::vector<Mat3X> PooledBlocks(const Design& d) {
  std::vector<Mat3X> out(d.stat.size());
  for (size_t i = 0; i < d.stat.size(); ++i) {
    out[i].resize(3, d.ns + d.np);
    out[i].leftCols(d.ns) = d.stat[i];
    out[i].rightCols(d.np) = d.cycle[i];
  }
  return out;
}

std::vector<Mat3X> ParamBlocks(const std::vector<Row>& rows, const std::vector<int>& params) {
  std::vector<Mat3X> out;
  for (const Row& r : rows) {
    Mat3X m(3, params.size());
    for (size_t j = 0; j < params.size(); ++j) m.col(j) = r.j_param.col(params[j]);
    out.push_back(m);
  }
  return out;
}

// Parameters among `params` not aliased with the design's columns (nor with earlier ones).
std::vector<int> Identifiable(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params,
                              double rtol = 1e-5) {
  const std::vector<int> keep = IndependentColumns(PooledBlocks(d), ParamBlocks(rows, params), rtol);
  std::vector<int> out;
  for (int k : keep) out.push_back(params[k]);
  return out;
}

// Per-cycle parameters among `params` not aliased with the design's per-cycle columns. Static
// columns are left out of this check: a per-cycle copy of a static direction (d6 against the ball
// offset) still varies from cycle to cycle, which the shared static parameter cannot follow.
std::vector<int> IdentifiablePerCycle(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params) {
  const std::vector<int> keep = IndependentColumns(d.cycle, ParamBlocks(rows, params));
  std::vector<int> out;
  for (int k : keep) out.push_back(params[k]);
  return out;
}

// Drift terms of the thermal candidates: per-cycle parameters (power −1) or static columns of a
// parameter times τ^power, in design order.
struct ThermalTerms {
  std::vector<std::pair<int, int>> cycle;   // (param, -1), per-cycle columns after the base's
  std::vector<std::pair<int, int>> smooth;  // (param, power), static columns after the base's
};

// Adds drift columns of `params`; returns the number of parameters added (0: all aliased).
int AddDrift(const Context& ctx, const std::vector<int>& params, bool per_cycle, Design* d, ThermalTerms* terms) {
  const std::vector<Row>& rows = ctx.rows->rows;
  if (per_cycle) {
    const std::vector<int> keep = IdentifiablePerCycle(rows, *d, params);
    const int first = d->np;
    AddParamColumns(rows, keep, true, d);
    // A drift is a change from the first (reference) cycle, as in thesis eq. 3-8: the first cycle's
    // values are 0, so a constant error stays with the static candidates.
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i].cycle_pos == 0) d->cycle[i].rightCols(d->np - first).setZero();
    for (int p : keep) terms->cycle.emplace_back(p, -1);
    return static_cast<int>(keep.size()) * ctx.rows->num_cycles;
  }
  double span = 0;
  for (const Row& r : rows) span = std::max(span, r.time_h);
  if (!(span > 0)) return 0;
  std::vector<Mat3X> cols;
  for (const Row& r : rows) {
    const double tau = r.time_h / span;
    Mat3X m(3, 3 * params.size());
    for (size_t k = 0; k < params.size(); ++k)
      for (int pw = 0; pw < 3; ++pw) m.col(3 * k + pw) = r.j_param.col(params[k]) * std::pow(tau, pw);
    cols.push_back(m);
  }
  const std::vector<int> keep = IndependentColumns(PooledBlocks(*d), cols);
  std::vector<std::string> names;
  for (int c : keep) {
    terms->smooth.emplace_back(params[c / 3], c % 3);
    names.push_back(kinematics::ParamName(params[c / 3]) + "*t^" + std::to_string(c % 3));
  }
  AddStaticColumns(SelectColumns(cols, keep), names, d);
  return static_cast<int>(keep.size());
}

double Score(double ss, int n, int k) { return n * std::log(std::max(ss / std::max(n, 1), 1e-300)) + 2.0 * k; }

CandidateFit MakeFit(const std::string& effect, int k, const CvResult& cv) {
  CandidateFit f;
  f.effect = effect;
  f.num_parameters = k;
  f.train_rms = cv.TrainRms();
  f.heldout_rms = cv.HeldoutRms();
  f.heldout_count = cv.heldout_n;
  return f;
}

// Static parameters of the design from column `first` on, with units, into the fit.
void ReportStatic(const Design& d, const CvResult& cv, int first, double sigma,
                  const std::vector<std::pair<std::string, double>>& key_and_factor, CandidateFit* f) {
  for (int j = first; j < d.ns; ++j) {
    const auto& [key, factor] = key_and_factor[j - first];
    f->parameters[key] = factor * cv.full.s[j];
    const double var = cv.full.s_cov_unit(j, j);
    if (var > 0) f->sigmas[key] = std::abs(factor) * sigma * std::sqrt(var);
  }
}

std::pair<std::string, double> ParamKey(int p, const std::string& suffix = "") {
  const bool angle = kinematics::IsAngleParam(p);
  return {kinematics::ParamName(p) + suffix + (angle ? "_deg" : "_mm"), angle ? kDegPerRad : 1.0};
}

// The drift of each added parameter per cycle (file units: mm, µrad) and its range over the cycles.
void ReportDrift(const Context& ctx, const CvResult& cv, const ThermalTerms& terms, const std::vector<int>& params,
                 Evaluated* e) {
  const int num_cycles = ctx.rows->num_cycles;
  std::vector<double> tau(num_cycles, 0.0);
  std::vector<int> count(num_cycles, 0);
  double span = 0;
  for (const Row& r : ctx.rows->rows) span = std::max(span, r.time_h);
  for (const Row& r : ctx.rows->rows) tau[r.cycle_pos] += span > 0 ? r.time_h / span : 0.0, ++count[r.cycle_pos];
  for (int c = 0; c < num_cycles; ++c) tau[c] /= std::max(1, count[c]);
  e->added_series = Eigen::MatrixXd::Zero(params.size(), num_cycles);
  const int first_cycle = static_cast<int>(cv.full.p.rows()) - static_cast<int>(terms.cycle.size());
  const int first_static = static_cast<int>(cv.full.s.size()) - static_cast<int>(terms.smooth.size());
  for (size_t k = 0; k < params.size(); ++k) {
    const double unit = kinematics::IsAngleParam(params[k]) ? 1e6 : 1.0;
    for (size_t j = 0; j < terms.cycle.size(); ++j)
      if (terms.cycle[j].first == params[k]) e->added_series.row(k) = unit * cv.full.p.row(first_cycle + j);
    for (size_t j = 0; j < terms.smooth.size(); ++j)
      if (terms.smooth[j].first == params[k])
        for (int c = 0; c < num_cycles; ++c)
          e->added_series(k, c) += unit * cv.full.s[first_static + j] * std::pow(tau[c], terms.smooth[j].second);
    const Eigen::VectorXd series = e->added_series.row(k).transpose();
    const bool angle = kinematics::IsAngleParam(params[k]);
    e->fit.parameters[kinematics::ParamName(params[k]) + "_drift_range" + (angle ? "_deg" : "_mm")] =
        (series.maxCoeff() - series.minCoeff()) / unit * (angle ? kDegPerRad : 1.0);
  }
}

Design WithParams(const Context& ctx, const Design& start, const std::vector<int>& params, bool per_cycle) {
  Design d = start;
  AddParamColumns(ctx.rows->rows, params, per_cycle, &d);
  return d;
}

CvResult Cv(const Context& ctx, const Design& d) {
  return CrossValidate(ctx.rows->rows, d, ctx.fold_of_row, ctx.folds, ctx.rows->num_cycles);
}

}  // namespace

Design CurrentModelDesign(const RobotDiagnoseInput& in, const RowSet& rs) {
  Design d = NuisanceDesign(rs.rows);
  if (!in.thermal_params.empty()) AddParamColumns(rs.rows, in.thermal_params, /*per_cycle=*/true, &d);
  return d;
}

std::vector<Evaluated> EvaluateCandidates(const Context& ctx, std::vector<std::string>* notes) {
  const std::vector<Row>& rows = ctx.rows->rows;
  const kinematics::RobotModel& model = ctx.input->model;
  const int num_cycles = ctx.rows->num_cycles;
  const bool multi_cycle = num_cycles >= 3;
  std::vector<Evaluated> out;
  int step = 0;
  const size_t steps = multi_cycle ? 9 : 5;
  auto tick = [&](const std::string& what) {
    if (ctx.progress) ctx.progress({"diagnose robot: " + what, static_cast<size_t>(++step), steps});
  };

  // Static parameter errors (joint zeros, link lengths), against the set-up nuisance.
  auto static_params = [&](const std::string& effect, const std::vector<int>& pool, const std::string& suffix,
                           double rtol = 1e-5) {
    const std::vector<int> params = Identifiable(rows, ctx.base, pool, rtol);
    if (params.size() < pool.size() && rtol > 1e-5) {
      std::vector<int> weak;
      const std::vector<int> structural = Identifiable(rows, ctx.base, pool);
      for (int p : structural)
        if (std::find(params.begin(), params.end(), p) == params.end()) weak.push_back(p);
      if (!weak.empty()) {
        notes->push_back(effect + ": " + thermal::ParamListToString(weak) +
                         " left out (less than " + std::to_string(rtol) +
                         " of each column outside the others: not identifiable from these poses)");
      }
    }
    if (params.empty()) {
      notes->push_back(effect + ": not testable (every parameter aliased with the current model)");
      return;
    }
    Evaluated e;
    e.design = WithParams(ctx, ctx.base, params, false);
    e.cv = Cv(ctx, e.design);
    e.fit = MakeFit(effect, static_cast<int>(params.size()), e.cv);
    std::vector<std::pair<std::string, double>> keys;
    for (int p : params) keys.push_back(ParamKey(p, suffix));
    ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
    e.note = effect + ": " + thermal::ParamListToString(params);
    out.push_back(std::move(e));
  };
  // A candidate made of extra constant-coefficient columns (the kept ones of `cols`).
  auto column_candidate = [&](const std::string& effect, const std::vector<Mat3X>& cols, const std::vector<int>& keep,
                              const std::vector<std::string>& col_names,
                              const std::vector<std::pair<std::string, double>>& keys) {
    Evaluated e;
    e.design = ctx.base;
    AddStaticColumns(SelectColumns(cols, keep), col_names, &e.design);
    e.cv = Cv(ctx, e.design);
    e.fit = MakeFit(effect, static_cast<int>(keep.size()), e.cv);
    ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
    out.push_back(std::move(e));
  };
  std::vector<int> thetas, lengths = thermal::TraditionalParams(model), angles;
  for (int p = 0; p < kNumParams; ++p) {
    if (model.structural_zero[p]) continue;
    if (kinematics::ParamKindOf(p) == ParamKind::kTheta) thetas.push_back(p);
    if (kinematics::IsAngleParam(p)) angles.push_back(p);
  }
  static_params("joint_offset", thetas, "_offset");
  tick("joint_offset");
  static_params("link_length_error", lengths, "_error");
  tick("link_length_error");
  // Static twists of the joint axes (α, and β where consecutive axes are near-parallel, thesis
  // §2.2.3), and the whole static kinematic calibration as one candidate (every link parameter the
  // set-up does not absorb). β is offered on near-parallel axes also when the file is DH.
  {
    std::vector<int> twists, geometric;
    for (int p = 0; p < kNumParams; ++p) {
      const int j = kinematics::ParamJointOf(p);
      const bool parallel = std::abs(std::sin(model.links[j].alpha)) < std::sin(DegToRad(10.0));
      const bool offered = !model.structural_zero[p] || (kinematics::ParamKindOf(p) == ParamKind::kBeta && parallel);
      if (!offered) continue;
      geometric.push_back(p);
      const ParamKind kind = kinematics::ParamKindOf(p);
      if (kind == ParamKind::kAlpha || kind == ParamKind::kBeta) twists.push_back(p);
    }
    // Weakly observable directions would carry model error into wild values: a column must keep
    // 0.1% of its norm outside the others' span (as the robot calibration's weak tolerance).
    static_params("axis_misalignment", twists, "_twist", 1e-3);
    static_params("geometric", geometric, "_error", 1e-3);
    tick("geometric");
  }

  // Thermal drift: lengths, then angles added greedily by held-out score; each in two forms, free
  // per cycle (thesis eq. 3-8) and smooth in time (a + b·τ + c·τ², τ = time / span), the better
  // score kept.
  if (multi_cycle) {
    std::vector<int> new_lengths;
    for (int p : lengths)
      if (std::find(ctx.input->thermal_params.begin(), ctx.input->thermal_params.end(), p) ==
          ctx.input->thermal_params.end())
        new_lengths.push_back(p);
    if (new_lengths.empty())
      notes->push_back("thermal_length_drift: already in the current model (" + ctx.input->thermal_label + ")");
    std::vector<Evaluated> forms[2];  // [length, angle] per form
    for (int form = 0; form < 2; ++form) {
      const bool per_cycle = form == 0;
      ThermalTerms terms;
      Design start = ctx.base;
      CvResult start_cv = ctx.base_cv;
      int start_k = 0;
      std::vector<int> lengths_used;
      if (!new_lengths.empty()) {
        lengths_used = new_lengths;
        Evaluated e;
        e.design = ctx.base;
        const int k = AddDrift(ctx, new_lengths, per_cycle, &e.design, &terms);
        if (k > 0) {
          e.cv = Cv(ctx, e.design);
          e.fit = MakeFit("thermal_length_drift", k, e.cv);
          e.added_cycle_params = new_lengths;
          ReportDrift(ctx, e.cv, terms, new_lengths, &e);
          e.note = std::string("thermal_length_drift (") + (per_cycle ? "per cycle" : "smooth in time") +
                   "): " + thermal::ParamListToString(new_lengths);
          start = e.design, start_cv = e.cv, start_k = k;
          forms[form].push_back(std::move(e));
        } else {
          lengths_used.clear();
        }
      }
      std::vector<int> pool = Identifiable(rows, start, angles);
      std::vector<int> chosen;
      Design current = start;
      CvResult current_cv = start_cv;
      ThermalTerms current_terms = terms;
      const int n = start_cv.heldout_n;
      int current_k = start_k;
      double current_score = Score(current_cv.heldout_ss, n, 0);
      while (!pool.empty() && chosen.size() < 6) {
        double best = INFINITY;
        int best_k = -1, best_count = 0;
        CvResult best_cv;
        Design best_design;
        ThermalTerms best_terms;
        for (size_t k = 0; k < pool.size(); ++k) {
          Design d = current;
          ThermalTerms t = current_terms;
          const int added = AddDrift(ctx, {pool[k]}, per_cycle, &d, &t);
          if (added == 0) continue;
          CvResult cv = Cv(ctx, d);
          const double sc = Score(cv.heldout_ss, n, added + current_k - start_k);
          if (sc < best)
            best = sc, best_k = static_cast<int>(k), best_cv = std::move(cv), best_design = std::move(d),
            best_terms = std::move(t), best_count = added;
        }
        if (best_k < 0 || !(best < current_score - ctx.min_improvement)) break;
        chosen.push_back(pool[best_k]);
        current = std::move(best_design);
        current_cv = std::move(best_cv);
        current_terms = std::move(best_terms);
        current_k += best_count;
        current_score = best;
        pool.erase(pool.begin() + best_k);
      }
      if (!chosen.empty()) {
        Evaluated e;
        e.design = current;
        e.cv = current_cv;
        std::vector<int> all_added = lengths_used;
        all_added.insert(all_added.end(), chosen.begin(), chosen.end());
        e.added_cycle_params = all_added;
        e.fit = MakeFit("thermal_angle_drift", current_k, e.cv);
        ReportDrift(ctx, e.cv, current_terms, all_added, &e);
        e.note = std::string("thermal_angle_drift (") + (per_cycle ? "per cycle" : "smooth in time") + "): add " +
                 thermal::ParamListToString(chosen) +
                 (lengths_used.empty() ? "" : " to the drifting lengths " + thermal::ParamListToString(lengths_used));
        forms[form].push_back(std::move(e));
      }
    }
    tick("thermal drift");
    // A drift must change with time: a thermal candidate whose held-out score a static error of
    // the same parameters matches (within min_improvement) is a static effect (joint compliance, a
    // zero or length error) seen through constant drift terms, and is dropped.
    for (auto& list : forms)
      for (auto it = list.begin(); it != list.end();) {
        const std::vector<int> params = Identifiable(rows, ctx.base, it->added_cycle_params);
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
        it = is_static ? list.erase(it) : it + 1;
      }
    for (const char* effect : {"thermal_length_drift", "thermal_angle_drift"}) {
      Evaluated* best = nullptr;
      for (auto& list : forms)
        for (Evaluated& e : list)
          if (e.fit.effect == effect &&
              (best == nullptr || Score(e.cv.heldout_ss, e.cv.heldout_n, e.fit.num_parameters) <
                                      Score(best->cv.heldout_ss, best->cv.heldout_n, best->fit.num_parameters)))
            best = &e;
      if (best != nullptr)
        out.push_back(std::move(*best));
      else if (std::string(effect) == "thermal_angle_drift")
        notes->push_back("thermal_angle_drift: no angle parameter improves the held-out score");
    }
    tick("thermal drift");
  } else {
    notes->push_back("thermal candidates need at least 3 cycles");
  }

  // Joint compliance: Δθ_j = c_j·τ_j(q), τ from a generic gravity load (robot_linear.h).
  {
    std::vector<Mat3X> cols;
    const bool masses = ctx.input->chain.HasMasses();
    if (!masses) {
      notes->push_back(
          "joint_compliance: the robot file has no link masses; a generic load (0.1 kg/mm along the links, 20 kg at "
          "the ball) shapes the torques, so the fitted compliance values are relative, not physical");
    }
    for (const Row& r : rows) {
      Eigen::Matrix<double, 6, 1> tau;
      if (masses) {
        // kg·mm of the file's masses times g, in kN·m.
        tau = kinematics::GravityTorques(ctx.input->chain, r.q) * 9.81e-6;
      } else {
        tau = GravityTorques(model, r.q, ctx.rows->setup.ball_in_flange) / 1000.0;  // kN·m
      }
      Mat3X m(3, 5);
      for (int j = 1; j < 6; ++j) m.col(j - 1) = r.j_param.col(kinematics::ParamIndex(ParamKind::kTheta, j)) * tau[j];
      cols.push_back(m);
    }
    // Joints whose load hardly varies (joint 6 about the flange axis) would only add noise.
    Eigen::VectorXd size = Eigen::VectorXd::Zero(5);
    for (const Mat3X& m : cols) size += m.colwise().squaredNorm().transpose();
    std::vector<int> loaded;
    for (int j = 0; j < 5; ++j)
      if (size[j] > 0.01 * size.maxCoeff()) loaded.push_back(j);
    std::vector<int> keep;
    for (int k : IndependentColumns(PooledBlocks(ctx.base), SelectColumns(cols, loaded))) keep.push_back(loaded[k]);
    if (!keep.empty()) {
      std::vector<std::string> names;
      std::vector<std::pair<std::string, double>> keys;
      for (int k : keep) {
        names.push_back("c" + std::to_string(k + 2));
        keys.emplace_back("joint" + std::to_string(k + 2) + "_compliance_urad_per_kNm", 1e6);
      }
      column_candidate("joint_compliance", cols, keep, names, keys);
    }
    tick("joint_compliance");
  }

  // Joint cyclic error (encoder eccentricity, gear run-out): Δθ_j = a·sin q_j + b·cos q_j +
  // c·sin 2q_j + d·cos 2q_j. Joints added greedily by held-out score (each must pay
  // min_improvement), at most two.
  {
    auto joint_cols = [&](int j) {
      std::vector<Mat3X> cols;
      const int theta = kinematics::ParamIndex(ParamKind::kTheta, j + 1);
      for (const Row& r : rows) {
        Mat3X m(3, 4);
        const double q = r.q[j];
        m.col(0) = r.j_param.col(theta) * std::sin(q);
        m.col(1) = r.j_param.col(theta) * std::cos(q);
        m.col(2) = r.j_param.col(theta) * std::sin(2 * q);
        m.col(3) = r.j_param.col(theta) * std::cos(2 * q);
        cols.push_back(m);
      }
      return cols;
    };
    Design current = ctx.base;
    const int n = ctx.base_cv.heldout_n;
    double current_score = Score(ctx.base_cv.heldout_ss, n, 0);
    int current_k = 0;
    std::vector<int> joints;
    std::vector<std::pair<std::string, double>> keys;
    CvResult current_cv;
    while (joints.size() < 2) {
      double best = INFINITY;
      int best_j = -1;
      Design best_design;
      CvResult best_cv;
      std::vector<std::pair<std::string, double>> best_keys;
      int best_added = 0;
      for (int j = 0; j < 6; ++j) {
        if (std::find(joints.begin(), joints.end(), j) != joints.end()) continue;
        // Once per turn (eccentricity: sin/cos q) or once and twice per turn (+ sin/cos 2q).
        for (const int terms : {2, 4}) {
          const std::vector<Mat3X> all = joint_cols(j);
          const std::vector<Mat3X> cols = SelectColumns(all, terms == 2 ? std::vector<int>{0, 1} : std::vector<int>{0, 1, 2, 3});
          const std::vector<int> keep = IndependentColumns(PooledBlocks(current), cols);
          if (keep.empty()) continue;
          static const char* kTerm[4] = {"sin_q", "cos_q", "sin_2q", "cos_2q"};
          std::vector<std::string> names;
          std::vector<std::pair<std::string, double>> ks;
          for (int k : keep) {
            names.push_back("q" + std::to_string(j + 1) + "_" + kTerm[k]);
            ks.emplace_back("joint" + std::to_string(j + 1) + "_" + kTerm[k] + "_deg", kDegPerRad);
          }
          Design d = current;
          AddStaticColumns(SelectColumns(cols, keep), names, &d);
          CvResult cv = Cv(ctx, d);
          const int added = static_cast<int>(keep.size());
          // A joint whose fitted cycle is beyond a plausible amplitude is aliased with something
          // else (the set-up, another joint): it is not offered.
          bool plausible = cv.full.ok;
          for (int k = 0; k < added && plausible; ++k) {
            plausible = std::abs(cv.full.s[d.ns - added + k]) * kDegPerRad <= PlausibilityBounds{}.cyclic_deg;
          }
          if (!plausible) continue;
          const double sc = Score(cv.heldout_ss, n, current_k + added);
          if (sc < best)
            best = sc, best_j = j, best_design = std::move(d), best_cv = std::move(cv), best_keys = ks,
            best_added = added;
        }
      }
      if (best_j < 0 || !(best < current_score - ctx.min_improvement)) break;
      joints.push_back(best_j);
      current = std::move(best_design);
      current_cv = std::move(best_cv);
      current_score = best;
      current_k += best_added;
      keys.insert(keys.end(), best_keys.begin(), best_keys.end());
    }
    if (!joints.empty()) {
      Evaluated e;
      e.design = current;
      e.cv = current_cv;
      e.fit = MakeFit("joint_cyclic_error", current_k, e.cv);
      ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
      std::string list;
      for (int j : joints) {
        list += (list.empty() ? "q" : ", q") + std::to_string(j + 1);
        const auto value = [&](const std::string& k) {
          const auto it = e.fit.parameters.find(k);
          return it == e.fit.parameters.end() ? 0.0 : it->second;
        };
        const double a = value("joint" + std::to_string(j + 1) + "_sin_q_deg");
        const double b = value("joint" + std::to_string(j + 1) + "_cos_q_deg");
        e.fit.parameters["joint" + std::to_string(j + 1) + "_amplitude_1q_deg"] = std::hypot(a, b);
      }
      e.note = "joint_cyclic_error: sin/cos of q and 2q on " + list;
      out.push_back(std::move(e));
    } else {
      notes->push_back("joint_cyclic_error: no joint's cyclic terms improve the held-out score");
    }
    tick("joint_cyclic_error");
  }

  // Temperature-driven drift: link lengths and the sensor translation linear in a measured
  // temperature column (any extra column whose name contains "temp"); the best column kept.
  {
    Evaluated best;
    double best_score = INFINITY;
    for (const std::string& column : ctx.rows->extra_columns) {
      std::string lower = column;
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
      if (lower.find("temp") == std::string::npos) continue;
      double mean = 0;
      for (const Row& r : rows) {
        const auto it = r.extra.find(column);
        mean += it == r.extra.end() ? 0.0 : it->second;
      }
      mean /= std::max<size_t>(1, rows.size());
      std::vector<Mat3X> cols;
      for (const Row& r : rows) {
        const auto it = r.extra.find(column);
        const double dt = (it == r.extra.end() ? mean : it->second) - mean;
        Mat3X m(3, lengths.size() + 3);
        for (size_t k = 0; k < lengths.size(); ++k) m.col(k) = r.j_param.col(lengths[k]) * dt;
        m.rightCols(3) = r.j_setup.middleCols(3, 3) * dt;
        cols.push_back(m);
      }
      const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
      if (keep.empty()) continue;
      std::vector<std::string> names;
      std::vector<std::pair<std::string, double>> keys;
      for (int k : keep) {
        const std::string name = k < static_cast<int>(lengths.size())
                                     ? kinematics::ParamName(lengths[k]) + "_mm_per_K"
                                     : std::string(k - lengths.size() == 0 ? "tx" : k - lengths.size() == 1 ? "ty" : "tz") +
                                           "_mm_per_K";
        names.push_back(name), keys.emplace_back(name, 1.0);
      }
      Evaluated e;
      e.design = ctx.base;
      AddStaticColumns(SelectColumns(cols, keep), names, &e.design);
      e.cv = Cv(ctx, e.design);
      e.fit = MakeFit("temperature_driven_drift", static_cast<int>(keep.size()), e.cv);
      ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
      e.note = "temperature_driven_drift: lengths and sensor translation linear in column '" + column + "'";
      const double sc = Score(e.cv.heldout_ss, e.cv.heldout_n, e.fit.num_parameters);
      if (sc < best_score) best_score = sc, best = std::move(e);
    }
    if (std::isfinite(best_score))
      out.push_back(std::move(best));
    else
      notes->push_back("temperature_driven_drift: no temperature column in the data");
  }
  notes->push_back("backlash: not testable (the data carry no direction of approach)");

  if (multi_cycle) {
    // Sensor frame drift: rotation and translation, quadratic in time (sensor frame).
    std::vector<Mat3X> cols;
    for (const Row& r : rows) {
      Mat3X m(3, 12);
      m.leftCols(6) = r.time_h * r.j_setup.leftCols(6);
      m.rightCols(6) = r.time_h * r.time_h * r.j_setup.leftCols(6);
      cols.push_back(m);
    }
    const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
    if (!keep.empty()) {
      static const char* names[6] = {"rx_urad", "ry_urad", "rz_urad", "tx_mm", "ty_mm", "tz_mm"};
      std::vector<std::string> col_names;
      std::vector<std::pair<std::string, double>> keys;
      for (int k : keep) {
        const std::string name = std::string(names[k % 6]) + (k < 6 ? "_per_h" : "_per_h2");
        col_names.push_back(name), keys.emplace_back(name, k % 6 < 3 ? 1e6 : 1.0);
      }
      column_candidate("sensor_frame_drift", cols, keep, col_names, keys);
    }
    tick("sensor_frame_drift");

    // Tool offset change: the ball moves on the flange from some cycle on (step; cycle searched
    // on the training rows of every fold).
    const int n = static_cast<int>(rows.size());
    auto design_for = [&](int from) {
      std::vector<Mat3X> c;
      for (const Row& r : rows) c.push_back(r.cycle_pos >= from ? Mat3X(r.ball_dir) : Mat3X(Mat3X::Zero(3, 3)));
      Design d = ctx.base;
      AddStaticColumns(c, {"dx_mm", "dy_mm", "dz_mm"}, &d);
      return d;
    };
    std::vector<int> grid;
    const int stride = std::max(1, (num_cycles - 1) / 30);
    for (int c = 1; c < num_cycles; c += stride) grid.push_back(c);
    auto best_step = [&](const std::vector<char>& train, Fit* fit) {
      double best = INFINITY;
      int best_c = grid[0];
      *fit = SolveDesign(rows, design_for(grid[0]), train, num_cycles);  // defined even if no step is finite
      for (int c : grid) {
        const Design d = design_for(c);
        const Fit f = SolveDesign(rows, d, train, num_cycles);
        double ss = 0;
        for (int i = 0; i < n; ++i)
          if (train[i]) ss += FitResidual(rows, d, f, i).squaredNorm();
        if (ss < best) best = ss, best_c = c, *fit = f;
      }
      return best_c;
    };
    Evaluated e;
    e.cv.heldout_residual.assign(n, Eigen::Vector3d::Zero());
    for (int k = 0; k < ctx.folds; ++k) {
      std::vector<char> train(n);
      for (int i = 0; i < n; ++i) train[i] = ctx.fold_of_row[i] != k;
      Fit f;
      const int c = best_step(train, &f);
      const Design d = design_for(c);
      for (int i = 0; i < n; ++i) {
        if (train[i]) continue;
        const Eigen::Vector3d r = FitResidual(rows, d, f, i);
        e.cv.heldout_residual[i] = r;
        e.cv.heldout_ss += r.squaredNorm();
        e.cv.heldout_n += 3;
      }
    }
    Fit full;
    const int from = best_step(std::vector<char>(n, 1), &full);
    e.design = design_for(from);
    e.cv.full = full;
    for (int i = 0; i < n; ++i) e.cv.train_ss += FitResidual(rows, e.design, full, i).squaredNorm(), e.cv.train_n += 3;
    e.fit = MakeFit("tool_offset_change", 4, e.cv);
    ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, {{"dx_mm", 1.0}, {"dy_mm", 1.0}, {"dz_mm", 1.0}}, &e.fit);
    e.fit.parameters["from_cycle"] = ctx.rows->cycle_numbers[from];
    out.push_back(std::move(e));
    tick("tool_offset_change");
  }
  return out;
}

}  // namespace ramtk::diagnose::robot_detail
