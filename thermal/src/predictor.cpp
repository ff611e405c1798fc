#include "ramtk/thermal/predictor.h"

#include <cstdio>

#include <Eigen/Cholesky>

#include "ramtk/core/error.h"

namespace ramtk::thermal {

std::string DriftPredictorOptions::Validate() const {
  if (window_every < 1) return "window_every must be >= 1";
  if (min_windows < 2) return "min_windows must be >= 2";
  if (!(ridge >= 0.0)) return "ridge must be >= 0";
  return "";
}

std::string DriftPredictionSummary::BriefReport() const {
  char buf[200];
  std::snprintf(buf, sizeof(buf), "drift prediction %s: %d windows, %d cycles predicted by the temperature model",
                termination.c_str(), windows, predicted_cycles);
  return buf;
}

DriftPrediction PredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                             const std::vector<int>& params, const DriftPredictorOptions& options,
                             DriftPredictionSummary* summary) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw InputError({"", 0, "DriftPredictorOptions"}, problem);
  const int cycles = static_cast<int>(identified.cols());
  if (temperatures.cols() != cycles) {
    throw InputError({"", 0, "temperatures"}, "temperature columns do not match the cycles");
  }
  const int j = static_cast<int>(temperatures.rows());
  DriftPrediction out;
  out.predicted = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.hold_last = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.is_window.assign(cycles, false);
  const Eigen::MatrixXd dt = temperatures.colwise() - temperatures.col(0);
  std::vector<int> windows;
  DriftPredictionSummary s;
  for (int c = 0; c < cycles; ++c) {
    const bool window = c % options.window_every == 0;
    out.is_window[c] = window;
    if (window) {
      windows.push_back(c);
      for (int p : params) {
        out.predicted(p, c) = identified(p, c);
        out.hold_last(p, c) = identified(p, c);
      }
      continue;
    }
    const int last = windows.back();
    for (int p : params) out.hold_last(p, c) = identified(p, last);
    if (static_cast<int>(windows.size()) < options.min_windows || j == 0) {
      out.predicted.col(c) = out.hold_last.col(c);
      continue;
    }
    // Ridge fit on the windows so far (causal).
    Eigen::MatrixXd t(j, windows.size());
    for (std::size_t w = 0; w < windows.size(); ++w) t.col(w) = dt.col(windows[w]);
    const double scale = t.squaredNorm() / std::max<Eigen::Index>(t.size(), 1);
    Eigen::MatrixXd normal = t * t.transpose();
    normal.diagonal().array() += options.ridge * scale * static_cast<double>(windows.size());
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(normal);
    for (int p : params) {
      Eigen::VectorXd y(windows.size());
      for (std::size_t w = 0; w < windows.size(); ++w) y[w] = identified(p, windows[w]);
      const Eigen::VectorXd b = ldlt.solve(t * y);
      out.predicted(p, c) = b.dot(dt.col(c));
    }
    ++s.predicted_cycles;
  }
  s.windows = static_cast<int>(windows.size());
  s.termination = "done";
  if (summary != nullptr) *summary = s;
  return out;
}

}  // namespace ramtk::thermal
