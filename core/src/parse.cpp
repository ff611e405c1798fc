#include "ramtk/core/parse.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ramtk {

double PrintedRoundingBound(const std::string& text) {
  const std::size_t e = text.find_first_of("eE");
  const std::string mantissa = text.substr(0, e);
  const int exponent = e == std::string::npos ? 0 : std::atoi(text.c_str() + e + 1);
  const std::size_t dot = mantissa.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
  return 0.5 * std::pow(10.0, exponent - decimals);
}

double ParseDouble(const std::string& text, const InputLocation& where) {
  const char* begin = text.c_str();
  while (*begin == ' ' || *begin == '\t') ++begin;
  if (*begin == '\0') throw InputError(where, "expected a number, got an empty value");
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  while (end && (*end == ' ' || *end == '\t' || *end == '\r')) ++end;
  if (end == begin || (end && *end != '\0')) {
    throw InputError(where, "expected a number, got '" + text + "'");
  }
  if (errno == ERANGE || !std::isfinite(value)) {
    throw InputError(where, "number out of range: '" + text + "'");
  }
  return value;
}

std::vector<double> ParseDoubleList(const std::string& text, const InputLocation& where,
                                    int expected_count) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  int index = 0;
  while (std::getline(ss, item, ',')) {
    InputLocation at = where;
    at.field += "[" + std::to_string(index++) + "]";
    values.push_back(ParseDouble(item, at));
  }
  if (!text.empty() && text.back() == ',') throw InputError(where, "trailing comma in '" + text + "'");
  if (expected_count > 0 && static_cast<int>(values.size()) != expected_count) {
    throw InputError(where, "expected " + std::to_string(expected_count) + " comma-separated values, got " +
                                std::to_string(values.size()) + " in '" + text + "'");
  }
  return values;
}

}  // namespace ramtk
