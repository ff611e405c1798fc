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
// (RequireRegularFile), or if reading it takes longer than ReadDeadlineSeconds() (a stalled
// network file system, a file that never ends).
std::string ReadTextFile(const std::string& path);

// The time one ReadTextFile may take, in seconds: the environment variable RAMTK_READ_DEADLINE_S
// when it holds a positive number, else kDefaultReadDeadlineS; SetReadDeadline overrides both
// (a value <= 0 restores them). At most 10^7 s.
constexpr double kDefaultReadDeadlineS = 60.0;
double ReadDeadlineSeconds();
void SetReadDeadline(double seconds);
// Reads `fd` (which it takes over and closes) to its end on a helper thread; InputError naming
// `path` when the end is not reached within `deadline_s` seconds. The helper then stops at its
// next chunk (a read blocked in the kernel ends when the kernel lets it).
std::string ReadToEndWithDeadline(int fd, const std::string& path, double deadline_s);
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
