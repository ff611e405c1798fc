// The tracker column file (YAML): TrackerFormat, its checks and its reader.
#include "tracker_internal.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <unordered_map>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"
#include "ramtk/core/yaml.h"

namespace ramtk::kinematics {

using tracker_detail::RotationColumnCount;

// ---------------------------------------------------------------------------------------------

std::string TrackerFormat::Validate() const {
  if (separator != 0 && separator != ',' && separator != ';' && separator != '\t' && separator != '|') {
    return "separator: expected ',', ';', tab, '|' or 0 (detect)";
  }
  if (decimal != 0 && decimal != '.' && decimal != ',') return "decimal: expected '.', ',' or 0 (detect)";
  if (decimal == ',' && separator == ',') return "decimal: the decimal mark ',' cannot also be the separator";
  auto named = [](const std::vector<std::string>& names) {
    for (const std::string& n : names) {
      if (n.empty()) return false;
    }
    return true;
  };
  if (joint_columns.size() > 12) return "joint_columns: at most 12 joints";
  if (!named(joint_columns)) return "joint_columns: empty column name";
  if (position_columns.size() % 3 != 0) {
    return "position_columns: expected three columns (x,y,z) per target, got " +
           std::to_string(position_columns.size());
  }
  if (!named(position_columns)) return "position_columns: empty column name";
  if (!target_column.empty() && position_columns.size() > 3) {
    return "position_columns: one target per row (target_column) takes exactly three columns";
  }
  if (!pose_column.empty() && target_column.empty()) {
    return "pose_column: only used with target_column (one target per row)";
  }
  if (rotation == RotationForm::kNone && !rotation_columns.empty()) {
    return "rotation_columns: given without a rotation form (rotation: none)";
  }
  if (!rotation_columns.empty() && static_cast<int>(rotation_columns.size()) != RotationColumnCount(rotation)) {
    return "rotation_columns: expected " + std::to_string(RotationColumnCount(rotation)) +
           " columns for this rotation form, got " + std::to_string(rotation_columns.size());
  }
  if (!named(rotation_columns)) return "rotation_columns: empty column name";
  if (!sigma_columns.empty() && !covariance_columns.empty()) {
    return "sigma_columns: give sigma_columns or covariance_columns, not both";
  }
  if (sigma_columns.size() % 3 != 0) return "sigma_columns: expected three columns (sx,sy,sz) per target";
  if (covariance_columns.size() % 6 != 0) {
    return "covariance_columns: expected six columns (cov_xx,cov_yy,cov_zz,cov_xy,cov_xz,cov_yz) per target";
  }
  if (!position_columns.empty() && !sigma_columns.empty() && sigma_columns.size() != position_columns.size()) {
    return "sigma_columns: expected as many columns as position_columns";
  }
  if (!position_columns.empty() && !covariance_columns.empty() &&
      covariance_columns.size() != 2 * position_columns.size()) {
    return "covariance_columns: expected six columns per target of position_columns";
  }
  if (!named(sigma_columns) || !named(covariance_columns)) return "sigma_columns: empty column name";
  if (reference_columns.size() % 3 != 0) return "reference_columns: expected three columns (x,y,z) per reference";
  if (!named(reference_columns)) return "reference_columns: empty column name";
  if (time_form != "auto" && time_form != "seconds" && time_form != "iso8601" && time_form != "yyyymmddhhmmss") {
    return "time_form: expected auto, seconds, iso8601 or yyyymmddhhmmss, got '" + time_form + "'";
  }
  return "";
}

// ---------------------------------------------------------------------------------------------
// The format file.

namespace {

InputLocation YamlAt(const std::string& path, const YAML::Node& node, const std::string& field) {
  InputLocation where{path, 0, field};
  if (node.IsDefined() && node.Mark().line >= 0) where.line = node.Mark().line + 1;
  return where;
}

std::string YamlText(const std::string& path, const YAML::Node& node, const std::string& key) {
  if (node.IsNull()) return {};
  if (!node.IsScalar()) throw InputError(YamlAt(path, node, key), "expected text");
  return node.Scalar();
}

std::vector<std::string> YamlNames(const std::string& path, const YAML::Node& node, const std::string& key) {
  if (node.IsNull()) return {};
  if (!node.IsSequence()) throw InputError(YamlAt(path, node, key), "expected a list of column names");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = key + "[" + std::to_string(i) + "]";
    if (!node[i].IsScalar() || node[i].Scalar().empty()) {
      throw InputError(YamlAt(path, node[i], field), "expected a column name");
    }
    out.push_back(node[i].Scalar());
  }
  return out;
}

char YamlChar(const std::string& path, const YAML::Node& node, const std::string& key, bool separator) {
  const std::string v = YamlText(path, node, key);
  if (v.empty() || v == "auto") return 0;
  if (separator && (v == "tab" || v == "\t")) return '\t';
  if (v.size() == 1) return v[0];
  throw InputError(
      YamlAt(path, node, key),
      std::string("expected ") + (separator ? "',', ';', tab, '|'" : "'.' or ','") + " or auto, got '" + v + "'");
}

}  // namespace

