// Tests of a residual against its expected noise: is it white at the expected level, or does it
// have structure? All p-values are for the null hypothesis "independent zero-mean noise of the
// stated standard deviation".
#pragma once

#include <string>
#include <vector>

#include "ramtk/core/autocorrelation.h"

namespace ramtk::diagnose {

struct TestResult {
  std::string name;              // e.g. "variance", "ljung_box(time)", "trend(q2)"
  double statistic = 0;          // the test statistic
  double dof = 0;                // its degrees of freedom (when chi-square)
  double p_value = 1;            // probability of a statistic at least this extreme under the null
  std::string Describe() const;  // one line for reports
};

// Chi-square test of Σ(r/σ)² against n degrees of freedom (one-sided: residual larger than noise).
// `sigma` is per residual (same length) or a single value.
TestResult VarianceTest(const std::vector<double>& residuals, const std::vector<double>& sigma);

// Ljung–Box test on the residual ordered by a variable (time, cycle, phase...): serial correlation
// up to `max_lag` (0 = min(20, n/5)). The series must already be sorted by that variable.
TestResult LjungBoxTest(const std::vector<double>& ordered_residuals, int max_lag, const std::string& name);

// Does a low-order model in `variable` explain the residual? F-test of a polynomial of the given
// degree (plus constant) against the noise-only model, with the known noise sigma (a chi-square test
// of the explained sum of squares).
TestResult TrendTest(const std::vector<double>& residuals, const std::vector<double>& sigma,
                     const std::vector<double>& variable, int degree, const std::string& name);

// The same test for an angle (rad): sin/cos of k·angle for k = 1..harmonics (2·harmonics dof), the
// natural low-order model of anything periodic in a joint angle.
TestResult HarmonicTrendTest(const std::vector<double>& residuals, const std::vector<double>& sigma,
                             const std::vector<double>& angle_rad, int harmonics, const std::string& name);

// Holm–Bonferroni family-wise correction; returns corrected p-values in the input order.
std::vector<double> HolmCorrection(const std::vector<double>& p_values);

// Distribution helpers.
double ChiSquareUpperTail(double statistic, double dof);  // P(X ≥ statistic)
double NormalUpperTail(double z);                         // P(Z ≥ z)

// The sample autocorrelation (core/autocorrelation.h).
using ramtk::Autocorrelation;

}  // namespace ramtk::diagnose
