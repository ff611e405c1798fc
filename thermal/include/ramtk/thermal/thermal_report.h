#pragma once
// HTML reports of `ramtk thermal screen --report` and `ramtk thermal compensate --report`: the
// tables of the text output and figures of the drift, the elimination and the monitoring error.

#include <string>
#include <utility>
#include <vector>

#include "ramtk/report/html_report.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/monitoring.h"
#include "ramtk/thermal/screening.h"

namespace ramtk::thermal {

// Per-cycle drift of the given parameters (rows of a 30 × cycles ΔX, SI units inside), lengths in
// mm and angles in mdeg on separate panels, against the cycles' times (h). With `sigma` (30
// standard deviations, SI, the same for every cycle) each series gets a ±1σ band.
report::Figure DriftFigure(const std::string& id, const std::string& caption, const Eigen::MatrixXd& delta_x,
                           const CycleSeries& cycles, const std::vector<int>& params,
                           const Eigen::VectorXd& sigma = Eigen::VectorXd());

// The screening page. `all_poses` and `budget` are the Table 5-2 comparisons (budget may be empty).
report::HtmlReport ScreeningReport(const ThermalExperiment& experiment, const ScreeningSummary& summary,
                                   const std::vector<ComparisonRow>& all_poses,
                                   const std::vector<ComparisonRow>& budget, double threshold_mm);

// The compensation page: RMS and worst monitoring error per cycle before and after (mm) against
// the threshold, the identification summary and the corrected joints of the chosen cycle.
struct CompensationReportInput {
  const ThermalExperiment* experiment = nullptr;
  std::vector<int> params;
  Eigen::MatrixXd before, after;  // monitoring residuals, directions × monitoring cycles (mm)
  Eigen::MatrixXd delta_x;        // 30 × monitoring cycles
  double threshold_mm = 0.1;
  int cycle_column = 0;           // the monitoring cycle whose joints were corrected
  std::vector<std::vector<double>> corrected_deg, taught_deg;  // per monitoring pose, q1..q6
  // The identification behind delta_x: the ±1σ band of the drift is σ_Y²(AᵀA)⁻¹ with σ_Y the
  // identification's residual per coordinate (degrees-of-freedom corrected). drift_model may be
  // null (no band).
  const DriftModel* drift_model = nullptr;
  IdentificationOptions identification_options;
  IdentificationSummary identification;
  // Per monitoring direction, the σ the identification's noise leaves (CompensatedMonitoringSigma).
  Eigen::VectorXd monitoring_sigma_mm;
};
report::HtmlReport CompensationReport(const CompensationReportInput& input);

}  // namespace ramtk::thermal
