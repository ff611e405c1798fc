#include "ramtk/core/error.h"

#include <cstdio>

namespace ramtk {

std::string FormatLocation(const InputLocation& where) {
  std::string out = where.file;
  if (!where.file.empty() && where.line > 0) out += ":" + std::to_string(where.line);
  if (!where.field.empty()) {
    if (!out.empty()) out += ": ";
    out += "field '" + where.field + "'";
  }
  return out;
}

static std::string Compose(const InputLocation& where, const std::string& message) {
  const std::string loc = FormatLocation(where);
  return loc.empty() ? message : loc + ": " + message;
}

std::string CheckNoise(const std::string& field, double value, double max, const char* unit) {
  if (value >= 0.0 && value <= max) return "";
  char text[160];
  std::snprintf(text, sizeof text, ": expected a noise sigma in [0, %g] %s, got %g", max, unit, value);
  return field + text;
}

OptionsProblem SplitOptionsProblem(const std::string& problem) {
  const std::size_t colon = problem.find(": ");
  if (colon == std::string::npos || colon == 0) return {"", problem};
  for (std::size_t i = 0; i < colon; ++i) {
    const char c = problem[i];
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '.' || c == '[' || c == ']';
    if (!ok) return {"", problem};
  }
  return {problem.substr(0, colon), problem.substr(colon + 2)};
}

void ThrowIfInvalid(const std::string& problem, const std::string& options_name) {
  if (problem.empty()) return;
  OptionsProblem p = SplitOptionsProblem(problem);
  throw InputError({"", 0, p.field.empty() ? options_name : p.field}, p.message);
}

InputError::InputError(InputLocation where, const std::string& message)
    : std::runtime_error(Compose(where, message)), where_(std::move(where)), message_(message) {}

}  // namespace ramtk
