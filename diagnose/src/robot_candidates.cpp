#include "robot_candidates.h"

#include <algorithm>
#include <cmath>

#include "ramtk/core/units.h"
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
std::vector<int> Identifiable(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params) {
  const std::vector<int> keep = IndependentColumns(PooledBlocks(d), ParamBlocks(rows, params));
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

// Per-cycle parameters from row `first` of p: their range over the cycles, in file units.
void ReportCycleRanges(const Design& d, const CvResult& cv, const std::vector<int>& params, int first,
                       CandidateFit* f) {
  for (size_t k = 0; k < params.size(); ++k) {
    const Eigen::VectorXd series = cv.full.p.row(first + static_cast<int>(k)).transpose();
    const auto [key, factor] = ParamKey(params[k], "_drift_range");
    f->parameters[key] = factor * (series.maxCoeff() - series.minCoeff());
  }
  (void)d;
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
  const int steps = 7;
  auto tick = [&](const std::string& what) {
    if (ctx.progress) ctx.progress({"diagnose robot: " + what, static_cast<size_t>(++step), steps});
  };

  // Static parameter errors (joint zeros, link lengths), against the set-up nuisance.
  auto static_params = [&](const std::string& effect, const std::vector<int>& pool, const std::string& suffix) {
    const std::vector<int> params = Identifiable(rows, ctx.base, pool);
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

  // Thermal drift: per-cycle lengths, then angles added greedily by held-out score.
  if (multi_cycle) {
    std::vector<int> new_lengths;
    for (int p : lengths)
      if (std::find(ctx.input->thermal_params.begin(), ctx.input->thermal_params.end(), p) ==
          ctx.input->thermal_params.end())
        new_lengths.push_back(p);
    new_lengths = IdentifiablePerCycle(rows, ctx.base, new_lengths);
    Design start = ctx.base;
    CvResult start_cv = ctx.base_cv;
    if (!new_lengths.empty()) {
      Evaluated e;
      e.design = WithParams(ctx, ctx.base, new_lengths, true);
      e.cv = Cv(ctx, e.design);
      e.fit = MakeFit("thermal_length_drift", static_cast<int>(new_lengths.size()) * num_cycles, e.cv);
      e.added_cycle_params = new_lengths;
      ReportCycleRanges(e.design, e.cv, new_lengths, ctx.base.np, &e.fit);
      e.note = "thermal_length_drift: per cycle " + thermal::ParamListToString(new_lengths);
      start = e.design;
      start_cv = e.cv;
      out.push_back(std::move(e));
    } else {
      notes->push_back("thermal_length_drift: already in the current model (" + ctx.input->thermal_label + ")");
    }
    tick("thermal_length_drift");
    std::vector<int> pool = Identifiable(rows, start, angles);
    std::vector<int> chosen;
    Design current = start;
    CvResult current_cv = start_cv;
    const int n = start_cv.heldout_n;
    double current_score = Score(current_cv.heldout_ss, n, 0);
    int added = 0;
    while (!pool.empty() && added < 6) {
      double best = INFINITY;
      int best_k = -1;
      CvResult best_cv;
      for (size_t k = 0; k < pool.size(); ++k) {
        const Design d = WithParams(ctx, current, {pool[k]}, true);
        CvResult cv = Cv(ctx, d);
        const double s = Score(cv.heldout_ss, n, (added + 1) * num_cycles);
        if (s < best) best = s, best_k = static_cast<int>(k), best_cv = std::move(cv);
      }
      if (best_k < 0 || !(best < current_score - ctx.min_improvement)) break;
      chosen.push_back(pool[best_k]);
      current = WithParams(ctx, current, {pool[best_k]}, true);
      current_cv = std::move(best_cv);
      current_score = best;
      pool.erase(pool.begin() + best_k);
      ++added;
    }
    if (!chosen.empty()) {
      Evaluated e;
      e.design = current;
      e.cv = current_cv;
      std::vector<int> all_added = new_lengths;
      all_added.insert(all_added.end(), chosen.begin(), chosen.end());
      e.added_cycle_params = all_added;
      e.fit = MakeFit("thermal_angle_drift", static_cast<int>(all_added.size()) * num_cycles, e.cv);
      ReportCycleRanges(e.design, e.cv, all_added, ctx.base.np, &e.fit);
      e.note = "thermal_angle_drift: add " + thermal::ParamListToString(chosen) +
               (new_lengths.empty() ? "" : " to the per-cycle lengths " + thermal::ParamListToString(new_lengths));
      out.push_back(std::move(e));
    } else {
      notes->push_back("thermal_angle_drift: no angle parameter improves the held-out score");
    }
    tick("thermal_angle_drift");
  } else {
    notes->push_back("thermal candidates need at least 3 cycles");
  }

  // Joint compliance: Δθ_j = c_j·τ_j(q), τ from a generic gravity load (robot_linear.h).
  {
    std::vector<Mat3X> cols;
    for (const Row& r : rows) {
      const Eigen::Matrix<double, 6, 1> tau =
          GravityTorques(model, r.q, ctx.rows->setup.ball_in_flange) / 1000.0;  // kN·m
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
      Evaluated e;
      e.design = ctx.base;
      std::vector<std::string> names;
      std::vector<std::pair<std::string, double>> keys;
      for (int k : keep) {
        names.push_back("c" + std::to_string(k + 2));
        keys.emplace_back("joint" + std::to_string(k + 2) + "_compliance_urad_per_kNm", 1e6);
      }
      AddStaticColumns(SelectColumns(cols, keep), names, &e.design);
      e.cv = Cv(ctx, e.design);
      e.fit = MakeFit("joint_compliance", static_cast<int>(keep.size()), e.cv);
      ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
      out.push_back(std::move(e));
    }
    tick("joint_compliance");
  }

  if (multi_cycle) {
    // Sensor frame drift: rotation and translation linear in time (sensor frame).
    std::vector<Mat3X> cols;
    for (const Row& r : rows) cols.push_back(r.time_h * r.j_setup.leftCols(6));
    const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
    if (!keep.empty()) {
      static const char* names[6] = {"rx_urad_per_h", "ry_urad_per_h", "rz_urad_per_h",
                                     "tx_mm_per_h",   "ty_mm_per_h",   "tz_mm_per_h"};
      Evaluated e;
      e.design = ctx.base;
      std::vector<std::string> col_names;
      std::vector<std::pair<std::string, double>> keys;
      for (int k : keep) col_names.push_back(names[k]), keys.emplace_back(names[k], k < 3 ? 1e6 : 1.0);
      AddStaticColumns(SelectColumns(cols, keep), col_names, &e.design);
      e.cv = Cv(ctx, e.design);
      e.fit = MakeFit("sensor_frame_drift", static_cast<int>(keep.size()), e.cv);
      ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
      out.push_back(std::move(e));
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
