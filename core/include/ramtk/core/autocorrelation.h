#pragma once
// The sample autocorrelation of a series, written once for the thermal screening's steadiness
// test and diagnose's Ljung–Box test.
#include <vector>

namespace ramtk {

// r_k = Σ_{i<n−k} (x_i − x̄)(x_{i+k} − x̄) / Σ (x_i − x̄)² for k = 0..max_lag (r_0 = 1). Lags at or
// beyond the series length, and every lag of a constant or empty series, are 0.
std::vector<double> Autocorrelation(const std::vector<double>& series, int max_lag);

}  // namespace ramtk
