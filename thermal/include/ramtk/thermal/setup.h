#pragma once
// The fixed geometry of a thermal-compensation cell (thesis §3.1, §5.1): where the calibration
// sensor sits relative to the robot base, where the ball sits on the flange, and where the
// tool-mounted sensor that measures the monitoring points sits on the flange. All in mm.
//
// File (JSON, docs/formats.md "Thermal setup"):
//   {"sensor_from_base": [[r00,r01,r02,tx],[..],[..]] or 4 rows,
//    "ball_in_flange_mm": [x,y,z],
//    "flange_from_tool_sensor": [[...],[...],[...]] (optional; needed for monitoring points)}

#include <string>

#include "ramtk/core/rotation.h"

namespace ramtk::thermal {

struct ThermalSetup {
  Isometry3 sensor_from_base = Isometry3::Identity();         // T_b^s (eq. 5-1)
  Vec3 ball_in_flange = Vec3::Zero();                         // P_e (eq. 5-2), mm
  Isometry3 flange_from_tool_sensor = Isometry3::Identity();  // tool-mounted sensor on the flange
  bool has_tool_sensor = false;                               // flange_from_tool_sensor was given
};

// The thesis's calibration result, eqs. (5-1) and (5-2), with the rotation re-orthonormalised
// (the printed 4-decimal matrix is orthonormal to about 1e-4).
Isometry3 ThesisSensorFromBase();
Vec3 ThesisBallInFlange();

// Reads / writes the JSON file. InputError names the file and the field.
ThermalSetup ReadThermalSetup(const std::string& path);
void WriteThermalSetup(const ThermalSetup& setup, const std::string& path);
std::string ThermalSetupToJson(const ThermalSetup& setup);

}  // namespace ramtk::thermal
