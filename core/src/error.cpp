#include "ramtk/core/error.h"

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

InputError::InputError(InputLocation where, const std::string& message)
    : std::runtime_error(Compose(where, message)), where_(std::move(where)), message_(message) {}

}  // namespace ramtk
