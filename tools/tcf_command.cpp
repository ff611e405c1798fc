// ramtk tcf …: cross-laser TCF device (sensor-frame calibration, TCF solve, method comparison,
// repeat scatter) and ramtk simulate tcf. Algorithms live in ramtk::tcf; this file parses options,
// calls the library and writes the results.
#include <filesystem>
#include <iostream>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/evaluation.h"
#include "ramtk/tcf/sensor_frame.h"
#include "ramtk/tcf/simulator.h"
#include "ramtk/tcf/statistics.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::tools {
namespace {

using namespace ramtk::tcf;

// --- calibrate-sensor -------------------------------------------------------------------------
struct CalibrateSensorOptions {
  std::string points;  // Table 5-3 CSV label,x,y,z
  std::string out;     // sensor frame JSON
  double max_gap_mm = 5.0;
};

int RunCalibrateSensor(const CalibrateSensorOptions& o, Provenance provenance) {
  CheckOutputAgainstInputs(o.out, {o.points}, "--out");
  SensorFrameOptions so;
  so.max_beam_gap_mm = o.max_gap_mm;
  const SensorFrame f = CalibrateSensorFrame(
      BeamPointsFromFlangePositions(ReadSensorCalibrationPoints(o.points), o.points), so, o.points);
  const std::string json = SensorFrameToJson(f);
  AddProvenanceFile(&provenance, o.points);
  if (!o.out.empty()) WriteFileAtomically(o.out, WithProvenance(json, provenance));
  auto v = [](const Vec3& p) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "(%.4f, %.4f, %.4f)", p.x(), p.y(), p.z());
    return std::string(buf);
  };
  std::cout << "sensor frame: " << f.BriefReport() << "\n"
            << "  A " << v(f.a_in_base) << "  B " << v(f.b_in_base) << "\n"
            << "  C " << v(f.c_in_base) << "  D " << v(f.d_in_base) << "\n"
            << "  M " << v(f.m_in_base) << "\n"
            << "  n (X_s) " << v(f.n) << "  m (y beam) " << v(f.m) << "\n"
            << "  o (Y'_s) " << v(f.o) << "  p (Z_s) " << v(f.p) << "\n";
  char buf[128];
  std::snprintf(buf, sizeof(buf), "  beta = arccos(n.m) = arccos(%.4f) = %.3f deg\n", f.n.dot(f.m),
                RadToDeg(f.beta_rad));
  std::cout << buf;
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  return kExitOk;
}

// --- solve ------------------------------------------------------------------------------------
struct SolveOptions {
  std::string log, motion, sensor, out;
  std::string variant = "ramtk";  // ramtk | no-self-calibration | thesis | thesis-uncorrected
  bool self_calibrate_beta = false;
  double timing_sigma_ms = 0.1;
  double repeatability_mm = 0.03;
  double max_tilt_deg = 30.0;
};

int RunSolve(const SolveOptions& o, Provenance provenance) {
  TcfMethod m = TcfMethod::kCrossLaser;
  if (o.variant == "no-self-calibration") {
    m = TcfMethod::kCrossLaserNoSelfCalibration;
  } else if (o.variant == "thesis") {
    m = TcfMethod::kThesisCorrected;
  } else if (o.variant == "thesis-uncorrected") {
    m = TcfMethod::kThesisUncorrected;
  } else if (o.variant != "ramtk") {
    throw InputError({"", 0, "--variant"}, "expected ramtk, no-self-calibration, thesis or thesis-uncorrected");
  }
  CheckOutputAgainstInputs(o.out, {o.log, o.motion, o.sensor}, "--out");
  TcfSolverOptions so = SolverOptionsFor(m);
  so.self_calibrate_beta = o.self_calibrate_beta;
  so.timing_sigma_s = o.timing_sigma_ms * 1e-3;
  so.repeatability_sigma_mm = o.repeatability_mm;
  so.max_axis_tilt_deg = o.max_tilt_deg;
  if (const std::string err = so.Validate(); !err.empty()) throw InputError({"", 0, "options"}, err);
  const std::vector<BeamEvent> events = ReadDeviceLog(o.log);
  const ProgrammedMotion motion = ReadProgrammedMotion(o.motion);
  const SensorFrame sensor = ReadSensorFrame(o.sensor);
  const TcfSummary s = SolveTcf(events, motion, sensor, so, o.log);
  for (const std::string& f : {o.log, o.motion, o.sensor}) AddProvenanceFile(&provenance, f);
  if (!o.out.empty()) WriteFileAtomically(o.out, WithProvenance(TcfSummaryToJson(s), provenance));
  std::cout << "variant " << o.variant << ": " << s.BriefReport() << "\n";
  const Eigen::Matrix4d t = s.solution.flange_from_tcp.matrix();
  std::cout << "flange_from_tcp (5 DOF):\n";
  char buf[160];
  for (int r = 0; r < 4; ++r) {
    std::snprintf(buf, sizeof(buf), "  %10.6f %10.6f %10.6f %12.4f\n", t(r, 0), t(r, 1), t(r, 2), t(r, 3));
    std::cout << buf;
  }
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  return kExitOk;
}

