// ramtk calib sensor-robot | simulate sensor-robot (and the registration of calib cameras and
// calib hand-eye: calib_cameras_command.cpp, calib_hand_eye_command.cpp): thin wrappers over
// ramtk::calib.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/calib/sensor_robot.h"
#include "ramtk/calib/sensor_robot_io.h"
#include "ramtk/calib/sensor_robot_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::tools {

void RegisterCalibCameras(CLI::App* calib, int* exit_code);                 // calib_cameras_command.cpp
void RegisterCalibHandEye(CLI::App& app, CLI::App* calib, int* exit_code);  // calib_hand_eye_command.cpp
void RegisterCalibRobot(CLI::App* calib, int* exit_code);                   // calib_robot_command.cpp
void RegisterSimulateRobot(CLI::App* simulate, int* exit_code);             // calib_robot_command.cpp
void RegisterCalibProjector(CLI::App* calib, CLI::App* simulate, int* exit_code);  // calib_projector_command.cpp

namespace {

struct SensorRobotCommandOptions {
  std::string robot_path;         // robot model YAML
  std::string measurements_path;  // ball measurement CSV
  std::string output_path;        // result JSON
  std::string method = "manifold";
  std::string loss = "huber";
  double loss_scale_mm = 0.1;
  double penalty = 1e8;
  int min_poses = 5;
  int cycle = -1;               // only the rows of this cycle (-1: every row)
  bool unweighted = false;      // ignore the centre covariance columns
  double robot_noise_mm = 0.0;  // robot repeatability σ per axis added to every centre's covariance
};

int RunSensorRobot(const SensorRobotCommandOptions& opt, Provenance provenance) {
  CheckOutputAgainstInputs(opt.output_path, {opt.robot_path, opt.measurements_path}, "--output");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  kinematics::RobotMeasurementSet set = kinematics::ReadRobotMeasurements(opt.measurements_path);
  if (opt.cycle >= 0) {
    std::vector<kinematics::RobotMeasurement> rows;
    for (const auto& r : set.rows) {
      if (r.cycle == opt.cycle) rows.push_back(r);
    }
    if (rows.empty()) {
      throw InputError({opt.measurements_path, 0, "cycle"},
                       "no row of cycle " + std::to_string(opt.cycle) + " (--cycle)");
    }
    set.rows = rows;
  }
  const std::vector<calib::BallObservation> obs = calib::BallObservationsFromMeasurements(set, opt.measurements_path);
  calib::SensorRobotSummary summary;
  calib::SensorRobotCalibration result;
  try {
    if (opt.method == "thesis") {
      calib::ThesisCalibrationOptions o;
      o.penalty_factor = opt.penalty;
      o.checks.min_poses = opt.min_poses;
      result = calib::CalibrateSensorRobotThesis(model, obs, o, &summary);
    } else {
      calib::SensorRobotOptions o;
      o.loss = opt.loss == "none"     ? calib::RobustLoss::kNone
               : opt.loss == "cauchy" ? calib::RobustLoss::kCauchy
                                      : calib::RobustLoss::kHuber;
      o.loss_scale_mm = opt.loss_scale_mm;
      o.checks.min_poses = opt.min_poses;
      o.use_covariance = !opt.unweighted;
      o.robot_noise_mm = opt.robot_noise_mm;
      result = calib::CalibrateSensorRobot(model, obs, o, &summary);
    }
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    throw InputError({opt.measurements_path, 0, e.where().field}, e.message());
  }
  for (const std::string& f : {opt.robot_path, opt.measurements_path}) AddProvenanceFile(&provenance, f);
  WriteFileAtomically(opt.output_path, WithProvenance(calib::SensorRobotResultJson(result, summary, obs), provenance));
  const Isometry3& t = result.sensor_from_base;
  const KukaAbc abc = KukaAbcFromRotation(t.linear());
  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf("sensor_from_base  t (mm) %12.4f %12.4f %12.4f   A,B,C (deg) %10.5f %10.5f %10.5f\n", t.translation().x(),
              t.translation().y(), t.translation().z(), RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c));
  std::printf("ball_in_flange      (mm) %12.4f %12.4f %12.4f\n", result.ball_in_flange.x(), result.ball_in_flange.y(),
              result.ball_in_flange.z());
  if (result.has_covariance) {
    const Vec3 sr = result.RotationStdArcsec(), st = result.TranslationStdMm(), sb = result.BallStdMm();
    std::printf("std: rotation (arcsec) %.2f %.2f %.2f  translation (mm) %.4f %.4f %.4f  ball (mm) %.4f %.4f %.4f\n",
                sr.x(), sr.y(), sr.z(), st.x(), st.y(), st.z(), sb.x(), sb.y(), sb.z());
  }
  if (summary.held_out_rms_mm > 0) {
    std::printf("held-out (poses left out in blocks): RMS %.4f mm against %.4f mm in the fit; sigma %s%s\n",
                summary.held_out_rms_mm, summary.rms_mm, summary.covariance_source.c_str(),
                summary.jackknife_ratio > 0 ? (" (jackknife/residual " + std::to_string(summary.jackknife_ratio) + ")").c_str()
                                            : "");
  }
  for (const std::string& w : summary.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("wrote %s\n", opt.output_path.c_str());
  if (summary.termination != Termination::kSuccess) {
    // The result file is written for diagnosis, but it is not a solution: say so, exit 3.
    std::fprintf(stderr, "ramtk: error: the calibration did not converge (%s); %s holds the last iterate\n",
                 calib::SensorRobotTerminationText(summary.termination), opt.output_path.c_str());
    return kExitNoSolution;
  }
  return kExitOk;
}

struct SimulateSensorRobotOptions {
  std::string robot_path;
  std::string csv_path;
  std::string truth_path;
  calib::SensorRobotSimOptions sim;  // the library's options and defaults, bound to the flags below
};

int RunSimulateSensorRobot(const SimulateSensorRobotOptions& opt, Provenance provenance) {
  CheckOutputsDistinct({{"--output", opt.csv_path}, {"--truth", opt.truth_path}});
  CheckOutputAgainstInputs(opt.csv_path, {opt.robot_path}, "--output");
  CheckOutputAgainstInputs(opt.truth_path, {opt.robot_path}, "--truth");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(opt.robot_path);
  const calib::SensorRobotSimOptions& o = opt.sim;
  const calib::SensorRobotSimulation sim = calib::SimulateSensorRobot(model, o);
  const std::string truth = calib::SensorRobotTruthJson(sim, o);
  kinematics::WriteRobotMeasurements(calib::MeasurementsFromObservations(sim.observations), opt.csv_path);
  WriteProvenanceSidecar(opt.csv_path, provenance);
  WriteFileAtomically(opt.truth_path, WithProvenance(truth, provenance));
  std::printf("simulated %d poses (centre noise %.4f mm, repeatability %.4f mm); wrote %s and %s\n", o.num_poses,
              o.center_noise_mm, o.repeatability_mm, opt.csv_path.c_str(), opt.truth_path.c_str());
  return kExitOk;
}

}  // namespace

