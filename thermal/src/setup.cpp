#include "ramtk/thermal/setup.h"

#include <Eigen/SVD>
#include <nlohmann/json.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/thesis_setup.h"

namespace ramtk::thermal {
namespace {

Isometry3 TransformFromJson(const nlohmann::json& j, const std::string& path, const std::string& field) {
  if (!j.is_array() || (j.size() != 3 && j.size() != 4)) {
    throw InputError({path, 0, field}, "expected 3 or 4 rows of 4 numbers");
  }
  Mat4 m = Mat4::Identity();
  for (std::size_t r = 0; r < j.size(); ++r) {
    if (!j[r].is_array() || j[r].size() != 4) throw InputError({path, 0, field}, "every row needs 4 numbers");
    for (int c = 0; c < 4; ++c) {
      if (!j[r][c].is_number()) throw InputError({path, 0, field}, "entries must be numbers");
      m(static_cast<int>(r), c) = j[r][c].get<double>();
    }
  }
  const Mat3 rot = m.topLeftCorner<3, 3>();
  if (OrthonormalityError(rot) > 1e-3) {
    throw InputError({path, 0, field},
                     "rotation part is not orthonormal (error " + std::to_string(OrthonormalityError(rot)) + ")");
  }
  Isometry3 t = Isometry3::Identity();
  t.linear() = NearestRotation(rot);
  t.translation() = m.block<3, 1>(0, 3);
  return t;
}

nlohmann::json TransformToJson(const Isometry3& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    rows.push_back({t.linear()(r, 0), t.linear()(r, 1), t.linear()(r, 2), t.translation()(r)});
  }
  return rows;
}

}  // namespace

Isometry3 ThesisSensorFromBase() { return ramtk::ThesisSensorFromBase(); }

Vec3 ThesisBallInFlange() { return ramtk::ThesisBallInFlange(); }

ThermalSetup ReadThermalSetup(const std::string& path) {
  const std::string text = ReadTextFile(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw InputError({path, 0, ""}, std::string("not valid JSON: ") + e.what());
  }
  ThermalSetup s;
  if (!j.contains("sensor_from_base")) throw InputError({path, 0, "sensor_from_base"}, "missing");
  s.sensor_from_base = TransformFromJson(j["sensor_from_base"], path, "sensor_from_base");
  if (!j.contains("ball_in_flange_mm")) throw InputError({path, 0, "ball_in_flange_mm"}, "missing");
  const auto& b = j["ball_in_flange_mm"];
  if (!b.is_array() || b.size() != 3 || !b[0].is_number() || !b[1].is_number() || !b[2].is_number()) {
    throw InputError({path, 0, "ball_in_flange_mm"}, "expected [x, y, z] in mm");
  }
  s.ball_in_flange = Vec3(b[0].get<double>(), b[1].get<double>(), b[2].get<double>());
  if (j.contains("flange_from_tool_sensor")) {
    s.flange_from_tool_sensor = TransformFromJson(j["flange_from_tool_sensor"], path, "flange_from_tool_sensor");
    s.has_tool_sensor = true;
  }
  return s;
}

std::string ThermalSetupToJson(const ThermalSetup& setup) {
  nlohmann::json j;
  j["sensor_from_base"] = TransformToJson(setup.sensor_from_base);
  j["ball_in_flange_mm"] = {setup.ball_in_flange.x(), setup.ball_in_flange.y(), setup.ball_in_flange.z()};
  if (setup.has_tool_sensor) j["flange_from_tool_sensor"] = TransformToJson(setup.flange_from_tool_sensor);
  return j.dump(2) + "\n";
}

void WriteThermalSetup(const ThermalSetup& setup, const std::string& path) {
  WriteFileAtomically(path, ThermalSetupToJson(setup));
}

}  // namespace ramtk::thermal
