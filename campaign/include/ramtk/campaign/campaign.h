#pragma once
// The digital twin of a measurement campaign (`ramtk simulate campaign`): the thermal robot
// simulator gives the joints and the true drifting parameters per cycle; for every cycle and ball
// pose the fringe simulator renders what the fixed stereo sensor sees of the 38.1 mm ball (the
// sensor frame is the left camera's; eq. 5-1 places it ~2 m from the base, eq. 5-2 the ball on
// the flange) in small camera windows around the ball; the image sets, the controller log and the
// truth are written. Then the user's chain runs from those files — scan batch → measure →
// sensor-to-robot calibration on the cold cycle → thermal identification → compensation of the
// monitoring points — and every stage is scored against truth (the error budget), beside the same
// chain fed the true centres.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "ramtk/core/progress.h"
#include "ramtk/core/provenance.h"
#include "ramtk/kinematics/robot_model.h"
#include "ramtk/report/html_report.h"
#include "ramtk/thermal/screening.h"

namespace ramtk::campaign {

struct CampaignOptions {
  int cycles = 4;                 // measurement cycles (thesis: 90)
  int ball_poses = 8;             // ball poses per cycle (thesis: 20)
  int monitoring_points = 8;      // tool-sensor monitoring points per cycle (thesis: 34)
  double cycle_period_s = 1800;   // time between cycles, s (4 × 30 min spans the warm-up)
  // Camera windows: the "small" fringe preset's 640×512 windows around the ball, scaled by this
  // (0.25: 160×128 px, ~64 px across the ball; pixels grow, so the centre σ grows too).
  double image_scale = 0.25;
  int supersampling = 2;          // n×n rays per camera pixel
  double repeatability_mm = 0.015;       // robot repeatability σ per axis (thermal simulator)
  double tool_sensor_noise_mm = 0.005;   // monitoring-point sensor σ per axis
  std::uint64_t seed = 1;         // thermal simulator (poses, drift, repeatability) and image noise
  // true: every ball pose and monitoring point sees the drift of its own instant; false: each
  // cycle's drift is held at its ball poses' mean time (ThermalSimOptions::drift_changes_within_cycle;
  // isolates what the drift's motion inside a cycle costs).
  bool drift_changes_within_cycle = true;
  // true: the robot stands (duty 0) through the first cycle, so the reference cycle is measured
  // cold; false: the warm-up starts with the first cycle (the thesis preset's duty profile), and
  // the structure has drifted ~0.1 mm at the ball by the time the first cycle's ball poses are
  // measured (15–28 min in), which the set-up calibration on that cycle takes up.
  bool cold_reference = false;
  int jobs = 2;                   // sets rendered / scanned at once
  // Parameters identified: empty = the simulator's drifting set (d4 d6 a1 a2 a3 α3 α4 β2).
  std::vector<int> params;
  // true: the drift is identified as a function of time, each centre at its own instant, piecewise
  // linear between the cycles' mean pose times (thermal::IdentifyDriftInTime); false: one ΔX per
  // cycle against the cold cycle (thermal::DriftModel::Solve), as `ramtk thermal identify`.
  bool drift_in_time = true;
  // Parameter screening (thesis §3.2, Tables 5-1/5-2) on the image-derived centres, as
  // `ramtk thermal screen`: the count kept (thesis: 8); 0 = chosen by held-out error; -1 = skip.
  int screen_keep = 8;
  // The depth range the scan searches, mm (`ramtk scan --min-depth/--max-depth`; its defaults
  // are 100 and 10000). The simulated scene lies 600–900 mm from the left camera.
  double scan_min_depth_mm = 400.0;
  double scan_max_depth_mm = 1000.0;
  bool html_report = false;       // also write report.html (CampaignReport) into the folder
  ProgressCallback progress;      // "render" and "scan" stages, per set
  std::string Validate() const;
};

// One stage's error against truth.
struct StageError {
  std::string stage;    // "centres", "calibration", "drift <param>", "monitoring"
  std::string quantity; // what the number is, with its unit
  double images = 0.0;  // chain fed the image-derived centres
  double truth = 0.0;   // chain fed the true centres (0 for the centres stage itself)
  // The image chain's own prediction of `images`, from the covariance each stage propagates
  // (centres: the scan covariance; calibration: its covariance, |std vector|; drift: the
  // weighted identification's covariance, RMS over warm cycles); NaN where none is propagated.
  double predicted = std::numeric_limits<double>::quiet_NaN();
};

struct CampaignSummary {
  std::string out_dir;
  // The progress callback asked to stop: nothing was written (out_dir is as before) and the
  // figures below are not filled in.
  bool cancelled = false;
  int sets = 0, centres = 0;         // image sets rendered; centres found
  std::vector<std::string> left_out; // sets without a centre
  std::vector<int> dropped_poses;    // poses without a centre in some cycle, left out of both chains
  double render_s = 0, scan_s = 0, chain_s = 0;
  double centre_rms_um = 0, centre_max_um = 0, centre_predicted_rms_um = 0;  // vs truth; from the scan covariance
  double rotation_error_arcsec = 0, translation_error_um = 0, ball_error_um = 0;  // set-up calibration vs truth
  // The calibration's own 1σ (|std vector|) from its covariance, image chain.
  double rotation_sigma_arcsec = 0, translation_sigma_um = 0, ball_sigma_um = 0;
  double rotation_error_truth_arcsec = 0, translation_error_truth_um = 0, ball_error_truth_um = 0;
  std::vector<int> params;
  std::vector<double> drift_rms_error, drift_rms_error_truth, drift_rms_true;  // per param, mm or deg, warm cycles
  // Per param, mm or deg: the image chain's predicted σ of the identified drift, RMS over the warm
  // cycles of the σ from the identification's covariance (thermal::IdentifyDriftInTime, or
  // DriftModel::WeightedCovariances with drift_in_time = false).
  std::vector<double> drift_predicted_sigma;
  double monitoring_uncompensated_mm = 0;  // RMS over warm cycles and directions
  double monitoring_compensated_mm = 0;    // with the image chain's drift and set-up
  double monitoring_compensated_truth_mm = 0;  // with the true-centre chain
  // The monitoring points' error caused by the identified drift's error alone, J·(ΔX − ΔX_true)
  // at each warm cycle's ball time (RMS over cycles and directions), for both chains, and the
  // image chain's prediction from its drift covariance, sqrt(mean of diag(J Σ_c Jᵀ)).
  double monitoring_drift_error_mm = 0, monitoring_drift_error_truth_mm = 0;
  double monitoring_drift_predicted_mm = std::numeric_limits<double>::quiet_NaN();
  // Per warm cycle RMS over the monitoring directions (for the picture): uncompensated,
  // compensated (images), compensated (true centres).
  std::vector<double> cycle_time_s, monitoring_before_mm, monitoring_after_mm, monitoring_after_truth_mm;
  // Screening on the image-derived centres (empty when options.screen_keep = -1): the kept set,
  // whether it equals the simulator's drifting set, the elimination (Table 5-1 form) and the
  // comparison of parameter sets (Table 5-2 form) as text.
  std::vector<int> screened;
  bool screened_is_drifting_set = false;
  std::string screening_elimination, screening_comparison;
  std::vector<thermal::ComparisonRow> screening_rows;  // before, traditional, screened, all
  std::string dominant_stage;  // the stage whose error contributes most to the monitoring residual
  std::vector<StageError> budget;
  std::string BriefReport() const;
};

// Simulates the campaign into out_dir: sets/cCCC_pPP/ fringe sets (manifests with
// capture_time_s), batch.txt, controller_log.csv, monitoring.csv, truth/ (setup.json,
// truth_params.csv, ball_truth.csv). Then runs the chain from those files into out_dir/chain/
// (scan/, ball.csv, calibration.json) and writes out_dir/budget.json and budget.md (and
// report.html). The folder is written as a unit (StagedFolder): out_dir appears only when
// complete; an existing non-empty out_dir needs `overwrite` and is replaced only then. The paths
// recorded inside (batch.txt, chain/scan/results.csv) are relative, so the folder can be moved.
// InputError on bad options or a bad out_dir.
// budget.json, budget.md and report.html carry `provenance` (docs/formats.md#provenance); each
// chain/scan/NNN_*/ folder records the `ramtk scan` command that reproduces it, run in out_dir.
CampaignSummary SimulateAndRunCampaign(const kinematics::RobotModel& model, const CampaignOptions& options,
                                       const std::string& out_dir, bool overwrite = false,
                                       const Provenance& provenance = {});

// The monitoring error per cycle (the PNG monitoring_error.png and the report's figure).
report::Figure MonitoringFigure(const CampaignSummary& summary);
// One self-contained HTML page: summary, the error budget, calibration errors against their σ,
// the monitoring figure, links to the files (`ramtk simulate campaign --report`).
report::HtmlReport CampaignReport(const CampaignSummary& summary);

// The error budget as Markdown and JSON text.
std::string BudgetMarkdown(const CampaignSummary& summary);
std::string BudgetJson(const CampaignSummary& summary);

}  // namespace ramtk::campaign