void RegisterCalibCommands(CLI::App& app, int* exit_code) {
  CLI::App* calib = GetOrAddSubcommand(app, "calib", "Calibrations: robot kinematics, sensor-to-robot, camera sessions, hand-eye");
  {
    auto opt = std::make_shared<SensorRobotCommandOptions>();
    CLI::App* sub = calib->add_subcommand(
        "sensor-robot", "sensor_from_base and ball_in_flange from ball centres measured at several robot poses");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--measurements", opt->measurements_path, "Ball measurement CSV (cycle,time_s,pose,q1..q6,x,y,z)")
        ->required();
    sub->add_option("--output", opt->output_path, "Result JSON")->required();
    sub->add_option("--method", opt->method, "manifold (closed form + Ceres on SO(3)) or thesis (eqs. 3-11..3-19)")
        ->check(CLI::IsMember({"manifold", "thesis"}));
    sub->add_option("--loss", opt->loss, "Robust loss of the manifold method: huber, cauchy or none")
        ->check(CLI::IsMember({"huber", "cauchy", "none"}));
    sub->add_option("--loss-scale", opt->loss_scale_mm, "Robust loss scale (mm)");
    sub->add_option("--penalty", opt->penalty, "Orthogonality penalty factor M of the thesis method (eq. 3-18)");
    sub->add_option("--min-poses", opt->min_poses, "Fewest poses accepted");
    sub->add_option("--cycle", opt->cycle, "Use only the rows of this cycle (e.g. 0, the cold cycle of a campaign)");
    sub->add_flag("--unweighted", opt->unweighted,
                  "Ignore the centre covariance columns cov_xx..cov_yz (default: the manifold method weights each "
                  "centre by its covariance when the file has them)");
    sub->add_option("--robot-noise", opt->robot_noise_mm,
                    "Robot repeatability sigma per axis (mm) added to every centre's covariance when weighting");
    sub->callback([opt, exit_code, sub]() { *exit_code = RunSensorRobot(*opt, CommandProvenance(sub)); });
  }
  RegisterCalibCameras(calib, exit_code);
  RegisterCalibRobot(calib, exit_code);
  CLI::App* simulate = SimulateCommand(app);
  {
    auto opt = std::make_shared<SimulateSensorRobotOptions>();
    CLI::App* sub = simulate->add_subcommand(
        "sensor-robot", "Ball centres measured by a fixed sensor at N robot poses (truth: thesis eqs. 5-1, 5-2)");
    sub->add_option("--robot", opt->robot_path, "Robot model file (YAML)")->required();
    sub->add_option("--output", opt->csv_path, "Ball measurement CSV to write")->required();
    sub->add_option("--truth", opt->truth_path, "Truth JSON to write")->required();
    sub->add_option("--poses", opt->sim.num_poses, "Number of poses")->capture_default_str();
    sub->add_option("--center-noise", opt->sim.center_noise_mm, "Sphere-centre noise per axis (mm, 1 sigma)")
        ->capture_default_str();
    sub->add_option("--repeatability", opt->sim.repeatability_mm, "Robot repeatability ISO 9283 RP (mm)")
        ->capture_default_str();
    sub->add_option("--max-tilt", opt->sim.max_tilt_deg, "Largest flange tilt from the nominal orientation (deg)")
        ->capture_default_str();
    sub->add_option("--seed", opt->sim.seed, "Seed of the pose geometry")->capture_default_str();
    sub->add_option("--noise-seed", opt->sim.noise_seed, "Seed of the noise")->capture_default_str();
    sub->callback([opt, exit_code, sub]() { *exit_code = RunSimulateSensorRobot(*opt, CommandProvenance(sub)); });
  }
  RegisterSimulateRobot(simulate, exit_code);
  RegisterCalibProjector(calib, simulate, exit_code);
  RegisterCalibHandEye(app, calib, exit_code);
}

}  // namespace ramtk::tools
