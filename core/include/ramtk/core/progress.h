#pragma once
// Progress reporting for long work. Library code takes a ProgressCallback in its Options and
// calls it; it never draws a progress bar itself.

#include <cstddef>
#include <functional>
#include <string>

namespace ramtk {

struct Progress {
  std::string stage;      // what is being done, e.g. "decode"
  std::size_t done = 0;   // items finished
  std::size_t total = 0;  // items in all (0 if unknown)
};

// Returns false to ask the caller to stop early (cancellation); true to continue.
using ProgressCallback = std::function<bool(const Progress&)>;

}  // namespace ramtk
