#pragma once
// Thermal drift simulator (`ramtk simulate thermal`).
//
// Heat sources at the joints warm up and cool down with first-order time constants driven by a
// duty profile (heating – steady – cooling). Each joint housing temperature rise ΔT_j follows
//   dΔT_j/dt = (gain_j · duty(t) − ΔT_j) / τ_j,  τ_j = tau_heat_s while rising, tau_cool_s while falling,
// and the structure that carries the kinematic parameters follows the housing with a lag:
//   dS_j/dt = (ΔT_j − S_j) / structure_tau_s.
// A drifting parameter moves linearly with the structure temperatures:
//   ΔX_p(t) = Σ_j per_kelvin_pj · S_j(t).
// The housing temperatures are what the robot reports (temp_j1..temp_j6 columns), so a model
// fitted on them sees the structure lag as a model error.
//
// Each cycle the robot first measures the monitoring points with its tool sensor, then carries the
// ball to the fixed sensor (thesis §5.1 order). Every measurement is made at its own time with
// the drift of that instant, robot repeatability (a random flange displacement) and sensor noise.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/core/provenance.h"
#include "ramtk/kinematics/measurements_io.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::thermal {

struct HeatSource {
  int joint = 0;             // 0-based joint
  double gain_k = 10.0;      // steady housing temperature rise at duty 1, K
  double tau_heat_s = 2400;  // time constant while warming, s
  double tau_cool_s = 3600;  // time constant while cooling, s
};

struct ParamDrift {
  int param = 0;                   // ParamVector index
  std::vector<double> per_kelvin;  // per joint (6): mm/K or rad/K of structure temperature
};

struct DutyPhase {
  double duration_s = 3600.0;
  double duty = 1.0;  // 0 (standing) .. 1 (fast production motion)
};

struct ThermalSimOptions {
  ThermalSetup setup;             // sensor_from_base, ball_in_flange, flange_from_tool_sensor
  int cycles = 90;                // measurement cycles (thesis: 90)
  double cycle_period_s = 120.0;  // 90 × 120 s = 3 h
  std::vector<DutyPhase> duty;    // repeats the last phase past its end
  std::vector<HeatSource> sources;
  double structure_tau_s = 900.0;              // lag of the structure behind the housing temperature
  std::vector<ParamDrift> drifts;              // the drifting parameters (truth)
  int ball_poses = 20;                         // thesis: 20
  int monitoring_points = 34;                  // thesis: 34
  double sensor_working_distance_mm = 700.0;   // fixed sensor: ball poses around this distance
  Vec3 sensor_field_mm = Vec3(400, 300, 150);  // full extent of the ball positions in the sensor frame
  double ball_orientation_spread_deg = 60.0;   // random flange rotations about the seed orientation
  double tool_working_distance_mm = 300.0;     // tool sensor stand-off to the monitoring points
  double sensor_noise_mm = 0.02;               // σ per axis, fixed sensor (ball centre)
  double tool_sensor_noise_mm = 0.02;          // σ per axis, tool sensor
  double repeatability_mm = 0.015;             // σ per axis of the flange's random displacement
  double temperature_noise_k = 0.05;           // σ of the reported temperatures
  double ambient_c = 22.0;
  // true: every measurement sees the drift of its own instant; false: each cycle's measurements
  // all see the drift at the mean time of its ball poses (isolates the within-cycle motion).
  bool drift_changes_within_cycle = true;
  std::uint64_t seed = 1;
  std::string Validate() const;
};

// The thesis experiment (§5.1): KR150, eq. (5-1)'s sensor rotation (translation re-placed for the
// representative model, ~2 m from the base), eq. (5-2)'s ball, 90 cycles over 3 h (heating 0–110
// min at full duty, cooling at 10 % duty after), 20 ball poses, 34 monitoring points, drifting
// d4 d6 a1 a2 a3 α3 α4 β2 (the parameters the thesis's screening found).
ThermalSimOptions ThesisPreset(std::uint64_t seed);

struct ThermalSimResult {
  ThermalSetup setup;
  kinematics::RobotMeasurementSet ball;                   // cycle,time_s,pose,q..,x,y,z,temp_j1..temp_j6
  kinematics::RobotMeasurementSet monitoring;             // cycle,time_s,point,q..,x,y,z,temp_j1..temp_j6
  std::vector<kinematics::JointVector> ball_poses;        // taught joints (rad)
  std::vector<kinematics::JointVector> monitoring_poses;  // taught joints (rad)
  std::vector<Vec3> monitoring_points_in_base;            // the car body points (truth)
  std::vector<int> drifting_params;                       // truth, ascending
  std::vector<double> cycle_time_s;                       // start of each cycle
  // Truth at the start of each cycle's ball measurements: 30 × cycles, and 6 × cycles housing
  // temperatures (°C, noise-free).
  Eigen::MatrixXd true_delta_x;
  std::vector<double> truth_time_s;  // time of each true_delta_x column (mean ball time), s
  Eigen::MatrixXd true_temperatures_c;
  // Truth at each monitoring measurement: per cycle, per point the 30-vector (30 × (cycles·points)).
  Eigen::MatrixXd true_delta_x_monitoring;
};

// InputError when the options are invalid or no reachable ball poses can be placed.
ThermalSimResult SimulateThermal(const kinematics::RobotModel& model, const ThermalSimOptions& options);

// ΔX(t) of the options' drift model, noise-free, at any time (30-vector), and the housing
// temperatures (6, °C).
kinematics::ParamVector TrueDriftAt(const ThermalSimOptions& options, double time_s,
                                    Eigen::Matrix<double, 6, 1>* housing_c = nullptr);

// What the tool sensor would read for a car-body point with the robot at joints q under the
// (warm) model, noise-free — to score compensated joints against truth.
Vec3 ToolSensorReading(const kinematics::RobotModel& warm_model, const ThermalSetup& setup,
                       const kinematics::JointVector& q, const Vec3& point_in_base);

// Writes the simulation as `ramtk simulate thermal` does: ball.csv, monitoring.csv, setup.json,
// truth_params.csv and truth.json into the folder `out_dir`, as a unit (core/outputs.h
// StagedFolder; an existing non-empty folder is replaced only with `overwrite`), with
// provenance.json describing them (the files are data other commands read: they stay as they
// are; docs/formats.md#provenance).
void WriteThermalSimulation(const ThermalSimResult& result, const ThermalSimOptions& options,
                            const std::string& preset, const std::string& out_dir, bool overwrite,
                            const Provenance& provenance = {});
// The largest distance of a ball centre from its cold-cycle position (mm).
double LargestBallDriftMm(const ThermalSimResult& result);

// Truth trajectories as CSV: cycle,time_s,temp_j1..temp_j6,<param>... for every parameter
// (mm / deg), plus a comment line naming the drifting set.
std::string TruthTrajectoriesCsv(const ThermalSimResult& result);

}  // namespace ramtk::thermal
