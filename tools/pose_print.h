#pragma once
// Printing of flange poses for the command line: position (mm), rotation matrix, KUKA A,B,C (deg).

#include <string>

#include "ramtk/core/json.h"
#include "ramtk/core/rotation.h"

namespace ramtk::tools {

std::string FormatPose(const std::string& title, const Isometry3& pose);
// JSON output uses ramtk::PoseToJson (core/json.h): position_mm, abc_deg, matrix.

}  // namespace ramtk::tools
