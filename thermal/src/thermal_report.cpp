#include "ramtk/thermal/thermal_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ramtk/core/units.h"

namespace ramtk::thermal {
namespace {

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string Names(const std::vector<int>& params) {
  std::string s;
  for (int p : params) s += (s.empty() ? "" : " ") + kinematics::ParamName(p);
  return s.empty() ? "-" : s;
}

std::vector<std::vector<std::string>> ComparisonRows(const std::vector<ComparisonRow>& rows) {
  std::vector<std::vector<std::string>> out;
  for (const ComparisonRow& r : rows)
    out.push_back({r.label, Names(r.params), std::to_string(r.num_poses), Fixed(r.lambda, 1),
                   Fixed(r.rms_residual_mm, 4), Fixed(r.worst_residual_mm, 4)});
  return out;
}

}  // namespace

report::Figure DriftFigure(const std::string& id, const std::string& caption, const Eigen::MatrixXd& delta_x,
                           const CycleSeries& cycles, const std::vector<int>& params, const Eigen::VectorXd& sigma) {
  report::Panel lengths, angles;
  lengths.title = "lengths", angles.title = "angles";
  lengths.x_label = angles.x_label = "time (h)";
  lengths.y_label = "drift (mm)", angles.y_label = "drift (mdeg)";
  for (int p : params) {
    report::Series s;
    s.label = kinematics::ParamName(p);
    s.style = report::SeriesStyle::kLinesPoints;
    const bool angle = kinematics::IsAngleParam(p);
    const auto unit = [angle](double v) { return angle ? RadToDeg(v) * 1000.0 : v; };
    const bool band = sigma.size() > p && std::isfinite(sigma(p)) && sigma(p) > 0;
    for (int c = 0; c < delta_x.cols() && c < cycles.NumCycles(); ++c) {
      s.x.push_back(cycles.cycles[c].time_s / 3600.0);
      s.y.push_back(unit(delta_x(p, c)));
      if (band) s.y_low.push_back(unit(delta_x(p, c) - sigma(p))), s.y_high.push_back(unit(delta_x(p, c) + sigma(p)));
    }
    (angle ? angles : lengths).series.push_back(std::move(s));
  }
  report::Figure f;
  f.id = id;
  f.caption = caption;
  if (!lengths.series.empty()) f.panels.push_back(lengths);
  if (!angles.series.empty()) f.panels.push_back(angles);
  return f;
}

report::HtmlReport ScreeningReport(const ThermalExperiment& e, const ScreeningSummary& s,
                                   const std::vector<ComparisonRow>& all_poses,
                                   const std::vector<ComparisonRow>& budget, double threshold_mm) {
  report::HtmlReport html("Thermal drift: parameter screening");
  html.Paragraph(s.BriefReport());
  html.KeyValues({{"ball cycles", std::to_string(e.ball.NumCycles())},
                  {"ball poses", std::to_string(e.ball.NumPoses())},
                  {"monitoring cycles", std::to_string(e.monitoring.NumCycles())},
                  {"selected", Names(s.selected)},
                  {"kept count chosen by", s.count_from_heldout ? "held-out error" : "fixed count"},
                  {"λ with every candidate (%)", Fixed(s.initial_lambda, 1)},
                  {"λ with the selected set (%)", Fixed(s.final_lambda, 1)},
                  {"threshold (mm)", Fixed(threshold_mm, 3)}});
  html.Section("Elimination (form of thesis Table 5-1)");
  std::vector<std::vector<std::string>> rows;
  report::Series lambda, heldout;
  lambda.label = "λ", heldout.label = "held-out RMS";
  lambda.style = heldout.style = report::SeriesStyle::kLinesPoints;
  for (const ScreeningStep& st : s.steps) {
    rows.push_back({std::to_string(st.card), st.removed < 0 ? "-" : kinematics::ParamName(st.removed),
                    Fixed(st.lambda, 1), Names(st.steady),
                    st.heldout_rms_mm > 0 ? Fixed(st.heldout_rms_mm * 1000.0, 2) : "",
                    st.heldout_rms_mm > 0 ? Fixed(st.heldout_z, 2) : ""});
    lambda.x.push_back(st.card), lambda.y.push_back(st.lambda);
    if (st.heldout_rms_mm > 0) heldout.x.push_back(st.card), heldout.y.push_back(st.heldout_rms_mm * 1000.0);
  }
  html.Table({"parameters", "removed", "λ (%)", "steady set S", "held-out RMS (µm)", "z to the best"}, rows);
  if (!lambda.x.empty()) {
    report::Figure f;
    f.id = "elimination";
    f.caption = "Each elimination step: the share λ of monitored directions under the threshold, and the "
                "leave-one-pose-out error of the set (when the count is chosen by it).";
    report::Panel a;
    a.title = "λ per step", a.x_label = "parameters in the set", a.y_label = "λ (%)", a.series = {lambda};
    f.panels.push_back(a);
    if (!heldout.x.empty()) {
      report::Panel b;
      b.title = "held-out error per step", b.x_label = "parameters in the set", b.y_label = "held-out RMS (µm)";
      b.series = {heldout};
      f.panels.push_back(b);
    }
    html.AddFigure(f);
  }
  if (s.initial_delta_x.cols() > 0 && !s.selected.empty())
    html.AddFigure(DriftFigure("selected_drift",
                               "Per-cycle drift of the selected parameters, identified with every candidate (the "
                               "curves of thesis Figs. 3-3/3-4).",
                               s.initial_delta_x, e.ball, s.selected));
  html.Section("Monitoring error with each set (form of thesis Table 5-2)");
  const std::vector<std::string> header = {"set", "parameters", "poses", "λ (%)", "RMS (mm)", "worst (mm)"};
  html.Table(header, ComparisonRows(all_poses));
  if (!budget.empty()) {
    html.Paragraph("Production budget: each set identified from its own D-optimal poses.");
    html.Table(header, ComparisonRows(budget));
  }
  return html;
}

report::HtmlReport CompensationReport(const CompensationReportInput& in) {
  const ThermalExperiment& e = *in.experiment;
  report::HtmlReport html("Thermal drift: compensation");
  html.Paragraph(in.identification.BriefReport());
  report::Series rms_before, rms_after, worst_before, worst_after, threshold;
  rms_before.label = "uncompensated", rms_after.label = "compensated";
  worst_before.label = "uncompensated", worst_after.label = "compensated";
  threshold.label = "threshold";
  for (auto* s : {&rms_before, &rms_after, &worst_before, &worst_after})
    s->style = report::SeriesStyle::kLinesPoints;
  threshold.style = report::SeriesStyle::kLines;
  int under_before = 0, under_after = 0, total = 0;
  for (int c = 0; c < in.before.cols() && c < e.monitoring.NumCycles(); ++c) {
    const double t = e.monitoring.cycles[c].time_s / 3600.0;
    const auto rms = [](const Eigen::MatrixXd& m, int col) { return std::sqrt(m.col(col).squaredNorm() / m.rows()); };
    rms_before.x.push_back(t), rms_before.y.push_back(rms(in.before, c));
    rms_after.x.push_back(t), rms_after.y.push_back(rms(in.after, c));
    worst_before.x.push_back(t), worst_before.y.push_back(in.before.col(c).cwiseAbs().maxCoeff());
    worst_after.x.push_back(t), worst_after.y.push_back(in.after.col(c).cwiseAbs().maxCoeff());
    threshold.x.push_back(t), threshold.y.push_back(in.threshold_mm);
    if (c == 0) continue;
    for (int r = 0; r < in.before.rows(); ++r) {
      ++total;
      under_before += std::abs(in.before(r, c)) < in.threshold_mm;
      under_after += std::abs(in.after(r, c)) < in.threshold_mm;
    }
  }
  html.KeyValues({{"parameters", Names(in.params)},
                  {"monitoring cycles", std::to_string(e.monitoring.NumCycles())},
                  {"monitored poses", std::to_string(e.monitoring.NumPoses())},
                  {"threshold (mm)", Fixed(in.threshold_mm, 3)},
                  {"directions under the threshold, warm cycles, before (%)",
                   Fixed(total ? 100.0 * under_before / total : 0.0, 1)},
                  {"directions under the threshold, warm cycles, after (%)",
                   Fixed(total ? 100.0 * under_after / total : 0.0, 1)}});
  if (in.monitoring_sigma_mm.size() > 0) {
    std::vector<double> v(in.monitoring_sigma_mm.data(), in.monitoring_sigma_mm.data() + in.monitoring_sigma_mm.size());
    std::sort(v.begin(), v.end());
    html.KeyValues({{"σ of a compensated direction from the identification noise, median (mm)", Fixed(v[v.size() / 2], 4)},
                    {"... largest (mm)", Fixed(v.back(), 4)}});
  }
  report::Figure f;
  f.id = "monitoring_error";
  f.caption = "Monitoring points: RMS and worst error over the monitored directions per cycle, before and after "
              "compensation, against the threshold.";
  report::Panel a, b;
  a.title = "RMS per cycle", a.x_label = "time (h)", a.y_label = "RMS error (mm)";
  a.series = {rms_before, rms_after, threshold};
  b.title = "worst direction per cycle", b.x_label = "time (h)", b.y_label = "|error| (mm)";
  b.series = {worst_before, worst_after, threshold};
  f.panels = {a, b};
  html.AddFigure(f);
  if (in.delta_x.cols() > 0) {
    Eigen::VectorXd sigma;
    std::string band;
    if (in.drift_model != nullptr) {
      const double sigma_y = ResidualSigmaY(in.identification);
      const Eigen::MatrixXd cov = in.drift_model->Covariance(in.identification_options, sigma_y);
      const std::vector<int>& order = in.identification_options.params;
      if (cov.rows() == static_cast<Eigen::Index>(order.size())) {
        sigma = Eigen::VectorXd::Zero(kinematics::kNumParams);
        for (size_t c = 0; c < order.size(); ++c) sigma(order[c]) = std::sqrt(std::max(0.0, cov(c, c)));
        band = " Shaded: ±1σ from the identification's residual (σ_Y " + Fixed(sigma_y * 1000.0, 1) +
               " µm per coordinate) through (AᵀA)⁻¹.";
      }
    }
    html.AddFigure(DriftFigure("identified_drift",
                               "Identified drift per monitoring cycle of the compensated parameters." + band,
                               in.delta_x, e.monitoring, in.params, sigma));
  }
  html.Section("Corrected joints, cycle " + std::to_string(e.monitoring.cycles[in.cycle_column].cycle) + " (deg)");
  std::vector<std::vector<std::string>> rows;
  for (size_t k = 0; k < in.corrected_deg.size(); ++k) {
    std::vector<std::string> row = {std::to_string(e.monitoring.ids[k])};
    for (int j = 0; j < 6; ++j) row.push_back(Fixed(in.corrected_deg[k][j], 5));
    for (int j = 0; j < 6; ++j) row.push_back(Fixed((in.corrected_deg[k][j] - in.taught_deg[k][j]) * 1000.0, 2));
    rows.push_back(row);
  }
  html.Table({"point", "q1", "q2", "q3", "q4", "q5", "q6", "Δq1 (mdeg)", "Δq2", "Δq3", "Δq4", "Δq5", "Δq6"}, rows);
  return html;
}

}  // namespace ramtk::thermal
