// Figures as Plotly.js charts (the library is inlined into each HTML report; see html_report.h).
#pragma once

#include <string>
#include <vector>

#include "ramtk/report/figure.h"

namespace ramtk::report {

// One panel as a Plotly {"data": [...], "layout": {...}} object, JSON text.
std::string PlotlyPanelJson(const Panel& panel);

// A 3D view of points (x, y, z in mm, subsampled to at most max_points) with an optional sphere
// (radius > 0) drawn as a translucent surface; JSON text as PlotlyPanelJson.
struct Cloud3d {
  std::string title;
  std::vector<float> xyz;            // x0 y0 z0 x1 ... (mm)
  std::vector<float> colour_value;   // optional per point value (e.g. fit residual in µm), coloured
  std::string colour_label;          // its name and unit
  bool diverging = true;             // blue–red around 0 (residuals); false: a sequential scale (depth)
  double sphere_centre[3] = {0, 0, 0};
  double sphere_radius = 0.0;        // mm; 0: no sphere
  size_t max_points = 30000;
};
std::string PlotlyCloudJson(const Cloud3d& cloud);

// Where the Plotly.js bundle is read from: $RAMTK_PLOTLY_JS, else share/ramtk/plotly.min.js
// beside the running program's prefix, else the build tree's copy. "" when none exists.
std::string FindPlotlyJs();

}  // namespace ramtk::report
