#pragma once
// Drift prediction between measurement windows (beyond the thesis).
//
// In production the ball is measured only in windows (every W cycles). Between windows the
// compensator either holds the last identified ΔX (hold-last) or predicts it. The predictor here
// is a temperature-driven linear model, fitted causally on the windows seen so far:
//   ΔX_p(t) ≈ b_p · [ΔT_1(t) … ΔT_J(t)]ᵀ    (ΔT = joint temperatures minus the cold reference's)
// solved per parameter by ridge regression (the joint temperatures are strongly collinear).
// Until `min_windows` windows are available it holds the last value.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace ramtk::thermal {

struct DriftPredictorOptions {
  int window_every = 10;    // a ball window every this many cycles (cycle 0 is always one)
  int min_windows = 4;      // windows (incl. cycle 0) before the model is used instead of hold-last
  double ridge = 1e-2;      // ridge weight relative to the mean squared temperature rise, per regressor
  std::string Validate() const;
};

struct DriftPredictionSummary {
  std::string termination = "not run";
  int windows = 0;                  // windows used in all
  int predicted_cycles = 0;         // cycles between windows that the model predicted
  std::string BriefReport() const;
};

struct DriftPrediction {
  Eigen::MatrixXd predicted;  // 30 × cycles: windows carry the identified value, others the prediction
  Eigen::MatrixXd hold_last;  // 30 × cycles: the last window's identified value
  std::vector<bool> is_window;
};

// `identified` 30 × cycles (only window columns are read), `temperatures` J × cycles (°C),
// `params` the rows to predict (others stay zero).
DriftPrediction PredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                             const std::vector<int>& params, const DriftPredictorOptions& options = {},
                             DriftPredictionSummary* summary = nullptr);

}  // namespace ramtk::thermal
