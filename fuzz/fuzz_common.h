// Shared by the fuzz targets: an InputError is the expected answer to bad input; anything else
// (another exception, a crash, a sanitizer report, a hang) is a finding.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"

namespace ramtk::fuzz {
inline std::string Text(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }
inline void Quiet() {
  static bool once = [] {
    SetLogSink([](LogLevel, const std::string&) {});
    return true;
  }();
  (void)once;
}
}  // namespace ramtk::fuzz

#define RAMTK_FUZZ_BODY(expr)          \
  ramtk::fuzz::Quiet();                \
  try {                                \
    expr;                              \
  } catch (const ramtk::InputError&) { \
  }                                    \
  return 0
