#pragma once
// The one progress display of the `ramtk` command (library code reports through a callback and
// never draws). On a terminal: one line redrawn in place with the rate and the time left. Into a
// pipe or a cluster log file: plain lines with a time stamp, at most one per stage every 10 s
// (and the stage's first and last), never a carriage return. The same plain lines go into the
// --log-file (ramtk/core/log.h), whose time stamps they share (LogTimeStamp).

#include <string>

#include "ramtk/core/progress.h"

namespace ramtk::tools {

// `unit` names what is counted ("sets", "folds"); stderr is the output.
ProgressCallback ProgressPrinter(const std::string& unit);

// The same decision for tests: the text one call would print (empty: nothing), given whether the
// output is a terminal and the seconds since the stage began and since the last line.
std::string ProgressLine(const Progress& p, const std::string& unit, bool terminal, double elapsed_s,
                         double since_last_s);

}  // namespace ramtk::tools
