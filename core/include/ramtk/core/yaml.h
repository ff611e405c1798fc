#pragma once
// The one YAML loader of ramtk's readers (robot files, tracker formats, calibration files):
// yaml-cpp, with a syntax error reported as an InputError at its line and a key given twice in
// one mapping refused (yaml-cpp keeps both and a lookup silently takes the first). Header-only:
// include it only from a module that links yaml-cpp.

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>

#include "ramtk/core/error.h"

namespace ramtk {

// InputError naming the file, the line and the key when a mapping in `node` (at any depth) has a
// scalar key twice.
inline void RequireYamlKeysOnce(const YAML::Node& node, const std::string& path) {
  if (node.IsMap()) {
    std::map<std::string, int> first_line;
    for (const auto& entry : node) {
      const YAML::Node& key = entry.first;
      if (key.IsScalar()) {
        const int line = key.Mark().is_null() ? 0 : key.Mark().line + 1;
        const auto [it, inserted] = first_line.emplace(key.Scalar(), line);
        if (!inserted)
          throw InputError({path, line, key.Scalar()}, "duplicate key: given again (first on line " +
                                                           std::to_string(it->second) + "); which value is meant?");
      }
      RequireYamlKeysOnce(entry.second, path);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) RequireYamlKeysOnce(item, path);
  }
}

// Parses `text` (the contents of `path`); InputError for a syntax error (at its line) or a key
// given twice in one mapping.
inline YAML::Node LoadYamlText(const std::string& text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError({path, e.mark.is_null() ? 0 : e.mark.line + 1, ""}, "YAML syntax error: " + e.msg);
  }
  RequireYamlKeysOnce(root, path);
  return root;
}

}  // namespace ramtk
