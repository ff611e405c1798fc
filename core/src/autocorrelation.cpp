#include "ramtk/core/autocorrelation.h"

#include <algorithm>
#include <numeric>

namespace ramtk {

std::vector<double> Autocorrelation(const std::vector<double>& series, int max_lag) {
  const int n = static_cast<int>(series.size());
  std::vector<double> acf(std::max(0, max_lag) + 1, 0.0);
  if (n == 0) return acf;
  const double mean = std::accumulate(series.begin(), series.end(), 0.0) / n;
  double c0 = 0.0;
  for (double v : series) c0 += (v - mean) * (v - mean);
  if (c0 <= 0.0) return acf;
  for (int k = 0; k <= max_lag && k < n; ++k) {
    double ck = 0.0;
    for (int i = 0; i + k < n; ++i) ck += (series[i] - mean) * (series[i + k] - mean);
    acf[k] = ck / c0;
  }
  return acf;
}

}  // namespace ramtk
