#include "ramtk/report/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"

extern char** environ;

namespace ramtk::report {
namespace {

namespace fs = std::filesystem;

// A gnuplot single-quoted string: no escapes, '' stands for '.
std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out + "'";
}

std::string Number(double v) {
  if (!std::isfinite(v)) return "NaN";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

// Filled markers first, then open ones: circle, square, triangle up, diamond, triangle down.
int PointType(int k) {
  static const int kTypes[] = {7, 5, 9, 13, 11, 6, 4, 8, 12, 10};
  return kTypes[k % 10];
}

bool IsExecutable(const fs::path& p) { return !p.empty() && ::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p); }

}  // namespace

std::string FindGnuplot(const PngOptions& options) {
  std::string name = options.gnuplot;
  if (name.empty()) {
    const char* env = std::getenv("RAMTK_GNUPLOT");
    name = env && *env ? env : "gnuplot";
  }
  if (name.find('/') != std::string::npos) return IsExecutable(name) ? name : "";
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    if (IsExecutable(candidate)) return candidate.string();
  }
  return "";
}

std::string GnuplotScript(const Figure& figure, const std::string& png_path, const PngOptions& options) {
  CheckFigure(figure);
  const int n = static_cast<int>(figure.panels.size());
  const int title_px = figure.title.empty() ? 0 : 40;
  std::ostringstream g;
  g << "set encoding utf8\n";
  g << "set terminal pngcairo size " << options.width << "," << n * options.panel_height + title_px
    << " font " << Quote(options.font) << " noenhanced\n";
  g << "set output " << Quote(png_path) << "\n";
  g << "set termoption noenhanced\n";
  g << "set style fill transparent solid 0.22 noborder\n";
  g << "set grid lc rgb '#dddddd'\n";
  g << "set border lc rgb '#555555'\n";
  g << "set key outside right top vertical Left reverse samplen 2 spacing 1.2\n";
  g << "set format x '%g'\nset format y '%g'\n";
  // Room for the legend outside the data, the same in every panel: the longest label plus the
  // sample line (in character widths).
  size_t longest = 8;
  for (const Panel& p : figure.panels) {
    if (p.zero_band > 0) longest = std::max(longest, p.zero_band_label.size());
    for (const Series& s : p.series) longest = std::max(longest, s.label.size());
  }
  g << "set rmargin " << std::min<size_t>(longest + 8, 60) << "\n";
  if (n > 1 || !figure.title.empty()) {
    g << "set multiplot layout " << n << ",1";
    if (!figure.title.empty()) g << " title " << Quote(figure.title) << " font ',13'";
    g << "\n";
  }
  for (int p = 0; p < n; ++p) {
    const Panel& panel = figure.panels[p];
    // Data blocks first: gnuplot reads them before the plot command.
    double x_min = INFINITY, x_max = -INFINITY;
    for (size_t k = 0; k < panel.series.size(); ++k) {
      const Series& s = panel.series[k];
      g << "$P" << p << "S" << k << " << EOD\n";
      for (size_t i = 0; i < s.x.size(); ++i) {
        g << Number(s.x[i]) << ' ' << Number(s.y[i]);
        if (!s.y_low.empty()) g << ' ' << Number(s.y_low[i]) << ' ' << Number(s.y_high[i]);
        g << '\n';
        if (std::isfinite(s.x[i])) x_min = std::min(x_min, s.x[i]), x_max = std::max(x_max, s.x[i]);
      }
      g << "EOD\n";
    }
    const bool band = panel.zero_band > 0 && std::isfinite(x_min);
    if (band) {
      g << "$P" << p << "Z << EOD\n"
        << Number(x_min) << ' ' << Number(-panel.zero_band) << ' ' << Number(panel.zero_band) << '\n'
        << Number(x_max) << ' ' << Number(-panel.zero_band) << ' ' << Number(panel.zero_band) << "\nEOD\n";
    }
    g << "set title " << Quote(panel.title) << "\n";
    g << "set xlabel " << Quote(panel.x_label) << "\n";
    g << "set ylabel " << Quote(panel.y_label) << "\n";
    g << (panel.log_y ? "set logscale y\n" : "unset logscale y\n");
    std::vector<std::string> items;
    if (band)
      items.push_back("$P" + std::to_string(p) + "Z using 1:2:3 with filledcurves lc rgb '#999999' title " +
                      Quote(panel.zero_band_label));
    for (size_t k = 0; k < panel.series.size(); ++k) {
      const Series& s = panel.series[k];
      const std::string data = "$P" + std::to_string(p) + "S" + std::to_string(k);
      const std::string colour = std::string("lc rgb '") + SeriesColour(static_cast<int>(k)) + "'";
      if (!s.y_low.empty()) items.push_back(data + " using 1:3:4 with filledcurves " + colour + " notitle");
      std::string item = data + " using 1:2 ";
      switch (s.style) {
        case SeriesStyle::kPoints:
          item += "with points pt " + std::to_string(PointType(static_cast<int>(k))) + " ps 0.6 ";
          break;
        case SeriesStyle::kLines:
          item += "with lines lw 2 dt " + std::to_string(1 + static_cast<int>(k) % 5) + " ";
          break;
        case SeriesStyle::kLinesPoints:
          item += "with linespoints lw 2 pt " + std::to_string(PointType(static_cast<int>(k))) + " ps 0.8 dt " +
                  std::to_string(1 + static_cast<int>(k) % 5) + " ";
          break;
      }
      item += colour + (s.label.empty() ? " notitle" : " title " + Quote(s.label));
      items.push_back(item);
    }
    g << "plot ";
    for (size_t i = 0; i < items.size(); ++i) g << (i ? ", \\\n     " : "") << items[i];
    g << "\n";
  }
  if (n > 1 || !figure.title.empty()) g << "unset multiplot\n";
  g << "set output\n";
  return g.str();
}

void WritePng(const Figure& figure, const std::string& png_path, const PngOptions& options) {
  CheckFigure(figure);
  const std::string gnuplot = FindGnuplot(options);
  if (gnuplot.empty())
    throw std::runtime_error("cannot draw " + png_path +
                             ": gnuplot not found (install the Debian package gnuplot-nox or set RAMTK_GNUPLOT)");
  const std::string stem = png_path + ".tmp-" + std::to_string(::getpid());
  const std::string tmp_png = stem + ".png", script = stem + ".gp", errors = stem + ".err";
  for (const std::string& f : {tmp_png, script, errors}) RegisterTemporary(f);
  auto cleanup = [&] {
    std::error_code ec;
    for (const std::string& f : {tmp_png, script, errors}) fs::remove(f, ec), UnregisterTemporary(f);
  };
  try {
    WriteFileAtomically(script, GnuplotScript(figure, tmp_png, options));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> argv = {const_cast<char*>(gnuplot.c_str()), const_cast<char*>(script.c_str()), nullptr};
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, gnuplot.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) throw std::runtime_error("cannot start " + gnuplot + " to draw " + png_path);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    std::string message;
    try {
      message = ReadTextFile(errors);
    } catch (...) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(tmp_png) || fs::file_size(tmp_png) == 0) {
      if (message.size() > 600) message = message.substr(0, 600) + "...";
      throw std::runtime_error("gnuplot failed to draw " + png_path + (message.empty() ? "" : ": " + message));
    }
    fs::rename(tmp_png, png_path);
  } catch (...) {
    cleanup();
    throw;
  }
  cleanup();
}

}  // namespace ramtk::report
