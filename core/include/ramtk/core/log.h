#pragma once
// The one logging layer. Library code never prints; it calls Log(...). Applications install a
// sink (the ramtk tool writes to stderr); with no sink installed, messages at or above the
// threshold go to stderr.

#include <functional>
#include <sstream>
#include <string>

namespace ramtk {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

using LogSink = std::function<void(LogLevel, const std::string&)>;

// Installs `sink` (an empty function restores the default stderr sink). Thread-safe.
void SetLogSink(LogSink sink);
// Messages below `level` are dropped before reaching the sink. Default: kInfo.
void SetLogThreshold(LogLevel level);
LogLevel LogThreshold();
const char* LogLevelName(LogLevel level);

void Log(LogLevel level, const std::string& message);

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