// --- compare ----------------------------------------------------------------------------------
struct CompareOptions {
  int runs = 20;
  unsigned long long seed = 1;
  double repeatability_mm = 0.03;
  double jitter_ms = 0.02;
  std::string effects;
};

int RunCompare(const CompareOptions& o) {
  EvaluationOptions e;
  e.runs = o.runs;
  e.first_seed = o.seed;
  e.simulation.repeatability_mm = o.repeatability_mm;
  e.simulation.timing_jitter_s = o.jitter_ms * 1e-3;
  e.simulation.effects.EnableList(o.effects);
  if (const std::string err = e.Validate(); !err.empty()) throw InputError({"", 0, "options"}, err);
  std::printf("repeatability %.3f mm (1-sigma per axis), jitter %.3f ms, %d runs, effects: %s\n", o.repeatability_mm,
              o.jitter_ms, o.runs, o.effects.empty() ? "none" : o.effects.c_str());
  std::cout << FormatAccuracyTable(EvaluateMethods(e));
  return kExitOk;
}

// --- scatter ----------------------------------------------------------------------------------
struct ScatterOptions {
  std::string points;
};

int RunScatter(const ScatterOptions& o) {
  const CsvTable t = ReadCsv(o.points);
  const int cx = t.Column("x"), cy = t.Column("y"), cz = t.Column("z");
  std::vector<Vec3> pts;
  for (std::size_t r = 0; r < t.size(); ++r) pts.emplace_back(t.Number(r, cx), t.Number(r, cy), t.Number(r, cz));
  if (pts.size() < 2) throw InputError({o.points, 0, ""}, "need at least two points");
  const PointScatter s = ComputePointScatter(pts);
  std::printf("%d points, mean (%.4f, %.4f, %.4f) mm\n", s.count, s.mean.x(), s.mean.y(), s.mean.z());
  std::printf("sample std (n-1) %.4f mm, RMS from mean (n) %.4f mm, max from mean %.4f mm\n", s.sample_std_mm,
              s.rms_from_mean_mm, s.max_from_mean_mm);
  return kExitOk;
}

// --- simulate tcf -----------------------------------------------------------------------------
struct SimulateOptions {
  std::string out_dir;
  unsigned long long seed = 1;
  double repeatability_mm = 0.03;
  double jitter_ms = 0.02;
  std::string effects;
};

int RunSimulate(const SimulateOptions& o, Provenance provenance) {
  TcfSimulationOptions so;
  so.seed = o.seed;
  so.repeatability_mm = o.repeatability_mm;
  so.timing_jitter_s = o.jitter_ms * 1e-3;
  so.effects.EnableList(o.effects);
  if (const std::string err = so.Validate(); !err.empty()) throw InputError({"", 0, "options"}, err);
  const TcfSimulation sim = SimulateTcf(so);
  // Everything is formatted before anything is written.
  const std::string log = FormatDeviceLog(sim.events), motion = ProgrammedMotionToJson(sim.motion),
                    sensor = SensorFrameToJson(sim.calibrated_sensor), truth = TcfTruthToJson(sim.truth, so.effects);
  const std::string d = o.out_dir + "/";
  std::error_code ec;
  if (!std::filesystem::is_directory(o.out_dir, ec)) throw InputError({o.out_dir, 0, "--out-dir"}, "is not a folder");
  // The four files as one unit: none of them is replaced unless all were written.
  std::vector<std::pair<std::string, std::string>> files = {
      {d + "laser_log.csv", log}, {d + "motion.json", motion}, {d + "sensor.json", sensor}, {d + "truth.json", truth}};
  // The four files are data other commands read; their provenance is one sidecar beside them.
  files.push_back(FolderProvenance(o.out_dir, {"laser_log.csv", "motion.json", "sensor.json", "truth.json"}, provenance));
  WriteFilesAtomically(files);
  std::cout << "wrote " << sim.events.size() << " events to " << d
            << "laser_log.csv, and motion.json, sensor.json, truth.json\n";
  return kExitOk;
}

}  // namespace

