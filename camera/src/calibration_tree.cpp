// Stereo calibration text → CalibrationNode tree (calibration_tree.h), with yaml-cpp and
// nlohmann-json instead of cv::FileStorage.
#include "calibration_tree.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "ramtk/core/error.h"
#include "ramtk/core/json.h"
#include "ramtk/core/yaml.h"

namespace ramtk::camera::internal {
namespace {

using Kind = CalibrationNode::Kind;

bool IsInteger(const std::string& s) {
  std::size_t i = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  if (i == s.size()) return false;
  for (; i < s.size(); ++i)
    if (s[i] < '0' || s[i] > '9') return false;
  return true;
}

// A plain YAML scalar as a number, if the whole of it is one (YAML's .inf / .nan spelled too).
bool ParseYamlNumber(const std::string& s, double* value) {
  if (s.empty()) return false;
  std::string lower;
  for (char c : s) lower += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  for (const auto& [word, v] : {std::pair<const char*, double>{".inf", HUGE_VAL},
                                {"+.inf", HUGE_VAL},
                                {"-.inf", -HUGE_VAL},
                                {".nan", std::nan("")}}) {
    if (lower == word) {
      *value = v;
      return true;
    }
  }
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  // Hexadecimal and "infinity"/"nan" spellings are strtod's, not YAML's: leave them as text.
  if (end != begin + s.size() || s.find_first_of("xXnN") != std::string::npos) return false;
  *value = v;  // an overflow gives ±HUGE_VAL, refused later as non-finite
  return true;
}

CalibrationNode FromYaml(const YAML::Node& node, const std::string& path, int depth) {
  CalibrationNode out;
  out.line = node.Mark().is_null() ? 0 : node.Mark().line + 1;
  if (depth > kMaxCalibrationDepth)
    throw InputError({path, out.line, ""}, "nested deeper than " + std::to_string(kMaxCalibrationDepth) + " levels");
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      out.kind = Kind::kNull;
      break;
    case YAML::NodeType::Scalar: {
      const std::string& s = node.Scalar();
      // A quoted scalar has the tag "!" and stays text.
      if (node.Tag() != "!" && ParseYamlNumber(s, &out.number)) {
        out.kind = Kind::kNumber;
        out.integer = IsInteger(s);
      } else {
        out.kind = Kind::kText;
        out.text = s;
      }
      break;
    }
    case YAML::NodeType::Sequence:
      out.kind = Kind::kList;
      for (const YAML::Node& item : node) out.items.push_back(FromYaml(item, path, depth + 1));
      break;
    case YAML::NodeType::Map:
      out.kind = Kind::kMap;
      for (const auto& kv : node) {
        if (!kv.first.IsScalar()) throw InputError({path, kv.first.Mark().line + 1, ""}, "a key that is not a name");
        const std::string key = kv.first.Scalar();
        if (out.Find(key) != nullptr) throw InputError({path, kv.first.Mark().line + 1, key}, "duplicate key");
        out.fields.emplace_back(key, FromYaml(kv.second, path, depth + 1));
      }
      break;
  }
  return out;
}

CalibrationNode FromJson(const nlohmann::json& j, const std::string& path, int depth) {
  if (depth > kMaxCalibrationDepth)
    throw InputError({path, 0, ""}, "nested deeper than " + std::to_string(kMaxCalibrationDepth) + " levels");
  CalibrationNode out;
  if (j.is_number()) {
    out.kind = Kind::kNumber;
    out.number = j.get<double>();
    out.integer = j.is_number_integer();
  } else if (j.is_string()) {
    out.kind = Kind::kText;
    out.text = j.get<std::string>();
  } else if (j.is_boolean()) {
    out.kind = Kind::kText;
    out.text = j.get<bool>() ? "true" : "false";
  } else if (j.is_array()) {
    out.kind = Kind::kList;
    for (const auto& item : j) out.items.push_back(FromJson(item, path, depth + 1));
  } else if (j.is_object()) {
    out.kind = Kind::kMap;
    for (auto it = j.begin(); it != j.end(); ++it)
      out.fields.emplace_back(it.key(), FromJson(it.value(), path, depth + 1));
  }
  return out;
}

CalibrationNode FromFileNode(const cv::FileNode& node, const std::string& path, int depth) {
  if (depth > kMaxCalibrationDepth)
    throw InputError({path, 0, ""}, "nested deeper than " + std::to_string(kMaxCalibrationDepth) + " levels");
  CalibrationNode out;
  if (node.isInt() || node.isReal()) {
    out.kind = Kind::kNumber;
    out.number = node.real();
    out.integer = node.isInt();
  } else if (node.isString()) {
    out.kind = Kind::kText;
    out.text = node.string();
  } else if (node.isSeq()) {
    out.kind = Kind::kList;
    for (const cv::FileNode& item : node) out.items.push_back(FromFileNode(item, path, depth + 1));
  } else if (node.isMap()) {
    out.kind = Kind::kMap;
    for (const cv::FileNode& item : node) {
      const std::string key = item.name();
      if (out.Find(key) != nullptr) throw InputError({path, 0, key}, "duplicate key");
      out.fields.emplace_back(key, FromFileNode(item, path, depth + 1));
    }
  }
  return out;
}

// OpenCV's XML FileStorage (<opencv_storage>), read by cv::FileStorage; no line numbers. Control
// characters (which XML 1.0 does not allow) are refused first: a NUL inside an attribute makes
// OpenCV 4.6's XML parser read through a null pointer (fuzz/crashes/fuzz_stereo_calibration-crash-5050…).
CalibrationNode FromXml(const std::string& text, const std::string& path) {
  int line = 1;
  for (const char c : text) {
    if (c == '\n') ++line;
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\t' && c != '\n' && c != '\r')
      throw InputError({path, line, ""}, "a control character (code " + std::to_string(u) + ") in an XML file");
  }
  try {
    cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_XML);
    if (!fs.isOpened()) throw InputError({path, 0, ""}, "cannot parse as OpenCV XML FileStorage");
    CalibrationNode root = FromFileNode(fs.root(), path, 0);
    if (root.kind == Kind::kNull) root.kind = Kind::kMap;  // <opencv_storage/>: no keys
    return root;
  } catch (const cv::Exception& e) {
    throw InputError({path, 0, ""}, "cannot parse as OpenCV XML FileStorage: " + e.msg);
  }
}

}  // namespace

