#pragma once
// Simulator of the cross-laser TCF device (`ramtk simulate tcf`).
//
// Truth: two beams in the device frame (x beam along X_s at height z_x, y beam at angle β at
// height z_y, each with a width), a ball-nosed cylindrical tool (radius r, apex = TCP, axis = the
// TCF's Z) mounted with flange_from_tcp. A beam is blocked while its centre line comes closer than
// r + width/2 to the tool (the ball and the cylinder above it).
// Robot: executes the programme with a per-segment position error (repeatability) and a speed
// profile. Receiver: reports each state change late by a latency plus Gaussian jitter.
// Programme (as the thesis's device would run it): circles about the device normal at two
// heights (ccw, ccw, then cw at the first height), the tool axis estimated from them with the
// library (EstimateToolAxisFromCircles, no truth used), then down/up moves of the estimated tip
// through the beam crossing (fast down, faster retract).
// The solver gets the device frame as calibrated: equal to the true one except for the hidden
// effects (sensor_plane_tilt tilts the true beam plane, beam_offset moves the beams along Z_s).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"

namespace ramtk::tcf {

// Laser-device effects of DESIGN.md's catalogue, each switchable, with its magnitude.
struct DeviceEffects {
  bool beam_non_perpendicular = false;  // β != 90°
  double beta_deg = 92.15;              // the thesis device's value (Table 5-3)
  bool beam_offset = false;             // beams at different heights along Z_s (hidden from the calibration)
  double beam_offset_mm = 0.4;          // z_x − z_y
  bool beam_width = false;              // beams of finite width (else lines)
  double beam_width_mm = 1.0;
  bool trigger_latency = false;  // receiver reports late
  double latency_s = 0.008;
  bool speed_variation = false;     // robot speed: scale error + ripple
  double speed_scale_error = 0.02;  // fraction
  double speed_ripple = 0.01;       // fraction of the speed
  double speed_ripple_hz = 1.7;
  bool sensor_plane_tilt = false;  // true beam plane tilted against the calibrated one
  double plane_tilt_deg = 0.3;
  bool tool_axis_rotation = false;  // tool rotated about its own axis (unobservable, 6th DOF)
  double tool_axis_rotation_deg = 25.0;

  // Switches on an effect by its catalogue name; false if the name is unknown.
  bool Enable(const std::string& name);
  // Switches on every effect of a comma-separated list of names ("all" = every one). InputError
  // naming `option` and the known names for an unknown one.
  void EnableList(const std::string& list, const std::string& option = "--effects");
  // All catalogue names of laser-device effects.
  static std::vector<std::string> Names();
};

struct TcfSimulationOptions {
  DeviceEffects effects;
  std::uint64_t seed = 1;
  double repeatability_mm = 0.03;  // robot: 1-sigma per axis of each segment's position error
  double timing_jitter_s = 2e-5;   // receiver: 1-sigma jitter of each event
  // True device frame and tool.
  Isometry3 base_from_lasersensor = DefaultBaseFromLaserSensor();
  double tool_radius_mm = 2.5;
  Vec3 tcp_in_flange = Vec3(3.0, -2.0, 150.5);  // a bumped tool: 3.6 mm off the flange axis
  double tool_psi_deg = 30.0;                   // direction of the tool's tilt (eq. 4-10)
  double tool_theta_deg = 3.0;                  // tilt of the tool axis from Z_e
  // Programme.
  double nominal_tool_length_mm = 150.0;  // the programme's prior for the tip (along Z_e)
  double circle_radius_mm = 12.0;
  double angular_speed_deg_s = 180.0;
  double revolutions = 1.25;     // per circle (> 1 so the period is measured)
  double upper_height_mm = 6.0;  // circle heights above the nominal tip
  double lower_height_mm = 26.0;
  double start_angle_deg = 45.0;
  double approach_speed_mm_s = 20.0;  // straight move down through the beams
  double retract_speed_mm_s = 40.0;   // and back up
  double approach_start_mm = 6.0;     // the estimated apex starts this far above the crossing
  double approach_travel_mm = 10.0;
  int approach_passes = 2;

  static Isometry3 DefaultBaseFromLaserSensor();
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

struct TcfTruth {
  Isometry3 flange_from_tcp = Isometry3::Identity();
  Vec3 tcp_in_flange = Vec3::Zero();
  Vec3 axis_in_flange = Vec3::UnitZ();
  Isometry3 base_from_lasersensor = Isometry3::Identity();  // true beam frame
  double beta_rad = 0.5 * 3.14159265358979323846;
  double x_beam_z_mm = 0.0, y_beam_z_mm = 0.0;
  double beam_width_mm = 0.0;
  double latency_s = 0.0;
};

struct TcfSimulation {
  std::vector<BeamEvent> events;  // the device log
  ProgrammedMotion motion;        // the programme
  SensorFrame calibrated_sensor;  // what the solver is given
  TcfTruth truth;
};

TcfSimulation SimulateTcf(const TcfSimulationOptions& options);

// Simulated sensor-frame calibration (thesis §4.3.1, Table 5-3 procedure) on the true beams: a
// calibration pin of radius pin_radius_mm on the flange axis is passed through each beam at two
// points (±half_span_mm from the beam's foot of the common perpendicular): horizontally (vertical
// pin; A1, A2 / C1, C2) and vertically (horizontal pin; A3, A4 / C3, C4). Each recorded flange
// position carries a Gaussian error of repeatability_mm per axis. Returns the 16 labelled
// positions of the Table 5-3 format.
struct SensorCalibrationSimulationOptions {
  std::uint64_t seed = 1;
  double repeatability_mm = 0.03;
  double pin_radius_mm = 2.5;
  double half_span_mm = 6.0;
};
std::map<std::string, Vec3> SimulateSensorCalibrationPoints(const TcfTruth& truth,
                                                            const SensorCalibrationSimulationOptions& options);

std::string TcfTruthToJson(const TcfTruth& truth, const DeviceEffects& effects);

}  // namespace ramtk::tcf