TrackerFormat ParseTrackerFormat(const std::string& yaml_text, const std::string& path) {
  const YAML::Node root = LoadYamlText(yaml_text, path);
  TrackerFormat f;
  if (root.IsNull()) return f;
  if (!root.IsMap()) throw InputError({path, 1, ""}, "expected a YAML mapping at the top level");
  std::map<std::string, int> key_lines;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string key = it->first.Scalar();
    const YAML::Node value = it->second;
    key_lines[key] = it->first.Mark().line + 1;
    auto unit = [&](const char* a, const char* b) {
      const std::string v = YamlText(path, value, key);
      if (v == a) return 0;
      if (v == b) return 1;
      throw InputError(YamlAt(path, value, key), std::string("expected '") + a + "' or '" + b + "', got '" + v + "'");
    };
    if (key == "separator") {
      f.separator = YamlChar(path, value, key, true);
    } else if (key == "decimal") {
      f.decimal = YamlChar(path, value, key, false);
    } else if (key == "joint_columns") {
      f.joint_columns = YamlNames(path, value, key);
    } else if (key == "joint_unit") {
      f.joint_unit = unit("deg", "rad") == 0 ? AngleUnit::kDegree : AngleUnit::kRadian;
    } else if (key == "position_columns") {
      f.position_columns = YamlNames(path, value, key);
    } else if (key == "length_unit") {
      f.length_unit = unit("mm", "m") == 0 ? LengthUnit::kMillimetre : LengthUnit::kMetre;
    } else if (key == "target_column") {
      f.target_column = YamlText(path, value, key);
    } else if (key == "pose_column") {
      f.pose_column = YamlText(path, value, key);
    } else if (key == "rotation") {
      const std::string v = YamlText(path, value, key);
      if (v == "none") {
        f.rotation = RotationForm::kNone;
      } else if (v == "quaternion") {
        f.rotation = RotationForm::kQuaternion;
      } else if (v == "kuka_abc") {
        f.rotation = RotationForm::kKukaAbc;
      } else if (v == "euler_xyz") {
        f.rotation = RotationForm::kEulerXyz;
      } else if (v == "matrix") {
        f.rotation = RotationForm::kMatrix;
      } else {
        throw InputError(YamlAt(path, value, key),
                         "expected none, quaternion, kuka_abc, euler_xyz or matrix, got '" + v + "'");
      }
    } else if (key == "rotation_columns") {
      f.rotation_columns = YamlNames(path, value, key);
    } else if (key == "rotation_unit") {
      f.rotation_unit = unit("deg", "rad") == 0 ? AngleUnit::kDegree : AngleUnit::kRadian;
    } else if (key == "sigma_columns") {
      f.sigma_columns = YamlNames(path, value, key);
    } else if (key == "covariance_columns") {
      f.covariance_columns = YamlNames(path, value, key);
    } else if (key == "reference_columns") {
      f.reference_columns = YamlNames(path, value, key);
    } else if (key == "time_column") {
      f.time_column = YamlText(path, value, key);
    } else if (key == "time_form") {
      f.time_form = YamlText(path, value, key);
    } else if (key == "cycle_column") {
      f.cycle_column = YamlText(path, value, key);
    } else {
      throw InputError({path, it->first.Mark().line + 1, key},
                       "unknown key (expected separator, decimal, joint_columns, joint_unit, position_columns, "
                       "length_unit, target_column, pose_column, rotation, rotation_columns, rotation_unit, "
                       "sigma_columns, covariance_columns, reference_columns, time_column, time_form, cycle_column)");
    }
  }
  const std::string problem = f.Validate();
  if (!problem.empty()) {
    const OptionsProblem p = SplitOptionsProblem(problem);
    const auto line = key_lines.find(p.field);
    throw InputError({path, line == key_lines.end() ? 0 : line->second, p.field}, p.message);
  }
  return f;
}

TrackerFormat ReadTrackerFormat(const std::string& path) { return ParseTrackerFormat(ReadTextFile(path), path); }

}  // namespace ramtk::kinematics
