#include "ramtk/report/figure.h"

#include <cmath>
#include <stdexcept>

namespace ramtk::report {

void CheckFigure(const Figure& figure) {
  if (figure.id.empty()) throw std::invalid_argument("figure without an id");
  for (char c : figure.id)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'))
      throw std::invalid_argument("figure id '" + figure.id + "': only letters, digits, '_' and '-' are allowed");
  if (figure.panels.empty()) throw std::invalid_argument("figure '" + figure.id + "' has no panel");
  bool any_finite = false;
  for (const Panel& p : figure.panels) {
    for (const Series& s : p.series) {
      if (s.x.size() != s.y.size())
        throw std::invalid_argument("figure '" + figure.id + "', series '" + s.label + "': " +
                                    std::to_string(s.x.size()) + " x values but " + std::to_string(s.y.size()) +
                                    " y values");
      if ((!s.y_low.empty() || !s.y_high.empty()) && (s.y_low.size() != s.x.size() || s.y_high.size() != s.x.size()))
        throw std::invalid_argument("figure '" + figure.id + "', series '" + s.label +
                                    "': the band needs as many low and high values as x values");
      for (size_t i = 0; i < s.x.size(); ++i) any_finite |= std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
    }
  }
  if (!any_finite) throw std::invalid_argument("figure '" + figure.id + "' has no finite point");
}

const char* SeriesColour(int k) {
  // Okabe & Ito (2008), without the yellow that vanishes on white.
  static const char* kPalette[] = {"#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7", "#56B4E9", "#000000"};
  constexpr int n = sizeof(kPalette) / sizeof(kPalette[0]);
  return kPalette[((k % n) + n) % n];
}

}  // namespace ramtk::report
