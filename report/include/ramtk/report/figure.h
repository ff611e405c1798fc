// A figure described once and drawn twice: as a PNG through gnuplot (gnuplot.h) and as an
// interactive Plotly chart in an HTML report (html_report.h). A figure is a column of panels;
// each panel has one unit per axis, so lengths and angles never share an axis.
#pragma once

#include <string>
#include <vector>

namespace ramtk::report {

enum class SeriesStyle {
  kPoints,  // markers only (residual scatter)
  kLines,   // a line through the points in the order given
  kLinesPoints,
};

struct Series {
  std::string label;  // legend text; empty: no legend entry
  std::vector<double> x, y;
  SeriesStyle style = SeriesStyle::kPoints;
  // Optional uncertainty band around y (same length as x when given): drawn as a shaded band of
  // the series' colour between y_low and y_high.
  std::vector<double> y_low, y_high;
};

struct Panel {
  std::string title;
  std::string x_label;  // with its unit, e.g. "time (h)"
  std::string y_label;  // with its unit, e.g. "residual (mm)"
  std::vector<Series> series;
  // A grey band ±zero_band around y = 0 (the expected noise, for example); 0: none.
  double zero_band = 0.0;
  std::string zero_band_label = "expected noise";
  bool log_y = false;
};

struct Figure {
  std::string id;       // element id in HTML and the PNG file stem: [A-Za-z0-9_-]+
  std::string title;    // above all panels (may be empty)
  std::string caption;  // one sentence under the figure
  std::vector<Panel> panels;
};

// Throws std::invalid_argument when the figure cannot be drawn: bad id, no panel, a series whose
// x and y (or band) lengths differ, or no finite point at all.
void CheckFigure(const Figure& figure);

// The colour of series k (Okabe–Ito palette, safe for colour-blind readers), as "#RRGGBB".
const char* SeriesColour(int k);

}  // namespace ramtk::report
