#pragma once
// File helpers. Outputs are written to a temporary file beside the target and renamed into
// place, so a failure never leaves a half-written output.

#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace ramtk {

// InputError naming the file unless `path` (after following symbolic links) is an existing
// regular file: a folder, a FIFO, a socket or a device (/dev/zero, /dev/urandom, a terminal) is
// refused before it is opened, since reading one may block forever or never end. Every reader of
// input files calls it first.
void RequireRegularFile(const std::string& path);
// Reads a whole file; InputError naming the file if it cannot be read or is not a regular file
// (RequireRegularFile).
std::string ReadTextFile(const std::string& path);
// Writes `contents` to `path` atomically (temporary file + rename); InputError on failure.
void WriteFileAtomically(const std::string& path, const std::string& contents);
// The same with the contents streamed by `write` (large outputs need no copy in memory); an
// exception from `write` removes the temporary and propagates.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);
// Writes several files as one unit: every temporary is written first and the renames happen
// only when all of them succeeded, so a failure (or an interruption, which removes the
// registered temporaries) leaves none of the new files. The paths must be distinct.
void WriteFilesAtomically(const std::vector<std::pair<std::string, std::string>>& path_and_contents);

}  // namespace ramtk
