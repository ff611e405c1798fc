#pragma once
// Robot model files (YAML; format in docs/formats.md). Lengths in mm, angles in degrees.
// Malformed files raise ramtk::InputError naming the file, line and field.

#include <string>

#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {

// A 6-joint robot (every command but `calib robot`); a file with another joint count is an
// InputError naming `joints`.
RobotModel ReadRobotModel(const std::string& path);
// Parses YAML text; `path` is only used in error messages.
RobotModel ParseRobotModel(const std::string& yaml_text, const std::string& path);
// Writes the model in the same format (degrees, mm). Written to a temporary file first and
// renamed, so a failure leaves no half-written file.
void WriteRobotModel(const RobotModel& model, const std::string& path);
std::string RobotModelToYaml(const RobotModel& model);

// The same file with any number of joints (1..kMaxChainJoints) and the optional gravity-load
// data: per joint `mass` (kg) and `com` ([x, y, z] mm in the link frame), `payload` {mass, com}
// in the flange frame, `gravity` (direction in the base frame, default [0, 0, -1]).
RobotChain ReadRobotChain(const std::string& path);
RobotChain ParseRobotChain(const std::string& yaml_text, const std::string& path);
void WriteRobotChain(const RobotChain& chain, const std::string& path);
std::string RobotChainToYaml(const RobotChain& chain);

}  // namespace ramtk::kinematics
