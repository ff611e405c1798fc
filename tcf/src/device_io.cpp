// Laser device log CSV and programmed-motion JSON.
#include "ramtk/tcf/device_io.h"

#include <cmath>
#include <cstdio>

#include "ramtk/core/csv.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"

namespace ramtk::tcf {

const char* BeamName(Beam beam) { return beam == Beam::kX ? "x" : "y"; }
const char* BeamStateName(BeamState state) { return state == BeamState::kBlocked ? "blocked" : "clear"; }

double CircleSegment::AngleAt(double time_s) const {
  return start_angle_rad + direction * angular_speed_rad_s * (time_s - start_time_s);
}

Isometry3 CircleSegment::BaseFromFlange(double time_s) const {
  const double phi = AngleAt(time_s);
  Isometry3 pose = base_from_flange_centre;
  pose.translation() += radius_mm * (std::cos(phi) * u_in_base + std::sin(phi) * v_in_base);
  return pose;
}

Isometry3 LineSegment::BaseFromFlange(double time_s) const {
  Isometry3 pose = base_from_flange_start;
  pose.translation() += velocity_in_base_mm_s * (time_s - start_time_s);
  return pose;
}

std::vector<BeamEvent> ParseDeviceLog(const std::string& text, const std::string& path) {
  const CsvTable t = ParseCsv(text, path);
  const int ct = t.Column("time_s"), cb = t.Column("beam"), cs = t.Column("state");
  std::vector<BeamEvent> out;
  out.reserve(t.size());
  for (std::size_t r = 0; r < t.size(); ++r) {
    BeamEvent e;
    e.line = t.line_numbers[r];
    e.time_s = t.Number(r, ct);
    const std::string& b = t.Text(r, cb);
    const std::string& s = t.Text(r, cs);
    if (b == "x") {
      e.beam = Beam::kX;
    } else if (b == "y") {
      e.beam = Beam::kY;
    } else {
      throw InputError({path, e.line, "beam"}, "expected 'x' or 'y', got '" + b + "'");
    }
    if (s == "blocked") {
      e.state = BeamState::kBlocked;
    } else if (s == "clear") {
      e.state = BeamState::kClear;
    } else {
      throw InputError({path, e.line, "state"}, "expected 'blocked' or 'clear', got '" + s + "'");
    }
    if (!out.empty() && e.time_s < out.back().time_s)
      throw InputError({path, e.line, "time_s"}, "times must not decrease");
    out.push_back(e);
  }
  return out;
}

std::vector<BeamEvent> ReadDeviceLog(const std::string& path) { return ParseDeviceLog(ReadTextFile(path), path); }

std::string FormatDeviceLog(const std::vector<BeamEvent>& events) {
  std::vector<std::vector<std::string>> rows;
  for (const BeamEvent& e : events)
    rows.push_back({FormatFixed(e.time_s, 7), BeamName(e.beam), BeamStateName(e.state)});
  return FormatCsv({"time_s", "beam", "state"}, rows);
}

void CheckAlternation(const std::vector<BeamEvent>& events, const std::string& path) {
  BeamState expected[2] = {BeamState::kBlocked, BeamState::kBlocked};
  for (const BeamEvent& e : events) {
    BeamState& want = expected[static_cast<int>(e.beam)];
    if (e.state != want) {
      throw InputError({path, e.line, "state"},
                       std::string("beam ") + BeamName(e.beam) + " events do not alternate: '" +
                           BeamStateName(e.state) + "' follows '" +
                           BeamStateName(want == BeamState::kBlocked ? BeamState::kClear : BeamState::kBlocked) + "'");
    }
    want = want == BeamState::kBlocked ? BeamState::kClear : BeamState::kBlocked;
  }
}

ProgrammedMotion ProgrammedMotionFromJson(const std::string& text, const std::string& path) {
  const nlohmann::json j = ParseJsonText(text, path);
  ProgrammedMotion m;
  m.source = path;
  m.tool_radius_mm = JsonNumberAt(j, "tool_radius_mm", path, "");
  if (!(m.tool_radius_mm >= 0.0)) throw InputError({path, 0, "tool_radius_mm"}, "must be >= 0");
  const nlohmann::json& circles = JsonRequire(j, "circles", path, "");
  if (!circles.is_array()) throw InputError({path, 0, "circles"}, "expected an array");
  for (std::size_t i = 0; i < circles.size(); ++i) {
    const nlohmann::json& c = circles[i];
    const std::string w = "circles[" + std::to_string(i) + "].";
    CircleSegment s;
    s.name = c.value("name", "circle" + std::to_string(i));
    s.start_time_s = JsonNumberAt(c, "start_time_s", path, w);
    s.duration_s = JsonNumberAt(c, "duration_s", path, w);
    s.base_from_flange_centre = JsonPoseAt(c, "centre_flange_pose", path, w);
    s.u_in_base = JsonVec3At(c, "u_in_base", path, w);
    s.v_in_base = JsonVec3At(c, "v_in_base", path, w);
    if (std::abs(s.u_in_base.norm() - 1.0) > 1e-6 || std::abs(s.v_in_base.norm() - 1.0) > 1e-6 ||
        std::abs(s.u_in_base.dot(s.v_in_base)) > 1e-6)
      throw InputError({path, 0, w + "u_in_base"}, "u_in_base and v_in_base must be orthonormal");
    s.radius_mm = JsonNumberAt(c, "radius_mm", path, w);
    if (!(s.radius_mm > 0.0)) throw InputError({path, 0, w + "radius_mm"}, "must be > 0");
    s.angular_speed_rad_s = DegToRad(JsonNumberAt(c, "angular_speed_deg_s", path, w));
    if (!(s.angular_speed_rad_s > 0.0)) throw InputError({path, 0, w + "angular_speed_deg_s"}, "must be > 0");
    const std::string dir = JsonRequire(c, "direction", path, w).get<std::string>();
    if (dir == "ccw") {
      s.direction = 1;
    } else if (dir == "cw") {
      s.direction = -1;
    } else {
      throw InputError({path, 0, w + "direction"}, "expected 'ccw' or 'cw', got '" + dir + "'");
    }
    s.start_angle_rad = DegToRad(JsonNumberAt(c, "start_angle_deg", path, w));
    m.circles.push_back(s);
  }
  if (j.contains("lines")) {
    const nlohmann::json& lines = j.at("lines");
    if (!lines.is_array()) throw InputError({path, 0, "lines"}, "expected an array");
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const nlohmann::json& l = lines[i];
      const std::string w = "lines[" + std::to_string(i) + "].";
      LineSegment s;
      s.name = l.value("name", "line" + std::to_string(i));
      s.start_time_s = JsonNumberAt(l, "start_time_s", path, w);
      s.duration_s = JsonNumberAt(l, "duration_s", path, w);
      s.base_from_flange_start = JsonPoseAt(l, "start_flange_pose", path, w);
      s.velocity_in_base_mm_s = JsonVec3At(l, "velocity_in_base_mm_s", path, w);
      m.lines.push_back(s);
    }
  }
  return m;
}

