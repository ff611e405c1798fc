// Pictures of a diagnosis. Each is a report::Figure: written as `<id>.png` through gnuplot
// (report/gnuplot.h) and kept in the Diagnosis, so the HTML report draws it interactively.
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"
#include "ramtk/report/figure.h"

namespace ramtk::diagnose {

// Writes `<folder>/<figure.id>.png` and appends the picture (file, figure.caption, figure). When
// gnuplot is missing the PNG is skipped with one logged warning and the picture keeps only the
// figure (file empty): the HTML report still draws it.
void AddFigure(const report::Figure& figure, const std::string& folder, std::vector<Picture>* pictures);

// A one-panel figure: the common case.
report::Figure OnePanel(const std::string& id, const std::string& caption, const std::string& title,
                        const std::string& x_label, const std::string& y_label, std::vector<report::Series> series,
                        double zero_band = 0.0);

}  // namespace ramtk::diagnose
