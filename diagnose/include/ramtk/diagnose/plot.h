// Residual pictures: scatter plots of a residual against an explaining variable, written as PNG
// (OpenCV drawing; no plotting library needed on the machine).
#pragma once

#include <string>
#include <vector>

namespace ramtk::diagnose {

struct PlotSeries {
  std::vector<double> x, y;
  std::string label;  // legend text (empty: no legend entry)
  unsigned char rgb[3] = {31, 119, 180};
  bool line = false;  // connect the points (sorted by x) instead of dots
};

struct PlotOptions {
  std::string title, x_label, y_label;
  int width = 900, height = 520;  // pixels
  // Horizontal band ±band drawn around zero (e.g. the expected noise, 0 = none).
  double band = 0.0;
};

// Writes a PNG scatter/line plot atomically. Throws on an empty plot or a failed write.
void WritePlot(const std::vector<PlotSeries>& series, const PlotOptions& options, const std::string& png_path);

}  // namespace ramtk::diagnose
