// The campaign layer for the Python package (python/ramtk/_campaign.py checks the arguments):
// batch scans with shards and `merge`, `measure`, the campaign digital twin, the robot calibration
// (`ramtk calib robot`) and hand-eye for a camera on a stand. Outputs follow the commands' rules:
// an existing output is replaced only with force, and only once the new one is complete.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <sstream>

#include "numpy_convert.h"
#include "progress_bridge.h"
#include "provenance_bridge.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/robot_calibration.h"
#include "ramtk/calib/robot_calibration_io.h"
#include "ramtk/campaign/campaign.h"
#include "ramtk/campaign/controller_log.h"
#include "ramtk/campaign/measure.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/tracker_io.h"
#include "ramtk/vision/scan/scan_batch.h"
#include "scan_options.h"

namespace ramtk::python {
namespace {

// The options that change a set's results, as `ramtk scan --batch` records them in each set's
// row.csv: resume keeps a set only when they are equal, so a batch resumed from Python keeps the
// sets the command finished and back. The test hooks are never set from Python.
vision::ScanResultSettings ResultSettings(const py::dict& o) {
  vision::ScanResultSettings s;
  s.calib = o["calibration"].cast<std::string>();
  s.radius = o["radius"].cast<double>();
  s.fix_radius = o["fix_radius"].cast<bool>();
  s.spheres = o["spheres"].cast<int>();
  s.min_depth = o["min_depth"].cast<double>();
  s.max_depth = o["max_depth"].cast<double>();
  s.no_nonlinearity = o["no_nonlinearity"].cast<bool>();
  s.whole_residual_sigma = o["whole_residual_sigma"].cast<bool>();
  s.phase_filter = o["phase_filter"].cast<int>();
  s.lr_sigma_factor = o["lr_sigma_factor"].cast<double>();
  s.no_noise_term = !o["noise_term"].cast<bool>();
  s.kernel_estimate = o["kernel_estimate"].cast<std::string>();
  s.roi = o["roi"].cast<std::string>();
  s.roi_margin = o["roi_margin"].cast<double>();
  s.roi_stride = o["roi_stride"].cast<int>();
  return s;
}

py::dict ScanBatch(const std::string& batch, const std::string& out, const py::dict& options, int jobs,
                   const std::string& shard_text, bool force, bool resume, const py::object& progress) {
  vision::ScanOptions o = ScanOptionsOf(options);
  const std::vector<std::string> sets = vision::ReadScanBatchList(batch);
  std::vector<std::string> inputs = {batch, o.calibration_path};
  for (const std::string& set : sets) {
    try {
      for (const std::string& f : vision::ReadFringeManifest(set).InputFiles()) inputs.push_back(f);
    } catch (const InputError&) {
      inputs.push_back(set);  // unreadable: reported on its row, never overwritten
    }
  }
  CheckOutputAgainstInputs(out, inputs, "out");
  std::vector<std::size_t> positions(sets.size());
  for (std::size_t i = 0; i < sets.size(); ++i) positions[i] = i;
  std::string results_name = "results.csv";
  if (!shard_text.empty()) {
    const vision::ScanShard shard = vision::ParseScanShard(shard_text);
    positions = vision::ShardPositions(sets.size(), shard);
    results_name = vision::ShardResultsName(shard);
  }
  std::filesystem::create_directories(out);
  const std::string results = out + "/" + results_name;
  const OutputLock lock(results, "out");
  if (!force && !resume) {
    std::error_code ec;
    const std::string how = ": pass resume=True to keep the sets it finished, or force=True to scan every set again";
    if (std::filesystem::exists(results, ec)) throw InputError({results, 0, "out"}, "exists" + how);
    for (std::size_t p : positions) {
      const std::string dir = vision::ScanBatchSetFolder(out, p, sets[p]);
      if (std::filesystem::exists(dir, ec) && !std::filesystem::is_empty(dir, ec))
        throw InputError({dir, 0, "out"}, "exists (a set folder of an earlier run)" + how);
    }
  }
  vision::ScanBatchReuse reuse;
  reuse.overwrite = force;
  reuse.resume = resume;
  reuse.settings = ResultSettings(options).ToString();
  ProgressBridge bridge(progress);
  std::vector<vision::ScanBatchRow> rows;
  vision::ScanBatchSummary totals;
  std::string csv;
  {
    py::gil_scoped_release release;
    const auto started = std::chrono::steady_clock::now();
    rows = vision::RunScanBatch(vision::ReadScanBatchEntries(batch), o, out, jobs, reuse, bridge.Callback(), positions);
    totals = vision::SummariseScanBatch(
        rows, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    csv = vision::ScanBatchCsv(rows);
    if (totals.cancelled == 0) WriteFileAtomically(results, csv);
  }
  bridge.Rethrow();
  py::dict d;
  d["results"] = totals.cancelled == 0 ? results : std::string();
  d["csv"] = csv;
  d["sets"] = totals.sets;
  d["ok"] = totals.ok;
  d["no_sphere"] = totals.no_sphere;
  d["errors"] = totals.errors;
  d["cancelled"] = totals.cancelled;
  d["report"] = totals.BriefReport();
  return d;
}

std::string Merge(const std::string& batch, const std::string& out, bool force, bool allow_errors) {
  const std::vector<std::string> sets = vision::ReadScanBatchList(batch);
  const std::vector<std::string> shards = vision::FindShardResults(out);
  const std::string target = out + "/results.csv";
  std::vector<std::string> inputs = shards;
  inputs.push_back(batch);
  CheckOutputAgainstInputs(target, inputs, "out");
  const OutputLock lock(target, "out");
  std::error_code ec;
  if (std::filesystem::exists(target, ec) && !force)
    throw InputError({target, 0, "out"}, "exists (pass force=True to replace it)");
  WriteFileAtomically(target, vision::MergeScanShards(sets, shards, allow_errors));
  return target;
}

py::dict Measure(const std::string& scans, const std::string& log, const std::string& out, double time_tolerance,
                 bool by_time) {
  campaign::MeasureOptions options;
  options.time_tolerance_s = time_tolerance;
  options.by_time = by_time;
  const std::string bad = options.Validate();
  if (!bad.empty()) throw InputError({"", 0, "time_tolerance"}, bad);
  if (!out.empty()) CheckOutputAgainstInputs(out, {scans, log}, "out");
  campaign::MeasureSummary summary;
  const kinematics::RobotMeasurementSet set = campaign::JoinCentresWithLog(
      campaign::ReadScanResults(scans), campaign::ReadControllerLog(log), options, &summary);
  if (set.rows.empty()) throw InputError({scans, 0, "status"}, "no capture has a sphere centre: nothing to write");
  if (!out.empty()) kinematics::WriteRobotMeasurements(set, out);
  py::list left_out;
  for (const campaign::LeftOut& l : summary.left_out) {
    py::dict row;
    row["set"] = l.set;
    row["cycle"] = l.cycle;
    row["pose"] = l.pose;
    row["reason"] = l.reason;
    left_out.append(row);
  }
  py::dict d;
  d["table"] = kinematics::FormatRobotMeasurements(set);
  d["match"] = summary.match;
  d["written"] = summary.written;
  d["left_out"] = left_out;
  d["warnings"] = summary.warnings;
  d["report"] = summary.BriefReport();
  return d;
}

py::dict Campaign(const kinematics::RobotModel& model, const std::string& out, const py::dict& o, bool force,
                  const py::object& progress) {
  campaign::CampaignOptions c;
  c.cycles = o["cycles"].cast<int>();
  c.ball_poses = o["poses"].cast<int>();
  c.monitoring_points = o["points"].cast<int>();
  c.cycle_period_s = o["period"].cast<double>();
  c.image_scale = o["scale"].cast<double>();
  c.supersampling = o["supersampling"].cast<int>();
  c.repeatability_mm = o["repeatability"].cast<double>();
  c.seed = o["seed"].cast<std::uint64_t>();
  c.jobs = o["jobs"].cast<int>();
  c.screen_keep = o["screen_keep"].cast<int>();
  c.html_report = o["report"].cast<bool>();
  const std::string bad = c.Validate();
  if (!bad.empty()) throw InputError({"", 0, "campaign options"}, bad);
  const Provenance provenance = PythonProvenance("simulate_campaign", o);
  ProgressBridge bridge(progress);
  c.progress = bridge.Callback();
  campaign::CampaignSummary s;
  {
    py::gil_scoped_release release;
    s = campaign::SimulateAndRunCampaign(model, c, out, force, provenance);
  }
  bridge.Rethrow();
  py::dict d;
  d["cancelled"] = s.cancelled;
  d["budget"] = s.cancelled ? py::object(py::dict()) : JsonToPython(campaign::BudgetJson(s));
  d["budget_md"] = s.cancelled ? std::string() : campaign::BudgetMarkdown(s);
  d["out_dir"] = s.out_dir;
  d["left_out"] = s.left_out;
  d["report"] = s.BriefReport();
  return d;
}

py::dict CalibrateRobot(const std::string& robot, const std::string& data_path, const std::string& format_path,
                        const std::string& out, bool force, bool remove_drift, const py::dict& o,
                        const py::object& progress) {
  const kinematics::RobotChain nominal = kinematics::ReadRobotChain(robot);
  const kinematics::TrackerFormat format =
      format_path.empty() ? kinematics::TrackerFormat{} : kinematics::ReadTrackerFormat(format_path);
  kinematics::TrackerMeasurements data = kinematics::ReadTrackerMeasurements(data_path, format);
  if (remove_drift) kinematics::RemoveTrackerDrift(&data);
  calib::RobotCalibrationOptions opt;
  opt.identify_links = !o["setup_only"].cast<bool>();
  opt.use_rotation = !o["no_rotation"].cast<bool>();
  opt.try_cyclic = !o["no_cyclic"].cast<bool>();
  opt.try_compliance = !o["no_compliance"].cast<bool>();
  const std::string split = o["split"].cast<std::string>(), loss = o["loss"].cast<std::string>(),
                    covariance = o["covariance"].cast<std::string>();
  opt.split = split == "blocks" ? calib::HoldoutSplit::kBlocks : calib::HoldoutSplit::kRandom;
  opt.loss = loss == "huber"    ? calib::RobustLoss::kHuber
             : loss == "cauchy" ? calib::RobustLoss::kCauchy
                                : calib::RobustLoss::kNone;
  opt.covariance = covariance == "sandwich"  ? calib::CovarianceKind::kSandwich
                   : covariance == "nominal" ? calib::CovarianceKind::kNominal
                                             : calib::CovarianceKind::kScaled;
  opt.folds = o["folds"].cast<int>();
  opt.seed = o["seed"].cast<unsigned>();
  std::unique_ptr<StagedFolder> staged;
  if (!out.empty()) {
    std::vector<std::string> inputs = {robot, data_path};
    if (!format_path.empty()) inputs.push_back(format_path);
    CheckOutputAgainstInputs(out, inputs, "out");
    staged = std::make_unique<StagedFolder>(out, force, "out");
  }
  ProgressBridge bridge(progress);
  opt.progress = bridge.Callback();
  calib::RobotCalibrationSummary summary;
  calib::RobotCalibration result;
  {
    py::gil_scoped_release release;
    result = calib::CalibrateRobot(nominal, data, opt, &summary);
  }
  bridge.Rethrow();
  kinematics::RobotChain out_chain = result.links_only;
  out_chain.source = "calibrated by ramtk calib robot from " + std::filesystem::path(data_path).filename().string() +
                     (nominal.source.empty() ? "" : "; nominal: " + nominal.source);
  const std::string json = calib::RobotCalibrationJson(result, summary);
  if (staged) {
    kinematics::WriteRobotChain(out_chain, (staged->path() / "robot.yaml").string());
    Provenance provenance = PythonProvenance("calibrate_robot", o);
    for (const std::string& f : {robot, data_path, format_path})
      if (!f.empty()) AddProvenanceInput(&provenance, f);
    WriteFileAtomically((staged->path() / "calibration.json").string(), WithProvenance(json, provenance));
    WriteFileAtomically((staged->path() / "residuals.csv").string(),
                        calib::RobotCalibrationResidualsCsv(data, summary));
    staged->Commit();
  }
  py::dict d;
  d["termination"] = std::string(TerminationName(summary.termination));
  d["robot_yaml"] = kinematics::RobotChainToYaml(out_chain);
  d["calibration"] = JsonToPython(json);
  d["table"] = calib::RobotCalibrationTable(result);
  d["report"] = summary.BriefReport();
  d["warnings"] = summary.warnings;
  d["rms_before_mm"] = summary.before.rms_per_coordinate_mm;
  d["rms_after_mm"] = summary.after.rms_per_coordinate_mm;
  d["rms_held_out_mm"] = summary.held_out.rms_per_coordinate_mm;
  return d;
}

Isometry3 PoseAt(const double* p) {
  Isometry3 t = Isometry3::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) t.matrix()(i, j) = p[4 * i + j];
  return t;
}

py::dict HandEye(const py::array_t<double, py::array::c_style | py::array::forcecast>& base_from_flange,
                 const py::array_t<double, py::array::c_style | py::array::forcecast>& camera_from_board,
                 const std::string& method, bool refine) {
  std::vector<calib::StandCameraObservation> obs(static_cast<std::size_t>(base_from_flange.shape(0)));
  std::vector<Isometry3> flanges;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    obs[i].base_from_flange = PoseAt(base_from_flange.data() + 16 * i);
    obs[i].camera_from_board = PoseAt(camera_from_board.data() + 16 * i);
    flanges.push_back(obs[i].base_from_flange);
  }
  calib::CheckRotationsExciteTwoAxes(flanges);
  calib::HandEyeOptions o;
  o.method = method == "li" ? calib::HandEyeMethod::kLi : calib::HandEyeMethod::kShah;
  o.refine = refine;
  ThrowIfInvalid(o.Validate(), "HandEyeOptions");
  calib::HandEyeSummary summary;
  calib::HandEyeResult r;
  {
    py::gil_scoped_release release;
    r = calib::CalibrateStandCamera(obs, o, &summary);
  }
  py::dict d;
  d["camera_from_base"] = ToArray(r.camera_from_base.matrix());
  d["flange_from_board"] = ToArray(r.flange_from_board.matrix());
  d["rotation_residual_deg"] = [&] {
    std::vector<double> v;
    for (double x : r.rotation_residual_rad) v.push_back(x * 180.0 / 3.14159265358979323846);
    return v;
  }();
  d["translation_residual_mm"] = r.translation_residual_mm;
  d["rms_rotation_deg"] = summary.rms_rotation_deg;
  d["rms_translation_mm"] = summary.rms_translation_mm;
  d["report"] = summary.BriefReport();
  return d;
}

}  // namespace

void BindCampaign(py::module_& m) {
  m.def("scan_batch", &ScanBatch);
  m.def("merge", &Merge);
  m.def("measure", &Measure);
  m.def("simulate_campaign", &Campaign);
  m.def("calibrate_robot", &CalibrateRobot);
  m.def("hand_eye", &HandEye);
}

}  // namespace ramtk::python
