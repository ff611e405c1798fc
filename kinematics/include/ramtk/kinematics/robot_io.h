#pragma once
// Robot model files (YAML; format in docs/formats.md). Lengths in mm, angles in degrees.
// Malformed files raise ramtk::InputError naming the file, line and field.

#include <string>

#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {

RobotModel ReadRobotModel(const std::string& path);
// Parses YAML text; `path` is only used in error messages.
RobotModel ParseRobotModel(const std::string& yaml_text, const std::string& path);
// Writes the model in the same format (degrees, mm). Written to a temporary file first and
// renamed, so a failure leaves no half-written file.
void WriteRobotModel(const RobotModel& model, const std::string& path);
std::string RobotModelToYaml(const RobotModel& model);

}  // namespace ramtk::kinematics
