#pragma once
// The one logging layer (spdlog underneath). Library code never prints; it calls Log(...).
// Applications install a sink for the terminal (the ramtk tool writes to stderr); with no sink
// installed, messages at or above the threshold go to stderr. A log file, when one is open,
// receives every message at debug and above as one time-stamped, levelled line.

#include <functional>
#include <sstream>
#include <string>

namespace ramtk {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

using LogSink = std::function<void(LogLevel, const std::string&)>;

// Installs `sink` (an empty function restores the default stderr sink). Thread-safe.
void SetLogSink(LogSink sink);
// Messages below `level` do not reach the sink (the log file has its own level, debug). Default:
// kInfo.
void SetLogThreshold(LogLevel level);
// The lowest level any destination takes: the sink's threshold, or kDebug while a log file is
// open. Messages below it are dropped before they are formatted.
LogLevel LogThreshold();
const char* LogLevelName(LogLevel level);

// Opens `path` for appending (created if missing) and from then on writes every message at debug
// and above into it as `2026-11-29T09:41:07.125Z warning: message`, flushed line by line. An
// empty path closes the file. Throws InputError naming the file when it cannot be opened.
void SetLogFile(const std::string& path);

void Log(LogLevel level, const std::string& message);
// Into the log file only (nothing when none is open): for lines the application has already
// drawn on the terminal itself, such as progress.
void LogToFile(LogLevel level, const std::string& message);

// Now in UTC as the log file stamps its lines: 2026-11-29T09:41:07.125Z.
std::string LogTimeStamp();

// Stream-style helper: RAMTK_LOG(kWarning) << "condition number " << c;
class LogLine {
 public:
  explicit LogLine(LogLevel level) : level_(level) {}
  ~LogLine() { Log(level_, stream_.str()); }
  template <typename T>
  LogLine& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};

}  // namespace ramtk

#define RAMTK_LOG(level)                                   \
  if (::ramtk::LogLevel::level < ::ramtk::LogThreshold()) \
    ;                                                      \
  else                                                     \
    ::ramtk::LogLine(::ramtk::LogLevel::level)
