#include "ramtk/thermal/setup.h"

#include <nlohmann/json.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/thesis_setup.h"

namespace ramtk::thermal {

Isometry3 ThesisSensorFromBase() { return ramtk::ThesisSensorFromBase(); }

Vec3 ThesisBallInFlange() { return ramtk::ThesisBallInFlange(); }

ThermalSetup ReadThermalSetup(const std::string& path) {
  const std::string text = ReadTextFile(path);
  const nlohmann::json j = ParseJsonText(text, path);
  ThermalSetup s;
  s.sensor_from_base = JsonPoseAt(j, "sensor_from_base", path);
  s.ball_in_flange = JsonVec3At(j, "ball_in_flange_mm", path);
  if (j.contains("flange_from_tool_sensor")) {
    s.flange_from_tool_sensor = JsonPoseAt(j, "flange_from_tool_sensor", path);
    s.has_tool_sensor = true;
  }
  return s;
}

std::string ThermalSetupToJson(const ThermalSetup& setup) {
  nlohmann::json j;
  j["sensor_from_base"] = PoseToJson(setup.sensor_from_base);
  j["ball_in_flange_mm"] = Vec3ToJson(setup.ball_in_flange);
  if (setup.has_tool_sensor) j["flange_from_tool_sensor"] = PoseToJson(setup.flange_from_tool_sensor);
  return j.dump(2) + "\n";
}

void WriteThermalSetup(const ThermalSetup& setup, const std::string& path) {
  WriteFileAtomically(path, ThermalSetupToJson(setup));
}

}  // namespace ramtk::thermal
