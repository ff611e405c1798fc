#include "ramtk/diagnose/engine/plot.h"

#include <atomic>
#include <filesystem>

#include "ramtk/core/log.h"
#include "ramtk/report/gnuplot.h"

namespace ramtk::diagnose {

void AddFigure(const report::Figure& figure, const std::string& folder, std::vector<Picture>* pictures) {
  Picture p;
  p.caption = figure.caption;
  p.figure = figure;
  if (!report::FindGnuplot().empty()) {
    std::filesystem::create_directories(folder);
    report::WritePng(figure, (std::filesystem::path(folder) / (figure.id + ".png")).string());
    p.file = figure.id + ".png";
  } else {
    static std::atomic<bool> warned{false};
    if (!warned.exchange(true))
      Log(LogLevel::kWarning,
          "gnuplot not found: PNG pictures are skipped (install gnuplot-nox); the HTML report still has them");
  }
  pictures->push_back(std::move(p));
}

report::Figure OnePanel(const std::string& id, const std::string& caption, const std::string& title,
                        const std::string& x_label, const std::string& y_label, std::vector<report::Series> series,
                        double zero_band) {
  report::Figure f;
  f.id = id;
  f.caption = caption;
  report::Panel p;
  p.title = title, p.x_label = x_label, p.y_label = y_label, p.series = std::move(series), p.zero_band = zero_band;
  f.panels.push_back(std::move(p));
  return f;
}

}  // namespace ramtk::diagnose
