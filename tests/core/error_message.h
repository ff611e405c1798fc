#pragma once
// The message of the InputError `f` throws, or "no error": tests compare it with the exact text a
// user sees.
#include <functional>
#include <string>

#include "ramtk/core/error.h"

namespace ramtk::testing {

inline std::string Message(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace ramtk::testing
