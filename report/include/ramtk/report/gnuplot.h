// PNG figures through gnuplot (Debian package gnuplot-nox, pngcairo terminal): nice tick values,
// a legend outside the data, distinct colours and markers per series.
#pragma once

#include <string>

#include "ramtk/report/figure.h"

namespace ramtk::report {

struct PngOptions {
  int width = 1000;             // pixels
  int panel_height = 380;       // pixels per panel
  std::string font = "DejaVu Sans,11";
  // The gnuplot program; empty: $RAMTK_GNUPLOT, else `gnuplot` on PATH.
  std::string gnuplot;
};

// The gnuplot program that would be used, or "" when none can be run.
std::string FindGnuplot(const PngOptions& options = {});

// The gnuplot script that draws `figure` into `png_path` (data inline as datablocks).
std::string GnuplotScript(const Figure& figure, const std::string& png_path, const PngOptions& options = {});

// Writes the figure as a PNG, atomically. Throws std::runtime_error when gnuplot is missing or
// fails (its message included), std::invalid_argument for a figure CheckFigure refuses.
void WritePng(const Figure& figure, const std::string& png_path, const PngOptions& options = {});

}  // namespace ramtk::report