void RegisterTcfCommand(CLI::App& app, int* exit_code) {
  CLI::App* tcf = app.add_subcommand("tcf", "Cross-laser TCF device: calibrate, solve, compare methods");
  tcf->require_subcommand(1);

  auto cal = std::make_shared<CalibrateSensorOptions>();
  CLI::App* c =
      tcf->add_subcommand("calibrate-sensor", "Device frame from beam crossing points (thesis eqs. 4-15..4-27)");
  c->add_option("--points", cal->points, "CSV label,x,y,z with A1..D4 (thesis Table 5-3 format)")->required();
  c->add_option("--out", cal->out, "Write the sensor frame JSON here");
  c->add_option("--max-gap", cal->max_gap_mm, "Largest accepted distance between the beam lines (mm)");
  c->callback([cal, exit_code, c]() { *exit_code = RunCalibrateSensor(*cal, CommandProvenance(c)); });

  auto sol = std::make_shared<SolveOptions>();
  CLI::App* s = tcf->add_subcommand("solve", "Tool frame from the laser device log and the programmed motion");
  s->add_option("--log", sol->log, "Laser device log CSV time_s,beam,state")->required();
  s->add_option("--motion", sol->motion, "Programmed motion JSON")->required();
  s->add_option("--sensor", sol->sensor, "Sensor frame JSON (ramtk tcf calibrate-sensor)")->required();
  s->add_option("--out", sol->out, "Write the result JSON here");
  s->add_option("--variant", sol->variant, "ramtk | no-self-calibration | thesis | thesis-uncorrected");
  s->add_flag("--self-calibrate-beta", sol->self_calibrate_beta,
              "Take beta from the circle phases (without it the sensor file's beta is used, with a warning when the "
              "phases disagree by > 5 sigma and 0.1 deg)");
  s->add_option("--timing-sigma-ms", sol->timing_sigma_ms, "1-sigma event timing noise for the uncertainty (ms)");
  s->add_option("--repeatability", sol->repeatability_mm, "Robot repeatability, 1-sigma per axis (mm)");
  s->add_option("--max-tilt", sol->max_tilt_deg, "Device range: largest tool-axis tilt (deg)");
  s->callback([sol, exit_code, s]() { *exit_code = RunSolve(*sol, CommandProvenance(s)); });

  auto cmp = std::make_shared<CompareOptions>();
  CLI::App* k =
      tcf->add_subcommand("compare", "Accuracy of the cross-laser variants and the baselines on simulated data");
  k->add_option("--runs", cmp->runs, "Simulated runs (seeds seed..seed+runs-1)");
  k->add_option("--seed", cmp->seed, "First seed");
  k->add_option("--repeatability", cmp->repeatability_mm, "Robot repeatability, 1-sigma per axis (mm)");
  k->add_option("--jitter-ms", cmp->jitter_ms, "Receiver timing jitter, 1-sigma (ms)");
  k->add_option("--effects", cmp->effects, "Comma-separated laser-device effects to switch on (or 'all')");
  k->callback([cmp, exit_code]() { *exit_code = RunCompare(*cmp); });

  auto sc = std::make_shared<ScatterOptions>();
  CLI::App* r = tcf->add_subcommand("scatter", "Scatter of repeated TCP measurements (thesis Table 5-6)");
  r->add_option("--points", sc->points, "CSV with columns x,y,z")->required();
  r->callback([sc, exit_code]() { *exit_code = RunScatter(*sc); });

  CLI::App* simulate = SimulateCommand(app);
  auto so = std::make_shared<SimulateOptions>();
  CLI::App* st = simulate->add_subcommand("tcf", "Cross-laser device: laser log, motion, sensor frame and truth");
  st->add_option("--out-dir", so->out_dir, "Existing folder for laser_log.csv, motion.json, sensor.json, truth.json")
      ->required();
  st->add_option("--seed", so->seed, "Random seed");
  st->add_option("--repeatability", so->repeatability_mm, "Robot repeatability, 1-sigma per axis (mm)");
  st->add_option("--jitter-ms", so->jitter_ms, "Receiver timing jitter, 1-sigma (ms)");
  st->add_option("--effects", so->effects, "Comma-separated laser-device effects to switch on (or 'all')");
  st->callback([so, exit_code, st]() { *exit_code = RunSimulate(*so, CommandProvenance(st)); });
}

}  // namespace ramtk::tools
