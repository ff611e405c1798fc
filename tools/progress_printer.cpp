#include "progress_printer.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "ramtk/core/log.h"

namespace ramtk::tools {
namespace {

std::string Duration(double s) {
  char text[32];
  if (s < 60) {
    std::snprintf(text, sizeof text, "%.0f s", s);
  } else if (s < 3600) {
    std::snprintf(text, sizeof text, "%d min %02d s", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  } else {
    std::snprintf(text, sizeof text, "%d h %02d min", static_cast<int>(s) / 3600, (static_cast<int>(s) % 3600) / 60);
  }
  return text;
}

}  // namespace

std::string ProgressLine(const Progress& p, const std::string& unit, bool terminal, double elapsed_s,
                         double since_last_s) {
  const bool last = p.total > 0 && p.done >= p.total;
  const bool first = p.done == 0;
  if (!terminal && !first && !last && since_last_s < 10.0) return "";
  char text[256];
  std::string rate;
  if (p.done > 0 && elapsed_s > 0) {
    const double per_s = static_cast<double>(p.done) / elapsed_s;
    char r[96];
    if (p.total > p.done) {
      std::snprintf(r, sizeof r, ", %.3g %s/s, %s left", per_s, unit.c_str(),
                    Duration(static_cast<double>(p.total - p.done) / per_s).c_str());
    } else {
      std::snprintf(r, sizeof r, ", %.3g %s/s, %s", per_s, unit.c_str(), Duration(elapsed_s).c_str());
    }
    rate = r;
  }
  if (p.total > 0) {
    std::snprintf(text, sizeof text, "%s %zu/%zu %s (%.0f%%)%s", p.stage.c_str(), p.done, p.total, unit.c_str(),
                  100.0 * static_cast<double>(p.done) / static_cast<double>(p.total), rate.c_str());
  } else {
    std::snprintf(text, sizeof text, "%s %zu %s%s", p.stage.c_str(), p.done, unit.c_str(), rate.c_str());
  }
  if (terminal) return std::string("\r") + text + "\033[K" + (last ? "\n" : "");
  return text + std::string("\n");
}

ProgressCallback ProgressPrinter(const std::string& unit) {
  struct State {
    std::string stage;
    std::chrono::steady_clock::time_point start, last_line, last_file_line;
  };
  auto state = std::make_shared<State>();
  const bool terminal = isatty(STDERR_FILENO) == 1;
  return [state, unit, terminal](const Progress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (p.stage != state->stage) {
      state->stage = p.stage;
      state->start = now;
      state->last_line = now - std::chrono::hours(1);
      state->last_file_line = state->last_line;
    }
    const double elapsed = std::chrono::duration<double>(now - state->start).count();
    const double since = std::chrono::duration<double>(now - state->last_line).count();
    const std::string line = ProgressLine(p, unit, terminal, elapsed, since);
    if (!line.empty()) {
      if (terminal) {
        std::fputs(line.c_str(), stderr);
      } else {
        std::fprintf(stderr, "%s %s", LogTimeStamp().c_str(), line.c_str());
      }
      std::fflush(stderr);
      state->last_line = now;
    }
    // The log file (--log-file) gets the lines a pipe would get, stamped as its other lines.
    const double since_file = std::chrono::duration<double>(now - state->last_file_line).count();
    const std::string plain = ProgressLine(p, unit, false, elapsed, since_file);
    if (!plain.empty()) {
      LogToFile(LogLevel::kInfo, "progress: " + plain.substr(0, plain.size() - 1));
      state->last_file_line = now;
    }
    return true;
  };
}

}  // namespace ramtk::tools
