#include "ramtk/core/log.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iostream>
#include <memory>
#include <mutex>

#include "ramtk/core/error.h"

namespace ramtk {
namespace {

// The log file's line: UTC time stamp with milliseconds (LogTimeStamp's form), level, message.
constexpr const char* kFilePattern = "%Y-%m-%dT%H:%M:%S.%eZ %l: %v";

spdlog::level::level_enum ToSpd(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return spdlog::level::debug;
    case LogLevel::kInfo:
      return spdlog::level::info;
    case LogLevel::kWarning:
      return spdlog::level::warn;
    case LogLevel::kError:
      return spdlog::level::err;
  }
  return spdlog::level::err;
}

LogLevel FromSpd(spdlog::level::level_enum level) {
  if (level <= spdlog::level::debug) return LogLevel::kDebug;
  if (level == spdlog::level::info) return LogLevel::kInfo;
  if (level == spdlog::level::warn) return LogLevel::kWarning;
  return LogLevel::kError;
}

// The terminal destination: the application's LogSink, or stderr when it installed none.
class FunctionSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  void Set(LogSink fn) {
    std::lock_guard<std::mutex> lock(mutex_);
    sink_ = std::move(fn);
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    const std::string text(msg.payload.data(), msg.payload.size());
    const LogLevel level = FromSpd(msg.level);
    if (sink_) {
      sink_(level, text);
    } else {
      std::cerr << "[ramtk " << LogLevelName(level) << "] " << text << '\n';
    }
  }
  void flush_() override {}

 private:
  LogSink sink_;
};

struct Logging {
  std::shared_ptr<FunctionSink> terminal = std::make_shared<FunctionSink>();
  std::shared_ptr<spdlog::logger> logger = std::make_shared<spdlog::logger>("ramtk", terminal);
  std::shared_ptr<spdlog::logger> file_only;  // the file sink alone, while a file is open
  std::mutex file_mutex;                      // SetLogFile against itself and LogToFile
  std::atomic<int> threshold{static_cast<int>(LogLevel::kInfo)};
  std::atomic<bool> file_open{false};

  Logging() {
    terminal->set_level(ToSpd(LogLevel::kInfo));
    logger->set_level(spdlog::level::debug);
    logger->flush_on(spdlog::level::debug);
  }
};

Logging& State() {
  static Logging state;
  return state;
}

}  // namespace

void SetLogSink(LogSink sink) { State().terminal->Set(std::move(sink)); }

void SetLogThreshold(LogLevel level) {
  State().threshold = static_cast<int>(level);
  State().terminal->set_level(ToSpd(level));
}

LogLevel LogThreshold() {
  if (State().file_open.load()) return LogLevel::kDebug;
  return static_cast<LogLevel>(State().threshold.load());
}

const char* LogLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "?";
}

void SetLogFile(const std::string& path) {
  Logging& s = State();
  std::lock_guard<std::mutex> lock(s.file_mutex);
  std::shared_ptr<spdlog::sinks::basic_file_sink_mt> file;
  if (!path.empty()) {
    // spdlog would create missing folders; a mistyped path is refused instead.
    std::FILE* probe = std::fopen(path.c_str(), "ab");
    if (probe == nullptr) {
      throw InputError({path, 0, "--log-file"}, std::string("cannot open the log file: ") + std::strerror(errno));
    }
    std::fclose(probe);
    try {
      file = std::make_shared<spdlog::sinks::basic_file_sink_mt>(path, false);
    } catch (const spdlog::spdlog_ex& e) {
      throw InputError({path, 0, "--log-file"}, std::string("cannot open the log file: ") + e.what());
    }
    file->set_formatter(
        std::make_unique<spdlog::pattern_formatter>(kFilePattern, spdlog::pattern_time_type::utc, "\n"));
    file->set_level(spdlog::level::debug);
  }
  auto logger = std::make_shared<spdlog::logger>("ramtk", s.terminal);
  if (file) logger->sinks().push_back(file);
  logger->set_level(spdlog::level::debug);
  logger->flush_on(spdlog::level::debug);
  std::atomic_store(&s.logger, logger);
  s.file_only = file ? std::make_shared<spdlog::logger>("ramtk-file", file) : nullptr;
  if (s.file_only) s.file_only->set_level(spdlog::level::debug);
  if (s.file_only) s.file_only->flush_on(spdlog::level::debug);
  s.file_open = static_cast<bool>(file);
}

void Log(LogLevel level, const std::string& message) {
  if (level < LogThreshold()) return;
  std::atomic_load(&State().logger)->log(ToSpd(level), message);
}

void LogToFile(LogLevel level, const std::string& message) {
  Logging& s = State();
  if (!s.file_open.load()) return;
  std::lock_guard<std::mutex> lock(s.file_mutex);
  if (s.file_only) s.file_only->log(ToSpd(level), message);
}

std::string LogTimeStamp() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[40];
  const size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  std::snprintf(text + n, sizeof text - n, ".%03dZ", static_cast<int>(ms));
  return text;
}

}  // namespace ramtk
