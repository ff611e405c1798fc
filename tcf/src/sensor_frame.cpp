// Sensor-frame calibration of the cross-laser device, thesis eqs. (4-15)..(4-27).
#include "ramtk/tcf/sensor_frame.h"

#include <cmath>
#include <cstdio>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"

namespace ramtk::tcf {

std::string SensorFrameOptions::Validate() const {
  if (!(min_beam_angle_deg > 0.0 && min_beam_angle_deg < 90.0)) return "min_beam_angle_deg must be in (0, 90)";
  if (!(max_beam_gap_mm > 0.0)) return "max_beam_gap_mm must be > 0";
  if (!(min_point_separation_mm > 0.0)) return "min_point_separation_mm must be > 0";
  return "";
}

Vec3 SensorFrame::YBeamDirection() const { return Vec3(std::cos(beta_rad), std::sin(beta_rad), 0.0); }

std::string SensorFrame::BriefReport() const {
  char buf[256];
  const Vec3& t = base_from_lasersensor.translation();
  std::snprintf(buf, sizeof(buf), "origin (%.3f, %.3f, %.3f) mm, beta %.3f deg, beam gap %.4f mm", t.x(), t.y(), t.z(),
                RadToDeg(beta_rad), beam_gap_mm);
  return buf;
}

BeamPoints BeamPointsFromFlangePositions(const std::map<std::string, Vec3>& flange_in_base, const std::string& source) {
  auto get = [&](const std::string& label) -> const Vec3& {
    auto it = flange_in_base.find(label);
    if (it == flange_in_base.end()) throw InputError({source, 0, label}, "missing calibration point");
    return it->second;
  };
  // Eq. (4-16): x, y from the horizontal pass (k = 1, 2), z from the vertical pass (k = 3, 4).
  auto point = [&](char name) {
    const std::string s(1, name);
    const Vec3& p1 = get(s + "1");
    const Vec3& p2 = get(s + "2");
    const Vec3& p3 = get(s + "3");
    const Vec3& p4 = get(s + "4");
    return Vec3(0.5 * (p1.x() + p2.x()), 0.5 * (p1.y() + p2.y()), 0.5 * (p3.z() + p4.z()));
  };
  return {point('A'), point('B'), point('C'), point('D')};
}

SensorFrame CalibrateSensorFrame(const BeamPoints& pts, const SensorFrameOptions& options, const std::string& source) {
  ThrowIfInvalid(options.Validate(), "SensorFrameOptions");
  const Vec3 d1 = pts.b - pts.a;  // (m1, n1, p1) of eq. (4-17)
  const Vec3 d2 = pts.d - pts.c;  // (m2, n2, p2) of eq. (4-18)
  if (d1.norm() < options.min_point_separation_mm)
    throw InputError({source, 0, "A,B"}, "points A and B of the x beam coincide; the beam direction is undefined");
  if (d2.norm() < options.min_point_separation_mm)
    throw InputError({source, 0, "C,D"}, "points C and D of the y beam coincide; the beam direction is undefined");
  SensorFrame f;
  f.a_in_base = pts.a;
  f.b_in_base = pts.b;
  f.c_in_base = pts.c;
  f.d_in_base = pts.d;
  f.n = d1.normalized();  // (4-23)
  f.m = d2.normalized();  // (4-24)
  const Vec3 cross = f.n.cross(f.m);
  const double angle = std::atan2(cross.norm(), f.n.dot(f.m));
  const double min_angle = DegToRad(options.min_beam_angle_deg);
  if (angle < min_angle || angle > kPi - min_angle) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "the beams are %.2f deg from parallel (minimum %.1f deg): they do not cross",
                  RadToDeg(std::min(angle, kPi - angle)), options.min_beam_angle_deg);
    throw InputError({source, 0, "AB,CD"}, buf);
  }
  // Eqs. (4-19)..(4-21): parameters of the common perpendicular's feet P (on AB) and Q (on CD).
  const Vec3 ac = pts.a - pts.c;
  const double k1 = d1.squaredNorm(), k2 = d2.squaredNorm(), k3 = d1.dot(d2);
  const double k4 = ac.dot(d1), k5 = ac.dot(d2);
  const double den = k3 * k3 - k1 * k2;
  const double t_p = (k2 * k4 - k3 * k5) / den;
  const double s_q = (k3 * k4 - k1 * k5) / den;
  f.p_in_base = pts.a + t_p * d1;
  f.q_in_base = pts.c + s_q * d2;
  f.m_in_base = 0.5 * (f.p_in_base + f.q_in_base);  // (4-22)
  f.beam_gap_mm = (f.p_in_base - f.q_in_base).norm();
  if (f.beam_gap_mm > options.max_beam_gap_mm) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "the beam lines pass %.3f mm apart (maximum %.3f mm): they do not cross",
                  f.beam_gap_mm, options.max_beam_gap_mm);
    throw InputError({source, 0, "AB,CD"}, buf);
  }
  f.p = cross.normalized();  // (4-25)
  f.o = f.p.cross(f.n);      // (4-26)
  f.beta_rad = std::acos(std::clamp(f.n.dot(f.m), -1.0, 1.0));
  f.base_from_lasersensor.linear().col(0) = f.n;
  f.base_from_lasersensor.linear().col(1) = f.o;
  f.base_from_lasersensor.linear().col(2) = f.p;
  f.base_from_lasersensor.translation() = f.m_in_base;  // (4-27)
  f.x_beam_z_mm = f.p.dot(f.p_in_base - f.m_in_base);
  f.y_beam_z_mm = f.p.dot(f.q_in_base - f.m_in_base);
  return f;
}

