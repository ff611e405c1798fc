// The campaign twin's chain from files, scored against truth (campaign.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "campaign_internal.h"
#include "ramtk/calib/sensor_robot.h"
#include "ramtk/calib/sensor_robot_io.h"
#include "ramtk/campaign/controller_log.h"
#include "ramtk/campaign/measure.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/thermal/drift_in_time.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/monitoring.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/vision/scan/scan_batch.h"

namespace ramtk::campaign {
namespace fs = std::filesystem;
namespace {

// What a campaign's set folder chain/scan/NNN_*/ records: the `ramtk scan` command that
// reproduces it when run in the campaign's folder (`set` and `folder` relative to it), its options
// (the others at `ramtk scan`'s defaults), and the campaign's version and run.
Provenance ScanProvenance(const Provenance& campaign, const CampaignOptions& options, const std::string& out_dir,
                          const std::string& set, const std::string& folder) {
  Provenance p = campaign;
  const std::string min_depth = nlohmann::json(options.scan_min_depth_mm).dump();
  const std::string max_depth = nlohmann::json(options.scan_max_depth_mm).dump();
  p.command = {"ramtk", "scan", set, "--min-depth", min_depth, "--max-depth", max_depth, "--out", folder};
  p.options = {{"set", set},
               {"out", folder},
               {"min-depth", options.scan_min_depth_mm},
               {"max-depth", options.scan_max_depth_mm}};
  p.inputs.clear();
  p.working_directory = out_dir;
  return p;
}

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct ChainResult {
  calib::SensorRobotCalibration calibration;
  calib::SensorRobotSummary calibration_summary;
  std::vector<calib::BallObservation> cold;  // the cold cycle's observations
  thermal::ThermalSetup setup;
  Eigen::MatrixXd delta_x;                        // 30 × ball cycles
  Eigen::MatrixXd before, after;                  // monitoring residuals, 3·points × cycles
  std::vector<Eigen::MatrixXd> drift_covariance;  // per cycle, params × params (mm / rad)
  std::vector<int> ball_column;                   // per monitoring cycle, its column in delta_x
  // Per monitoring cycle (warm ones), direction: the compensated position's error caused by the
  // identified drift's error, J·(ΔX − ΔX_true), and its predicted σ² from the drift covariance.
  double monitoring_drift_error_ss = 0, monitoring_drift_predicted_ss = 0;
  long monitoring_drift_terms = 0;
  bool screened = false;
  thermal::ScreeningSummary screening;
  std::vector<thermal::ComparisonRow> comparison;
};

// Sensor-to-robot calibration on the cold cycle, then identification and compensation.
ChainResult RunChain(const kinematics::RobotModel& model, const kinematics::RobotMeasurementSet& ball,
                     const std::string& ball_path, const thermal::CycleSeries& monitoring,
                     const thermal::ThermalSetup& truth, const std::vector<int>& params, int reference_cycle,
                     double robot_noise_mm, int screen_keep, bool drift_in_time,
                     const Eigen::MatrixXd& true_delta_x) {
  ChainResult r;
  kinematics::RobotMeasurementSet cold = ball;
  cold.rows.clear();
  for (const auto& row : ball.rows) {
    if (row.cycle == reference_cycle) cold.rows.push_back(row);
  }
  r.cold = calib::BallObservationsFromMeasurements(cold, ball_path);
  calib::SensorRobotOptions co;
  co.robot_noise_mm = robot_noise_mm;
  r.calibration = calib::CalibrateSensorRobot(model, r.cold, co, &r.calibration_summary);
  r.setup.sensor_from_base = r.calibration.sensor_from_base;
  r.setup.ball_in_flange = r.calibration.ball_in_flange;
  // The tool-mounted sensor is calibrated separately (not part of this chain).
  r.setup.flange_from_tool_sensor = truth.flange_from_tool_sensor;
  r.setup.has_tool_sensor = true;
  const thermal::CycleSeries series = thermal::GroupCycles(ball, ball_path);
  thermal::IdentificationOptions id;
  id.params = params;
  id.difference_covariance_mm2 = series.DifferenceCovariances(robot_noise_mm);
  const thermal::ThermalExperiment ex = thermal::MakeExperiment(model, r.setup, series, monitoring);
  const thermal::DriftModel dm(model, r.setup, series.taught);
  if (drift_in_time) {
    // Each centre at its own instant, the drift piecewise linear between the cycles' mean times.
    thermal::DriftInTimeOptions to;
    to.params = params;
    to.robot_noise_mm = robot_noise_mm;
    const thermal::DriftInTimeResult timed = thermal::IdentifyDriftInTime(dm, series, to);
    r.delta_x = timed.delta_x;
    if (timed.weighted) r.drift_covariance = timed.covariance;
  } else {
    r.delta_x = dm.Solve(series.DifferencesFromReference(), id);
    if (!id.difference_covariance_mm2.empty()) r.drift_covariance = dm.WeightedCovariances(id);
  }
  Eigen::MatrixXd x_mon(r.delta_x.rows(), static_cast<Eigen::Index>(ex.ball_column.size()));
  for (std::size_t c = 0; c < ex.ball_column.size(); ++c) x_mon.col(c) = r.delta_x.col(ex.ball_column[c]);
  const thermal::MonitoringModel mon(model, r.setup, monitoring);
  r.before = mon.Uncompensated();
  r.after = mon.Residuals(x_mon);
  r.ball_column = ex.ball_column;
  // The monitoring points' error from the identification alone, against the true drift of the
  // same ball cycle, and what the drift covariance predicts for it.
  for (std::size_t m = 1; m < ex.ball_column.size(); ++m) {
    const int col = ex.ball_column[m];
    Eigen::VectorXd dx(params.size());
    for (std::size_t j = 0; j < params.size(); ++j)
      dx[static_cast<Eigen::Index>(j)] =
          r.delta_x(params[j], col) - (true_delta_x(params[j], col) - true_delta_x(params[j], 0));
    for (int k = 0; k < mon.NumPoints(); ++k) {
      Eigen::MatrixXd jac(3, static_cast<Eigen::Index>(params.size()));
      for (std::size_t j = 0; j < params.size(); ++j)
        jac.col(static_cast<Eigen::Index>(j)) = mon.Jacobian(k).col(params[j]);
      const Eigen::Vector3d e = jac * dx;
      r.monitoring_drift_error_ss += e.squaredNorm();
      if (!r.drift_covariance.empty())
        r.monitoring_drift_predicted_ss +=
            (jac * r.drift_covariance.at(static_cast<std::size_t>(col)) * jac.transpose()).trace();
      r.monitoring_drift_terms += 3;
    }
  }
  if (screen_keep >= 0) {
    // As `ramtk thermal screen --keep N`, weighted by the centres' covariance.
    thermal::ScreeningOptions so;
    so.keep = screen_keep;
    so.identification.difference_covariance_mm2 = id.difference_covariance_mm2;
    r.screening = thermal::ScreenParameters(ex, so);
    r.comparison = thermal::CompareParameterSets(ex,
                                                 {{"traditional", thermal::TraditionalParams(model)},
                                                  {"screened", r.screening.selected},
                                                  {"all", model.FreeParams()}},
                                                 so.identification, so.lambda);
    r.screened = true;
  }
  return r;
}

// The simulator's drift (30 × cycles) at each cycle's mean pose time.
Eigen::MatrixXd TrueDriftAtCycleTimes(const thermal::ThermalSimOptions& options, const thermal::CycleSeries& series) {
  Eigen::MatrixXd x(kinematics::kNumParams, series.NumCycles());
  for (int c = 0; c < series.NumCycles(); ++c) x.col(c) = thermal::TrueDriftAt(options, series.cycles[c].time_s);
  return x;
}

double WarmRms(const Eigen::MatrixXd& r) {
  const Eigen::Index warm = r.cols() - 1;
  return warm > 0 ? std::sqrt(r.rightCols(warm).squaredNorm() / static_cast<double>(r.rows() * warm)) : 0.0;
}

}  // namespace

std::string CampaignSummary::BriefReport() const {
  char buf[400];
  std::snprintf(buf, sizeof(buf),
                "campaign: %d sets, %d centres (RMS error %.2f um, predicted %.2f um); set-up %.2f arcsec / %.1f um; "
                "monitoring RMS %.4f mm uncompensated -> %.4f mm compensated (true centres: %.4f mm); dominant: %s",
                sets, centres, centre_rms_um, centre_predicted_rms_um, rotation_error_arcsec, translation_error_um,
                monitoring_uncompensated_mm, monitoring_compensated_mm, monitoring_compensated_truth_mm,
                dominant_stage.c_str());
  return buf;
}

namespace {

// Centre errors against the simulator's true centres, and the RMS its covariances predict.
void CentreErrors(const thermal::ThermalSimResult& sim, const kinematics::RobotMeasurementSet& ball,
                  const std::string& ball_path, CampaignSummary* summary) {
  CampaignSummary& s = *summary;
  std::map<std::pair<int, int>, Vec3> truth_centre;
  for (const auto& row : sim.ball.rows) truth_centre[{row.cycle, row.index}] = row.position_mm;
  double sq = 0.0, pred = 0.0;
  for (const auto& row : ball.rows) {
    const double e = (row.position_mm - truth_centre.at({row.cycle, row.index})).norm() * 1000.0;
    sq += e * e;
    s.centre_max_um = std::max(s.centre_max_um, e);
    pred += kinematics::CentreCovariance(row, ball_path).trace() * 1e6;
  }
  s.centre_rms_um = std::sqrt(sq / ball.rows.size());
  s.centre_predicted_rms_um = std::sqrt(pred / ball.rows.size());
}

// Errors of the calibrated set-up (sensor frame, ball on the flange) from image and from true
// centres, against their predicted σ.
void SetupBudget(const thermal::ThermalSimResult& sim, const ChainResult& img, const ChainResult& tru,
                 CampaignSummary* summary) {
  CampaignSummary& s = *summary;
  auto setup_errors = [&](const ChainResult& r, double* rot, double* trans, double* ball_um) {
    *rot = RotationAngleBetween(r.setup.sensor_from_base.linear(), sim.setup.sensor_from_base.linear()) * kArcsecPerRad;
    *trans = (r.setup.sensor_from_base.translation() - sim.setup.sensor_from_base.translation()).norm() * 1000.0;
    *ball_um = (r.setup.ball_in_flange - sim.setup.ball_in_flange).norm() * 1000.0;
  };
  setup_errors(img, &s.rotation_error_arcsec, &s.translation_error_um, &s.ball_error_um);
  s.rotation_sigma_arcsec = img.calibration.RotationStdArcsec().norm();
  s.translation_sigma_um = img.calibration.TranslationStdMm().norm() * 1000.0;
  s.ball_sigma_um = img.calibration.BallStdMm().norm() * 1000.0;
  setup_errors(tru, &s.rotation_error_truth_arcsec, &s.translation_error_truth_um, &s.ball_error_truth_um);
  s.budget.push_back({"centres", "RMS 3-D centre error, um", s.centre_rms_um, 0.0, s.centre_predicted_rms_um});
  s.budget.push_back({"calibration", "rotation error, arcsec", s.rotation_error_arcsec, s.rotation_error_truth_arcsec,
                      s.rotation_sigma_arcsec});
  s.budget.push_back({"calibration", "translation error, um", s.translation_error_um, s.translation_error_truth_um,
                      s.translation_sigma_um});
  s.budget.push_back(
      {"calibration", "ball_in_flange error, um", s.ball_error_um, s.ball_error_truth_um, s.ball_sigma_um});
}

// Drift per parameter against the true drift relative to the cold cycle, warm cycles.
void DriftBudget(const Eigen::MatrixXd& true_delta_x, const ChainResult& img, const ChainResult& tru,
                 CampaignSummary* summary) {
  CampaignSummary& s = *summary;
  const int cycles = static_cast<int>(img.delta_x.cols());
  for (std::size_t j = 0; j < s.params.size(); ++j) {
    const int p = s.params[j];
    double ei = 0.0, et = 0.0, tt = 0.0, vp = 0.0;
    for (int c = 1; c < cycles; ++c) {
      if (!img.drift_covariance.empty())
        vp += img.drift_covariance.at(static_cast<std::size_t>(c))(static_cast<Eigen::Index>(j),
                                                                   static_cast<Eigen::Index>(j));
      const double truth = thermal::ToFileUnits(p, true_delta_x(p, c) - true_delta_x(p, 0));
      ei += std::pow(thermal::ToFileUnits(p, img.delta_x(p, c)) - truth, 2);
      et += std::pow(thermal::ToFileUnits(p, tru.delta_x(p, c)) - truth, 2);
      tt += truth * truth;
    }
    s.drift_rms_error.push_back(std::sqrt(ei / (cycles - 1)));
    s.drift_rms_error_truth.push_back(std::sqrt(et / (cycles - 1)));
    s.drift_rms_true.push_back(std::sqrt(tt / (cycles - 1)));
    s.drift_predicted_sigma.push_back(img.drift_covariance.empty()
                                          ? std::numeric_limits<double>::quiet_NaN()
                                          : std::abs(thermal::ToFileUnits(p, std::sqrt(vp / (cycles - 1)))));
    const std::string unit = kinematics::IsAngleParam(p) ? "deg" : "mm";
    s.budget.push_back({"drift " + kinematics::ParamName(p), "RMS error over warm cycles, " + unit,
                        s.drift_rms_error.back(), s.drift_rms_error_truth.back(), s.drift_predicted_sigma.back()});
  }
}

// The monitoring points' residual before and after compensation, per cycle, and the stage that
// dominates it.
void MonitoringBudget(const thermal::CycleSeries& monitoring, const ChainResult& img, const ChainResult& tru,
                      CampaignSummary* summary) {
  CampaignSummary& s = *summary;
  s.monitoring_uncompensated_mm = WarmRms(img.before);
  s.monitoring_compensated_mm = WarmRms(img.after);
  s.monitoring_compensated_truth_mm = WarmRms(tru.after);
  auto rms = [](double ss, long n) { return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : 0.0; };
  s.monitoring_drift_error_mm = rms(img.monitoring_drift_error_ss, img.monitoring_drift_terms);
  s.monitoring_drift_error_truth_mm = rms(tru.monitoring_drift_error_ss, tru.monitoring_drift_terms);
  s.monitoring_drift_predicted_mm = img.drift_covariance.empty()
                                        ? std::numeric_limits<double>::quiet_NaN()
                                        : rms(img.monitoring_drift_predicted_ss, img.monitoring_drift_terms);
  s.budget.push_back({"monitoring", "error from the identified drift J(dX - dX_true), mm", s.monitoring_drift_error_mm,
                      s.monitoring_drift_error_truth_mm, s.monitoring_drift_predicted_mm});
  s.budget.push_back({"monitoring", "RMS residual after compensation, mm", s.monitoring_compensated_mm,
                      s.monitoring_compensated_truth_mm});
  for (int c = 1; c < monitoring.NumCycles(); ++c) {
    s.cycle_time_s.push_back(monitoring.cycles[c].time_s);
    const auto col_rms = [](const Eigen::MatrixXd& m, int col) {
      return std::sqrt(m.col(col).squaredNorm() / m.rows());
    };
    s.monitoring_before_mm.push_back(col_rms(img.before, c));
    s.monitoring_after_mm.push_back(col_rms(img.after, c));
    s.monitoring_after_truth_mm.push_back(col_rms(tru.after, c));
  }
  // What the vision stage adds to the monitoring residual, against what remains with perfect centres.
  const double vision_part = std::sqrt(
      std::max(0.0, std::pow(s.monitoring_compensated_mm, 2) - std::pow(s.monitoring_compensated_truth_mm, 2)));
  s.dominant_stage = vision_part > s.monitoring_compensated_truth_mm
                         ? "vision (image-derived centres)"
                         : "robot repeatability, tool sensor and drift model (not the vision stage)";
}

}  // namespace

CampaignSummary SimulateAndRunCampaign(const kinematics::RobotModel& model, const CampaignOptions& options,
                                       const std::string& out_dir, bool overwrite, const Provenance& provenance) {
  ThrowIfInvalid(options.Validate(), "CampaignOptions");
  CampaignSummary s;
  s.out_dir = out_dir;
  // The whole campaign folder is written as a unit: an interrupted or failed run leaves no folder
  // that looks complete. Every path recorded inside it is relative, so it survives the move.
  StagedFolder staged(out_dir, overwrite, "--out");
  const fs::path dir = staged.path();
  const internal::CampaignFiles files = internal::SimulateCampaignFiles(model, options, dir.string(), &s.render_s);
  const auto& sim = files.sim;
  s.sets = static_cast<int>(sim.ball.rows.size());
  if (files.cancelled) {
    s.cancelled = true;
    return s;  // the staged folder is removed
  }

  // 1. Scan every set (as `ramtk scan --batch`), 2. join with the controller log (`ramtk measure`).
  auto t0 = std::chrono::steady_clock::now();
  // The scan is `ramtk scan` with its defaults but for the depth range (options.scan_*_depth_mm);
  // each set folder records the command (ScanProvenance) and paths relative to out_dir.
  const std::vector<vision::ScanBatchEntry> sets = vision::ReadScanBatchEntries((dir / "batch.txt").string());
  vision::ScanOptions so;
  so.match.min_depth_mm = options.scan_min_depth_mm;
  so.match.max_depth_mm = options.scan_max_depth_mm;
  ProgressCallback scan_progress;
  if (options.progress) scan_progress = [&](const Progress& p) { return options.progress({"scan", p.done, p.total}); };
  vision::ScanBatchReuse reuse;
  reuse.paths_relative_to = dir.string();
  const std::string target = fs::path(out_dir).lexically_normal().string();
  reuse.provenance = [&](const std::string& set, const std::string& folder) {
    return ScanProvenance(provenance, options, target, set, folder);
  };
  const auto rows =
      vision::RunScanBatch(sets, so, (dir / "chain" / "scan").string(), options.jobs, reuse, scan_progress);
  for (const vision::ScanBatchRow& r : rows) {
    if (r.status == "cancelled") {
      s.cancelled = true;
      return s;  // the staged folder is removed
    }
  }
  WriteFileAtomically((dir / "chain" / "scan" / "results.csv").string(),
                      vision::ScanBatchCsv(rows, (dir / "chain" / "scan").string()));
  s.scan_s = Seconds(t0);
  t0 = std::chrono::steady_clock::now();
  const std::string ball_path = (dir / "chain" / "ball.csv").string();
  MeasureSummary ms;
  const kinematics::RobotMeasurementSet measured =
      JoinCentresWithLog(ReadScanResults((dir / "chain" / "scan" / "results.csv").string()),
                         ReadControllerLog((dir / "controller_log.csv").string()), {}, &ms);
  kinematics::WriteRobotMeasurements(measured, ball_path);
  for (const LeftOut& l : ms.left_out) s.left_out.push_back(l.set + ": " + l.reason);
  kinematics::RobotMeasurementSet ball = kinematics::ReadRobotMeasurements(ball_path);
  s.centres = static_cast<int>(ball.rows.size());
  // The drift is measured pose by pose against the cold cycle, so a pose that lost its centre in
  // any cycle is dropped from both chains (and reported).
  kinematics::RobotMeasurementSet truth_ball =
      kinematics::ReadRobotMeasurements((dir / "truth" / "ball_truth.csv").string());
  const std::vector<int> dropped = PosesMissingInSomeCycle(ball, sim.ball);
  if (!dropped.empty()) {
    ball = DropPoses(ball, dropped);
    truth_ball = DropPoses(truth_ball, dropped);
    for (int p : dropped) s.dropped_poses.push_back(p);
  }

  CentreErrors(sim, ball, ball_path, &s);

  // 3.–5. The chain on the image centres and on the true centres.
  const std::string mon_path = (dir / "monitoring.csv").string();
  const thermal::CycleSeries monitoring = thermal::GroupCycles(kinematics::ReadRobotMeasurements(mon_path), mon_path);
  s.params = options.params.empty() ? sim.drifting_params : options.params;
  // The true drift at the instant each cycle's identified ΔX refers to: the mean time of its poses.
  const Eigen::MatrixXd true_delta_x = TrueDriftAtCycleTimes(files.options, thermal::GroupCycles(ball, ball_path));
  const ChainResult img = RunChain(model, ball, ball_path, monitoring, sim.setup, s.params, 0, options.repeatability_mm,
                                   options.screen_keep, options.drift_in_time, true_delta_x);
  const std::string truth_path = (dir / "truth" / "ball_truth.csv").string();
  const ChainResult tru = RunChain(model, truth_ball, truth_path, monitoring, sim.setup, s.params, 0,
                                   options.repeatability_mm, -1, options.drift_in_time, true_delta_x);
  if (img.screened) {
    s.screened = img.screening.selected;
    std::vector<int> a = s.screened, b = sim.drifting_params;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    s.screened_is_drifting_set = a == b;
    s.screening_elimination = thermal::FormatEliminationTable(img.screening);
    s.screening_comparison = thermal::FormatComparisonTable(img.comparison);
    s.screening_rows = img.comparison;
    WriteFileAtomically((dir / "chain" / "screening.txt").string(),
                        "Elimination from the image-derived centres (form of thesis Table 5-1):\n" +
                            s.screening_elimination + img.screening.BriefReport() +
                            "\n\nParameter sets compared (form of thesis Table 5-2):\n" + s.screening_comparison);
  }
  WriteFileAtomically((dir / "chain" / "calibration.json").string(),
                      WithProvenance(calib::SensorRobotResultJson(img.calibration, img.calibration_summary, img.cold),
                                     provenance));
  // The calibrated set-up in the thermal commands' format (the tool sensor's mounting from truth).
  thermal::WriteThermalSetup(img.setup, (dir / "chain" / "setup.json").string());
  s.chain_s = Seconds(t0);

  SetupBudget(sim, img, tru, &s);

  DriftBudget(true_delta_x, img, tru, &s);
  MonitoringBudget(monitoring, img, tru, &s);

  WriteFileAtomically((dir / "budget.json").string(), WithProvenance(BudgetJson(s), provenance));
  WriteFileAtomically((dir / "budget.md").string(), BudgetMarkdown(s) + "\n" + ProvenanceMarkdown(provenance));
  if (s.cycle_time_s.size() >= 1) {
    std::vector<diagnose::Picture> pictures;
    diagnose::AddFigure(MonitoringFigure(s), dir.string(), &pictures);
  }
  if (options.html_report) {
    report::HtmlReport page = CampaignReport(s);
    page.AddProvenance(provenance);
    page.Write((dir / "report.html").string());
  }
  staged.Commit();
  return s;
}

std::string BudgetJson(const CampaignSummary& s) {
  nlohmann::json j;
  j["sets"] = s.sets;
  j["centres"] = s.centres;
  j["left_out"] = s.left_out;
  j["dropped_poses"] = s.dropped_poses;
  j["seconds"] = {{"render", s.render_s}, {"scan", s.scan_s}, {"chain", s.chain_s}};
  j["centre_rms_error_um"] = s.centre_rms_um;
  j["centre_max_error_um"] = s.centre_max_um;
  j["centre_predicted_rms_um"] = s.centre_predicted_rms_um;
  j["calibration_sigma"] = {{"rotation_arcsec", s.rotation_sigma_arcsec},
                            {"translation_um", s.translation_sigma_um},
                            {"ball_um", s.ball_sigma_um}};
  j["dominant_stage"] = s.dominant_stage;
  if (!s.screened.empty()) {
    j["screening"] = {{"selected", thermal::ParamListToString(s.screened)},
                      {"is_simulated_drifting_set", s.screened_is_drifting_set}};
  }
  nlohmann::json b = nlohmann::json::array();
  for (const StageError& e : s.budget) {
    b.push_back({{"stage", e.stage}, {"quantity", e.quantity}, {"images", e.images}, {"true_centres", e.truth}});
    if (std::isfinite(e.predicted)) b.back()["predicted"] = e.predicted;
  }
  j["budget"] = b;
  j["monitoring"] = {{"uncompensated_rms_mm", s.monitoring_uncompensated_mm},
                     {"compensated_rms_mm", s.monitoring_compensated_mm},
                     {"compensated_true_centres_rms_mm", s.monitoring_compensated_truth_mm},
                     {"cycle_time_s", s.cycle_time_s},
                     {"per_cycle_uncompensated_mm", s.monitoring_before_mm},
                     {"per_cycle_compensated_mm", s.monitoring_after_mm},
                     {"per_cycle_compensated_true_centres_mm", s.monitoring_after_truth_mm}};
  j["brief"] = s.BriefReport();
  return j.dump(2) + "\n";
}

report::Figure MonitoringFigure(const CampaignSummary& s) {
  std::vector<report::Series> series(3);
  for (auto& ps : series) ps.style = report::SeriesStyle::kLinesPoints;
  for (std::size_t i = 0; i < s.cycle_time_s.size(); ++i) {
    const double t = s.cycle_time_s[i] / 60.0;
    series[0].x.push_back(t);
    series[0].y.push_back(s.monitoring_before_mm[i]);
    series[1].x.push_back(t);
    series[1].y.push_back(s.monitoring_after_mm[i]);
    series[2].x.push_back(t);
    series[2].y.push_back(s.monitoring_after_truth_mm[i]);
  }
  series[0].label = "uncompensated";
  series[1].label = "compensated (centres from images)";
  series[2].label = "compensated (true centres)";
  return diagnose::OnePanel("monitoring_error",
                            "RMS error of the monitoring points per warm cycle: uncompensated, compensated with the "
                            "chain fed by image-derived centres, and with the chain fed by the true centres.",
                            "Monitoring points: RMS error per cycle", "time (min)",
                            "RMS over monitored directions (mm)", series);
}

report::HtmlReport CampaignReport(const CampaignSummary& s) {
  char buf[64];
  auto f = [&buf](double v, const char* fmt = "%.4g") {
    std::snprintf(buf, sizeof(buf), fmt, v);
    return std::string(buf);
  };
  report::HtmlReport html("Campaign: images to compensated joints");
  html.Paragraph(s.BriefReport());
  html.KeyValues({{"image sets", std::to_string(s.sets)},
                  {"centres found", std::to_string(s.centres)},
                  {"sets left out", std::to_string(s.left_out.size())},
                  {"dominant stage", s.dominant_stage},
                  {"render / scan / chain (s)",
                   f(s.render_s, "%.1f") + " / " + f(s.scan_s, "%.1f") + " / " + f(s.chain_s, "%.1f")}});
  html.Section("Error budget, stage by stage");
  std::vector<std::vector<std::string>> rows;
  for (const StageError& e : s.budget)
    rows.push_back({e.stage, e.quantity, f(e.images), std::isfinite(e.predicted) ? f(e.predicted) : "—",
                    e.stage == "centres" ? "—" : f(e.truth)});
  html.Table({"stage", "quantity", "centres from images", "predicted (propagated σ)", "true centres"}, rows);
  html.Section("Centres and set-up calibration against the truth");
  html.Table({"quantity", "error", "predicted σ"},
             {{"centre RMS (µm)", f(s.centre_rms_um), f(s.centre_predicted_rms_um)},
              {"sensor_from_base rotation (arcsec)", f(s.rotation_error_arcsec), f(s.rotation_sigma_arcsec)},
              {"sensor_from_base translation (µm)", f(s.translation_error_um), f(s.translation_sigma_um)},
              {"ball_in_flange (µm)", f(s.ball_error_um), f(s.ball_sigma_um)}});
  if (!s.cycle_time_s.empty()) {
    html.Section("Monitoring points");
    html.AddFigure(MonitoringFigure(s));
  }
  if (!s.left_out.empty()) {
    std::vector<std::vector<std::string>> lo;
    for (const std::string& l : s.left_out) lo.push_back({l});
    html.Section("Sets left out (no centre)");
    html.Table({"set"}, lo);
  }
  html.Section("Files");
  html.Links({{"error budget (Markdown)", "budget.md"},
              {"error budget (JSON)", "budget.json"},
              {"monitoring picture (PNG)", "monitoring_error.png"},
              {"controller log", "controller_log.csv"},
              {"scan batch results", "chain/scan/results.csv"},
              {"ball centres joined with the log", "chain/ball.csv"}});
  return html;
}

std::string BudgetMarkdown(const CampaignSummary& s) {
  std::string md =
      "| stage | quantity | centres from images | predicted (propagated σ) | true centres |\n|---|---|---|---|---|\n";
  char buf[300];
  for (const StageError& e : s.budget) {
    char truth[32] = "—", predicted[32] = "—";
    if (e.stage != "centres") std::snprintf(truth, sizeof(truth), "%.4g", e.truth);
    if (std::isfinite(e.predicted)) std::snprintf(predicted, sizeof(predicted), "%.4g", e.predicted);
    std::snprintf(buf, sizeof(buf), "| %s | %s | %.4g | %s | %s |\n", e.stage.c_str(), e.quantity.c_str(), e.images,
                  predicted, truth);
    md += buf;
  }
  std::snprintf(buf, sizeof(buf),
                "\nMonitoring RMS over the warm cycles: %.4f mm uncompensated. Centres predicted by the scan "
                "covariance: %.2f um RMS (observed %.2f um). Dominant: %s.\n",
                s.monitoring_uncompensated_mm, s.centre_predicted_rms_um, s.centre_rms_um, s.dominant_stage.c_str());
  md += buf;
  if (!s.screened.empty()) {
    md += "\nScreening from the image-derived centres kept " + thermal::ParamListToString(s.screened) +
          (s.screened_is_drifting_set ? " (the simulator's drifting set)" : " (not the simulator's drifting set)") +
          "; chain/screening.txt has the elimination (Table 5-1 form) and the comparison (Table 5-2 form).\n";
  }
  if (!s.dropped_poses.empty()) {
    md += "\nPoses dropped from both chains (no centre in some cycle):";
    for (int p : s.dropped_poses) md += " " + std::to_string(p);
    md += "\n";
  }
  return md;
}

}  // namespace ramtk::campaign