ProgrammedMotion ReadProgrammedMotion(const std::string& path) {
  return ProgrammedMotionFromJson(ReadTextFile(path), path);
}

std::string ProgrammedMotionToJson(const ProgrammedMotion& m) {
  nlohmann::json j;
  j["tool_radius_mm"] = m.tool_radius_mm;
  j["circles"] = nlohmann::json::array();
  for (const CircleSegment& c : m.circles) {
    nlohmann::json o;
    o["name"] = c.name;
    o["start_time_s"] = c.start_time_s;
    o["duration_s"] = c.duration_s;
    o["centre_flange_pose"] = PoseToJson(c.base_from_flange_centre);
    o["u_in_base"] = Vec3ToJson(c.u_in_base);
    o["v_in_base"] = Vec3ToJson(c.v_in_base);
    o["radius_mm"] = c.radius_mm;
    o["angular_speed_deg_s"] = RadToDeg(c.angular_speed_rad_s);
    o["direction"] = c.direction > 0 ? "ccw" : "cw";
    o["start_angle_deg"] = RadToDeg(c.start_angle_rad);
    j["circles"].push_back(o);
  }
  j["lines"] = nlohmann::json::array();
  for (const LineSegment& l : m.lines) {
    nlohmann::json o;
    o["name"] = l.name;
    o["start_time_s"] = l.start_time_s;
    o["duration_s"] = l.duration_s;
    o["start_flange_pose"] = PoseToJson(l.base_from_flange_start);
    o["velocity_in_base_mm_s"] = Vec3ToJson(l.velocity_in_base_mm_s);
    j["lines"].push_back(o);
  }
  return j.dump(2) + "\n";
}

}  // namespace ramtk::tcf
