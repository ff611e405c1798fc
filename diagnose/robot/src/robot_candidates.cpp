#include "robot_fit_kit.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "ramtk/core/units.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::diagnose::robot_detail {

using kinematics::kNumParams;
using kinematics::ParamKind;

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

std::vector<int> Identifiable(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params,
                              double rtol) {
  const std::vector<int> keep = IndependentColumns(PooledBlocks(d), ParamBlocks(rows, params), rtol);
  std::vector<int> out;
  for (int k : keep) out.push_back(params[k]);
  return out;
}

std::vector<int> IdentifiablePerCycle(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params) {
  const std::vector<int> keep = IndependentColumns(d.cycle, ParamBlocks(rows, params));
  std::vector<int> out;
  for (int k : keep) out.push_back(params[k]);
  return out;
}


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

void ReportStatic(const Design& d, const CvResult& cv, int first, double sigma,
                  const std::vector<std::pair<std::string, double>>& key_and_factor, CandidateFit* f) {
  for (int j = first; j < d.ns; ++j) {
    const auto& [key, factor] = key_and_factor[j - first];
    f->parameters[key] = factor * cv.full.s[j];
    const double var = cv.full.s_cov_unit(j, j);
    if (var > 0) f->sigmas[key] = std::abs(factor) * sigma * std::sqrt(var);
  }
}

std::pair<std::string, double> ParamKey(int p, const std::string& suffix) {
  const bool angle = kinematics::IsAngleParam(p);
  return {kinematics::ParamName(p) + suffix + (angle ? "_deg" : "_mm"), angle ? kDegPerRad : 1.0};
}

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

Design CurrentModelDesign(const RobotDiagnoseInput& in, const RowSet& rs) {
  Design d = NuisanceDesign(rs.rows);
  if (!in.thermal_params.empty()) AddParamColumns(rs.rows, in.thermal_params, /*per_cycle=*/true, &d);
  return d;
}

void FitStaticParams(const Context& ctx, CauseOutput out, const std::string& effect, const std::vector<int>& pool,
                     const std::string& suffix, double rtol) {
  const std::vector<Row>& rows = ctx.rows->rows;
  const std::vector<int> params = Identifiable(rows, ctx.base, pool, rtol);
  if (params.size() < pool.size() && rtol > 1e-5) {
    std::vector<int> weak;
    const std::vector<int> structural = Identifiable(rows, ctx.base, pool);
    for (int p : structural)
      if (std::find(params.begin(), params.end(), p) == params.end()) weak.push_back(p);
    if (!weak.empty()) {
      out.notes->push_back(effect + ": " + thermal::ParamListToString(weak) + " left out (less than " +
                           std::to_string(rtol) +
                           " of each column outside the others: not identifiable from these poses)");
    }
  }
  if (params.empty()) {
    out.notes->push_back(effect + ": not testable (every parameter aliased with the current model)");
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
  out.evaluated->push_back(std::move(e));
}

void FitColumns(const Context& ctx, CauseOutput out, const std::string& effect, const std::vector<Mat3X>& cols,
                const std::vector<int>& keep, const std::vector<std::string>& col_names,
                const std::vector<std::pair<std::string, double>>& keys) {
  Evaluated e;
  e.design = ctx.base;
  AddStaticColumns(SelectColumns(cols, keep), col_names, &e.design);
  e.cv = Cv(ctx, e.design);
  e.fit = MakeFit(effect, static_cast<int>(keep.size()), e.cv);
  ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
  out.evaluated->push_back(std::move(e));
}

std::vector<int> ThetaParams(const kinematics::RobotModel& model) {
  std::vector<int> out;
  for (int p = 0; p < kNumParams; ++p)
    if (!model.structural_zero[p] && kinematics::ParamKindOf(p) == ParamKind::kTheta) out.push_back(p);
  return out;
}

std::vector<int> AngleParams(const kinematics::RobotModel& model) {
  std::vector<int> out;
  for (int p = 0; p < kNumParams; ++p)
    if (!model.structural_zero[p] && kinematics::IsAngleParam(p)) out.push_back(p);
  return out;
}

std::vector<Evaluated> EvaluateCandidates(const Context& ctx, std::vector<std::string>* notes) {
  const int num_cycles = ctx.rows->num_cycles;
  auto runs = [&](const RobotCause& c) { return (c.code.fit != nullptr || c.extra) && num_cycles >= c.code.min_cycles; };
  size_t steps = 0;
  for (const RobotCause& c : RobotCauses()) steps += runs(c) ? 1 : 0;
  std::vector<Evaluated> out;
  size_t step = 0;
  for (const RobotCause& c : RobotCauses()) {
    if (!runs(c)) {
      if (num_cycles < c.code.min_cycles && *c.code.skip_note) notes->push_back(c.code.skip_note);
      continue;
    }
    if (c.extra)
      FitExtraCause(ctx, {&out, notes}, *c.extra);
    else
      c.code.fit(ctx, {&out, notes});
    if (ctx.progress) ctx.progress({"diagnose robot: " + c.name, ++step, steps});
  }
  return out;
}

}  // namespace ramtk::diagnose::robot_detail
