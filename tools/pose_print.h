#pragma once
// Printing of flange poses for the command line: position (mm), rotation matrix, KUKA A,B,C (deg).

#include <string>

#include <nlohmann/json.hpp>

#include "ramtk/core/rotation.h"

namespace ramtk::tools {

std::string FormatPose(const std::string& title, const Isometry3& pose);
nlohmann::json PoseToJson(const Isometry3& pose);

}  // namespace ramtk::tools