std::map<std::string, Vec3> ReadSensorCalibrationPoints(const std::string& path) {
  const CsvTable t = ReadCsv(path);
  const int cl = t.Column("label"), cx = t.Column("x"), cy = t.Column("y"), cz = t.Column("z");
  std::map<std::string, Vec3> out;
  for (std::size_t r = 0; r < t.size(); ++r) {
    const std::string& label = t.Text(r, cl);
    const bool ok = label.size() == 2 && label[0] >= 'A' && label[0] <= 'D' && label[1] >= '1' && label[1] <= '4';
    if (!ok)
      throw InputError({path, t.line_numbers[r], "label"},
                       "expected A1..A4, B1..B4, C1..C4 or D1..D4, got '" + label + "'");
    if (out.count(label)) throw InputError({path, t.line_numbers[r], "label"}, "duplicate label '" + label + "'");
    out[label] = Vec3(t.Number(r, cx), t.Number(r, cy), t.Number(r, cz));
  }
  return out;
}

std::string SensorFrameToJson(const SensorFrame& f) {
  nlohmann::json j;
  j["base_from_lasersensor"] = PoseToJson(f.base_from_lasersensor);
  j["beta_deg"] = RadToDeg(f.beta_rad);
  j["beam_gap_mm"] = f.beam_gap_mm;
  j["x_beam_z_mm"] = f.x_beam_z_mm;
  j["y_beam_z_mm"] = f.y_beam_z_mm;
  // Only the intermediate results that were computed (a simulated frame has no beam points).
  nlohmann::json points = nlohmann::json::object(), units = nlohmann::json::object();
  const std::pair<const char*, const Vec3*> named_points[] = {
      {"A", &f.a_in_base}, {"B", &f.b_in_base}, {"C", &f.c_in_base}, {"D", &f.d_in_base},
      {"P", &f.p_in_base}, {"Q", &f.q_in_base}, {"M", &f.m_in_base}};
  for (const auto& [name, v] : named_points) {
    if (v->allFinite()) points[name] = Vec3ToJson(*v);
  }
  const std::pair<const char*, const Vec3*> named_units[] = {
      {"n_x_axis", &f.n}, {"m_y_beam", &f.m}, {"o_y_prime_axis", &f.o}, {"p_z_axis", &f.p}};
  for (const auto& [name, v] : named_units) {
    if (v->allFinite()) units[name] = Vec3ToJson(*v);
  }
  j["points_in_base_mm"] = points;
  j["unit_vectors"] = units;
  return j.dump(2) + "\n";
}

SensorFrame SensorFrameFromJson(const std::string& text, const std::string& path) {
  const nlohmann::json j = ParseJsonText(text, path);
  SensorFrame f;
  f.base_from_lasersensor = JsonPoseAt(j, "base_from_lasersensor", path, "");
  f.beta_rad = DegToRad(JsonNumberAt(j, "beta_deg", path, ""));
  if (!(f.beta_rad > DegToRad(1.0) && f.beta_rad < DegToRad(179.0)))
    throw InputError({path, 0, "beta_deg"}, "must be in (1, 179) degrees");
  f.beam_gap_mm = j.contains("beam_gap_mm") ? JsonNumberAt(j, "beam_gap_mm", path, "") : 0.0;
  f.x_beam_z_mm = j.contains("x_beam_z_mm") ? JsonNumberAt(j, "x_beam_z_mm", path, "") : 0.0;
  f.y_beam_z_mm = j.contains("y_beam_z_mm") ? JsonNumberAt(j, "y_beam_z_mm", path, "") : 0.0;
  const Mat3 r = f.base_from_lasersensor.linear();
  f.n = r.col(0);
  f.o = r.col(1);
  f.p = r.col(2);
  f.m = std::cos(f.beta_rad) * f.n + std::sin(f.beta_rad) * f.o;
  f.m_in_base = f.base_from_lasersensor.translation();
  return f;
}

SensorFrame ReadSensorFrame(const std::string& path) { return SensorFrameFromJson(ReadTextFile(path), path); }

}  // namespace ramtk::tcf
