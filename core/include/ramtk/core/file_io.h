#pragma once
// File helpers. Outputs are written to a temporary file beside the target and renamed into
// place, so a failure never leaves a half-written output.

#include <string>

namespace ramtk {

// Reads a whole file; InputError naming the file if it cannot be read.
std::string ReadTextFile(const std::string& path);
// Writes `contents` to `path` atomically (temporary file + rename); InputError on failure.
void WriteFileAtomically(const std::string& path, const std::string& contents);

}  // namespace ramtk
