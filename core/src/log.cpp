#include "ramtk/core/log.h"

#include <atomic>
#include <iostream>
#include <mutex>

namespace ramtk {
namespace {
std::mutex g_mutex;
LogSink g_sink;
std::atomic<int> g_threshold{static_cast<int>(LogLevel::kInfo)};
}  // namespace

void SetLogSink(LogSink sink) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_sink = std::move(sink);
}

void SetLogThreshold(LogLevel level) { g_threshold = static_cast<int>(level); }

LogLevel LogThreshold() { return static_cast<LogLevel>(g_threshold.load()); }

const char* LogLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kInfo: return "info";
    case LogLevel::kWarning: return "warning";
    case LogLevel::kError: return "error";
  }
  return "?";
}

void Log(LogLevel level, const std::string& message) {
  if (static_cast<int>(level) < g_threshold.load()) return;
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_sink) {
    g_sink(level, message);
  } else {
    std::cerr << "[ramtk " << LogLevelName(level) << "] " << message << '\n';
  }
}

}  // namespace ramtk