const CalibrationNode* CalibrationNode::Find(const std::string& key) const {
  if (kind != Kind::kMap) return nullptr;
  for (const auto& [name, node] : fields)
    if (name == key) return &node;
  return nullptr;
}

CalibrationNode ParseCalibrationTree(const std::string& text, const std::string& path) {
  if (text.size() > kMaxCalibrationFileBytes)
    throw InputError({path, 0, ""}, "is " + std::to_string(text.size()) + " bytes; a calibration file is at most " +
                                        std::to_string(kMaxCalibrationFileBytes) + " bytes");
  std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text.compare(first, 3, "\xEF\xBB\xBF") == 0) first += 3;  // UTF-8 BOM
  const char lead = first == std::string::npos ? '\0' : text[first];
  if (lead == '<') return FromXml(text, path);
  if (lead == '{') {
    return FromJson(ParseJsonText(text.substr(first), path), path, 0);
  }
  // OpenCV's YAML starts with "%YAML:1.0", which is not a YAML directive: drop that line but
  // keep its newline so that line numbers stay those of the file.
  std::string yaml = text;
  if (yaml.compare(0, 6, "%YAML:") == 0) {
    const std::size_t eol = yaml.find('\n');
    yaml.erase(0, eol == std::string::npos ? yaml.size() : eol);
  }
  try {
    return FromYaml(LoadYamlText(yaml, path), path, 0);
  } catch (const YAML::Exception& e) {
    throw InputError({path, e.mark.is_null() ? 0 : e.mark.line + 1, ""}, "cannot parse as YAML: " + e.msg);
  }
}

}  // namespace ramtk::camera::internal
