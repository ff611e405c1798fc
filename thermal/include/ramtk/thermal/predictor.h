#pragma once
// Drift prediction between measurement windows (beyond the thesis).
//
// In production the ball is measured only in windows (every W cycles). Between windows the
// compensator either holds the last identified ΔX (hold-last) or predicts it from the joint
// temperatures the controller logs every cycle, with a linear model
//   ΔX_p(t) ≈ Σ_j b_pj · F_j(t),   F_j = first-order low-pass (time constant lag_s) of ΔT_j,
// ΔT_j = temperature of joint j minus its value in the cold reference cycle. The low-pass stands
// for the structure lagging the housing sensor; lag_s is chosen from candidates by the fit.
//
// Two ways to get b:
//  * offline: fit it on a long characterisation run identified every cycle (the screening run of
//    §5.1), then in production add the mean offset of the windows seen so far;
//  * online: refit it by ridge regression on the windows seen so far (causal).
// Until `min_windows` windows are available the online predictor holds the last value.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/core/termination.h"
#include "ramtk/thermal/cycles.h"
#include "ramtk/thermal/monitoring.h"

namespace ramtk::thermal {

struct TemperatureModelOptions {
  double ridge = 1e-3;  // ridge weight relative to the mean squared regressor, per regressor
  std::vector<double> lag_candidates_s = {0.0, 300.0, 600.0, 900.0, 1200.0, 1800.0};  // low-pass τ tried
  std::string Validate() const;
};

struct TemperatureDriftModel {
  std::vector<int> params;       // rows predicted
  double lag_s = 0.0;            // chosen low-pass time constant
  Eigen::MatrixXd coefficients;  // 30 × J (rows outside params are zero); mm/K or rad/K
  double training_rms = 0.0;     // RMS fit residual over params and cycles (mixed units: a ranking aid)
};

// Low-pass filtered temperature rises F (J × N) for temperatures (J × N, °C) at `times_s` (N).
Eigen::MatrixXd FilteredTemperatureRise(const Eigen::MatrixXd& temperatures, const std::vector<double>& times_s,
                                        double lag_s);

// Fits b on the columns `use` (all if empty) of `identified` (30 × N). InputError on bad sizes.
TemperatureDriftModel FitTemperatureModel(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                                          const std::vector<double>& times_s, const std::vector<int>& params,
                                          const TemperatureModelOptions& options = {},
                                          const std::vector<int>& use = {});

struct DriftPredictorOptions {
  int window_every = 10;  // a ball window every this many cycles (cycle 0 is always one)
  int min_windows = 4;    // online: windows (incl. cycle 0) before the model replaces hold-last
  TemperatureModelOptions model;
  std::string Validate() const;
};

struct DriftPredictionSummary {
  Termination termination = Termination::kNotRun;
  std::string message = "not run";  // "offline model" or "online model"
  int windows = 0;                  // windows used in all
  int predicted_cycles = 0;         // cycles between windows predicted by a model (not held)
  double lag_s = 0.0;               // low-pass time constant of the (last) model
  std::string BriefReport() const;
};

struct DriftPrediction {
  Eigen::MatrixXd predicted;  // 30 × cycles: windows carry the identified value, others the prediction
  Eigen::MatrixXd hold_last;  // 30 × cycles: the last window's identified value
  std::vector<bool> is_window;
};

// `identified` 30 × cycles (only window columns are read), `temperatures` J × cycles (°C, every
// cycle), `times_s` per cycle. With `offline` the model is not refitted: its prediction plus the
// windows' mean offset is used. Otherwise the online fit.
DriftPrediction PredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                             const std::vector<double>& times_s, const std::vector<int>& params,
                             const DriftPredictorOptions& options = {}, const TemperatureDriftModel* offline = nullptr,
                             DriftPredictionSummary* summary = nullptr);

// Kalman filter over the identified parameters (params only). State x = ΔX_params; between cycles
//   x ← x + B·(F_c − F_{c−1})      (B from `model`; without a model a random walk),
//   P ← P + ratio_per_hour · (Δt / 3600 s) · R,
// and at each window the identification z (covariance R) updates it. Cycle 0 starts at the
// first window's value with covariance R.
struct KalmanDriftOptions {
  int window_every = 10;
  // Process noise per hour as a multiple of the window covariance R (how fast the model's error
  // can wander between windows).
  double process_ratio_per_hour = 0.5;
  std::string Validate() const;
};

DriftPrediction KalmanPredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& window_covariance,
                                   const Eigen::MatrixXd& temperatures, const std::vector<double>& times_s,
                                   const std::vector<int>& params, const KalmanDriftOptions& options = {},
                                   const TemperatureDriftModel* model = nullptr);

// Joint temperatures (kNumJoints × columns.size(), °C, from the extra columns temp_j1..temp_j6 of
// each cycle) and the cycle times of the cycles `columns` of a series. InputError naming the file
// and the missing column otherwise.
void CycleTemperatures(const CycleSeries& series, const std::vector<int>& columns, Eigen::MatrixXd* temperatures,
                       std::vector<double>* times_s);

// A prediction scored on the monitoring points of the cycles between windows: RMS 3-D error of
// the prediction and of hold-last against `reference` (30 × cycles, e.g. the every-cycle
// identification; it carries that identification's own noise).
struct PredictionScore {
  double predicted_rms_mm = 0.0;
  double hold_last_rms_mm = 0.0;
  int samples = 0;  // monitoring points × scored cycles
};
PredictionScore ScorePredictionOnMonitoring(const MonitoringModel& monitoring, const DriftPrediction& prediction,
                                            const Eigen::MatrixXd& reference);

}  // namespace ramtk::thermal
