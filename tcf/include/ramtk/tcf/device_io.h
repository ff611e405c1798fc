#pragma once
// Inputs of the cross-laser TCF solver (formats in docs/formats.md):
//  * the laser device log, CSV `time_s,beam,state` (beam x|y, state blocked|clear), and
//  * the programmed robot motion, JSON: the tool's nominal radius, the circles (flange centre pose,
//    plane axes, radius, angular speed, direction, start angle, start time, duration) and the
//    straight moves (start pose, velocity, start time, duration), all in the robot base frame.
// Times of the log and of the motion share one clock (seconds).

#include <string>
#include <vector>

#include "ramtk/core/rotation.h"

namespace ramtk::tcf {

enum class Beam { kX = 0, kY = 1 };
enum class BeamState { kBlocked, kClear };

const char* BeamName(Beam beam);
const char* BeamStateName(BeamState state);

// One state change of a beam's receiver.
struct BeamEvent {
  double time_s = 0.0;
  Beam beam = Beam::kX;
  BeamState state = BeamState::kBlocked;
  int line = 0;  // 1-based line in the log file (0 if not read from a file)
};

// A programmed circle: the flange translates (constant orientation) along
//   base_from_flange(t).translation = centre + R (cos φ u + sin φ v),
//   φ(t) = start_angle + direction · ω · (t − start_time),   0 ≤ t − start_time ≤ duration.
struct CircleSegment {
  std::string name;
  double start_time_s = 0.0;
  double duration_s = 0.0;
  Isometry3 base_from_flange_centre = Isometry3::Identity();  // flange pose at the circle centre
  Vec3 u_in_base = Vec3::UnitX();                             // unit, φ = 0 direction (the device's X_s)
  Vec3 v_in_base = Vec3::UnitY();                             // unit, φ = 90° direction (the device's Y'_s)
  double radius_mm = 10.0;
  double angular_speed_rad_s = 1.0;  // > 0
  int direction = 1;                 // +1 counter-clockwise about u × v, −1 clockwise
  double start_angle_rad = 0.0;

  double AngleAt(double time_s) const;
  Isometry3 BaseFromFlange(double time_s) const;  // the programmed pose
};

// A programmed straight move at constant velocity (constant orientation).
struct LineSegment {
  std::string name;
  double start_time_s = 0.0;
  double duration_s = 0.0;
  Isometry3 base_from_flange_start = Isometry3::Identity();
  Vec3 velocity_in_base_mm_s = Vec3::Zero();

  Isometry3 BaseFromFlange(double time_s) const;
};

struct ProgrammedMotion {
  double tool_radius_mm = 0.0;  // nominal radius of the tool's ball-nosed tip (from its drawing)
  std::vector<CircleSegment> circles;
  std::vector<LineSegment> lines;
  std::string source;  // file it was read from, for error messages
};

// Log: reads and checks the header, beam/state names, finite non-decreasing times.
std::vector<BeamEvent> ReadDeviceLog(const std::string& path);
std::vector<BeamEvent> ParseDeviceLog(const std::string& text, const std::string& path);
std::string FormatDeviceLog(const std::vector<BeamEvent>& events);

// Checks that each beam's states alternate blocked, clear, blocked, ... starting with blocked
// (the device starts clear); InputError naming the offending log line otherwise.
void CheckAlternation(const std::vector<BeamEvent>& events, const std::string& path);

ProgrammedMotion ReadProgrammedMotion(const std::string& path);
ProgrammedMotion ProgrammedMotionFromJson(const std::string& text, const std::string& path);
std::string ProgrammedMotionToJson(const ProgrammedMotion& motion);

}  // namespace ramtk::tcf
