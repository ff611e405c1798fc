#include "ramtk/thermal/predictor.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

#include "ramtk/core/error.h"

namespace ramtk::thermal {

std::string TemperatureModelOptions::Validate() const {
  if (!(ridge >= 0.0)) return "ridge must be >= 0";
  if (lag_candidates_s.empty()) return "lag_candidates_s needs at least one value";
  for (double l : lag_candidates_s) {
    if (!(l >= 0.0)) return "lag candidates must be >= 0";
  }
  return "";
}

std::string DriftPredictorOptions::Validate() const {
  if (window_every < 1) return "window_every must be >= 1";
  if (min_windows < 2) return "min_windows must be >= 2";
  return model.Validate();
}

std::string DriftPredictionSummary::BriefReport() const {
  char buf[240];
  std::snprintf(buf, sizeof(buf),
                "drift prediction %s: %d windows, %d cycles predicted by the temperature model (lag %.0f s)",
                message.c_str(), windows, predicted_cycles, lag_s);
  return buf;
}

Eigen::MatrixXd FilteredTemperatureRise(const Eigen::MatrixXd& temperatures, const std::vector<double>& times_s,
                                        double lag_s) {
  const Eigen::Index n = temperatures.cols();
  if (static_cast<Eigen::Index>(times_s.size()) != n) {
    throw InputError({"", 0, "times_s"}, "temperature columns and times differ in number");
  }
  Eigen::MatrixXd f(temperatures.rows(), n);
  if (n == 0) return f;
  const Eigen::VectorXd cold = temperatures.col(0);
  f.col(0).setZero();
  for (Eigen::Index c = 1; c < n; ++c) {
    const Eigen::VectorXd rise = temperatures.col(c) - cold;
    if (lag_s <= 0.0) {
      f.col(c) = rise;
    } else {
      const double w = 1.0 - std::exp(-(times_s[c] - times_s[c - 1]) / lag_s);
      f.col(c) = f.col(c - 1) + w * (rise - f.col(c - 1));
    }
  }
  return f;
}

namespace {

// Ridge solution b (params × J) of identified(params, use) ≈ b · f(:, use).
Eigen::MatrixXd RidgeFit(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& f, const std::vector<int>& params,
                         const std::vector<int>& use, double ridge, double* rms) {
  const int j = static_cast<int>(f.rows());
  Eigen::MatrixXd t(j, use.size());
  Eigen::MatrixXd y(params.size(), use.size());
  for (std::size_t u = 0; u < use.size(); ++u) {
    t.col(u) = f.col(use[u]);
    for (std::size_t p = 0; p < params.size(); ++p) y(p, u) = identified(params[p], use[u]);
  }
  const double scale = t.size() > 0 ? t.squaredNorm() / static_cast<double>(t.size()) : 0.0;
  Eigen::MatrixXd normal = t * t.transpose();
  normal.diagonal().array() += ridge * std::max(scale, 1e-12) * static_cast<double>(use.size());
  const Eigen::MatrixXd b = Eigen::LDLT<Eigen::MatrixXd>(normal).solve(t * y.transpose()).transpose();
  if (rms != nullptr) {
    const Eigen::MatrixXd r = y - b * t;
    *rms = r.size() > 0 ? std::sqrt(r.squaredNorm() / static_cast<double>(r.size())) : 0.0;
  }
  return b;
}

}  // namespace

TemperatureDriftModel FitTemperatureModel(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                                          const std::vector<double>& times_s, const std::vector<int>& params,
                                          const TemperatureModelOptions& options, const std::vector<int>& use) {
  ThrowIfInvalid(options.Validate(), "TemperatureModelOptions");
  if (identified.cols() != temperatures.cols()) {
    throw InputError({"", 0, "temperatures"}, "temperature columns do not match the identified cycles");
  }
  std::vector<int> cols = use;
  if (cols.empty()) {
    for (int c = 0; c < identified.cols(); ++c) cols.push_back(c);
  }
  TemperatureDriftModel best;
  best.params = params;
  best.training_rms = -1.0;
  for (double lag : options.lag_candidates_s) {
    // Scale-free ranking: residuals of each parameter relative to its own spread.
    Eigen::MatrixXd scaled = identified;
    for (int p : params) {
      double s = 0.0;
      for (int c : cols) s += identified(p, c) * identified(p, c);
      if (s > 0.0) scaled.row(p) /= std::sqrt(s);
    }
    const Eigen::MatrixXd f = FilteredTemperatureRise(temperatures, times_s, lag);
    double rms = 0.0;
    RidgeFit(scaled, f, params, cols, options.ridge, &rms);
    if (best.training_rms < 0.0 || rms < best.training_rms) {
      best.training_rms = rms;
      best.lag_s = lag;
    }
  }
  const Eigen::MatrixXd f = FilteredTemperatureRise(temperatures, times_s, best.lag_s);
  const Eigen::MatrixXd b = RidgeFit(identified, f, params, cols, options.ridge, nullptr);
  best.coefficients = Eigen::MatrixXd::Zero(identified.rows(), temperatures.rows());
  for (std::size_t p = 0; p < params.size(); ++p) best.coefficients.row(params[p]) = b.row(p);
  return best;
}

DriftPrediction PredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& temperatures,
                             const std::vector<double>& times_s, const std::vector<int>& params,
                             const DriftPredictorOptions& options, const TemperatureDriftModel* offline,
                             DriftPredictionSummary* summary) {
  ThrowIfInvalid(options.Validate(), "DriftPredictorOptions");
  const int cycles = static_cast<int>(identified.cols());
  if (temperatures.cols() != cycles || static_cast<int>(times_s.size()) != cycles) {
    throw InputError({"", 0, "temperatures"}, "temperature columns or times do not match the cycles");
  }
  if (offline != nullptr && offline->coefficients.cols() != temperatures.rows()) {
    throw InputError({"", 0, "model"}, "the offline model was fitted on a different number of temperatures");
  }
  DriftPrediction out;
  out.predicted = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.hold_last = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.is_window.assign(cycles, false);
  DriftPredictionSummary s;
  Eigen::MatrixXd f_offline;
  if (offline != nullptr) {
    f_offline = FilteredTemperatureRise(temperatures, times_s, offline->lag_s);
    s.lag_s = offline->lag_s;
  }
  std::vector<int> windows;
  Eigen::VectorXd offset_sum = Eigen::VectorXd::Zero(identified.rows());
  TemperatureModelOptions online_options = options.model;
  for (int c = 0; c < cycles; ++c) {
    const bool window = c % options.window_every == 0;
    out.is_window[c] = window;
    if (window) {
      windows.push_back(c);
      for (int p : params) {
        out.predicted(p, c) = identified(p, c);
        out.hold_last(p, c) = identified(p, c);
      }
      if (offline != nullptr) {
        const Eigen::VectorXd model_value = offline->coefficients * f_offline.col(c);
        for (int p : params) offset_sum[p] += identified(p, c) - model_value[p];
      }
      continue;
    }
    const int last = windows.back();
    for (int p : params) out.hold_last(p, c) = identified(p, last);
    if (offline != nullptr) {
      const Eigen::VectorXd model_value = offline->coefficients * f_offline.col(c);
      for (int p : params) out.predicted(p, c) = model_value[p] + offset_sum[p] / static_cast<double>(windows.size());
      ++s.predicted_cycles;
      continue;
    }
    if (static_cast<int>(windows.size()) < options.min_windows) {
      out.predicted.col(c) = out.hold_last.col(c);
      continue;
    }
    // Online: refit on the windows so far (causal); temperatures up to c are known.
    std::vector<double> t(times_s.begin(), times_s.begin() + c + 1);
    const TemperatureDriftModel m = FitTemperatureModel(identified.leftCols(c + 1), temperatures.leftCols(c + 1), t,
                                                        params, online_options, windows);
    const Eigen::MatrixXd f = FilteredTemperatureRise(temperatures.leftCols(c + 1), t, m.lag_s);
    const Eigen::VectorXd value = m.coefficients * f.col(c);
    for (int p : params) out.predicted(p, c) = value[p];
    s.lag_s = m.lag_s;
    ++s.predicted_cycles;
  }
  s.windows = static_cast<int>(windows.size());
  s.termination = Termination::kSuccess;
  s.message = offline != nullptr ? "offline model" : "online model";
  if (summary != nullptr) *summary = s;
  return out;
}

std::string KalmanDriftOptions::Validate() const {
  if (window_every < 1) return "window_every must be >= 1";
  if (!(process_ratio_per_hour >= 0.0 && std::isfinite(process_ratio_per_hour)))
    return "process_ratio_per_hour must be >= 0 and finite";
  return "";
}

DriftPrediction KalmanPredictDrift(const Eigen::MatrixXd& identified, const Eigen::MatrixXd& window_covariance,
                                   const Eigen::MatrixXd& temperatures, const std::vector<double>& times_s,
                                   const std::vector<int>& params, const KalmanDriftOptions& options,
                                   const TemperatureDriftModel* model) {
  ThrowIfInvalid(options.Validate(), "KalmanDriftOptions");
  const int cycles = static_cast<int>(identified.cols());
  const int k = static_cast<int>(params.size());
  if (temperatures.cols() != cycles || static_cast<int>(times_s.size()) != cycles) {
    throw InputError({"", 0, "temperatures"}, "temperature columns or times do not match the cycles");
  }
  if (window_covariance.rows() != k || window_covariance.cols() != k) {
    throw InputError({"", 0, "window_covariance"}, "needs one row and column per parameter");
  }
  DriftPrediction out;
  out.predicted = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.hold_last = Eigen::MatrixXd::Zero(identified.rows(), cycles);
  out.is_window.assign(cycles, false);
  Eigen::MatrixXd f;
  if (model != nullptr) f = FilteredTemperatureRise(temperatures, times_s, model->lag_s);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(k, temperatures.rows());
  if (model != nullptr) {
    for (int i = 0; i < k; ++i) b.row(i) = model->coefficients.row(params[i]);
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(k);
  Eigen::MatrixXd p = window_covariance;
  const Eigen::MatrixXd& r = window_covariance;
  int last_window = 0;
  for (int c = 0; c < cycles; ++c) {
    if (c > 0) {
      if (model != nullptr) x += b * (f.col(c) - f.col(c - 1));
      p += options.process_ratio_per_hour * (times_s[c] - times_s[c - 1]) / 3600.0 * r;
    }
    const bool window = c % options.window_every == 0;
    out.is_window[c] = window;
    if (window) {
      Eigen::VectorXd z(k);
      for (int i = 0; i < k; ++i) z[i] = identified(params[i], c);
      if (c == 0) {
        x = z;
        p = r;
      } else {
        // gain = P (P + R)⁻¹, both symmetric.
        const Eigen::MatrixXd gain = Eigen::MatrixXd((p + r).ldlt().solve(p)).transpose();
        x += gain * (z - x);
        p = (Eigen::MatrixXd::Identity(k, k) - gain) * p;
      }
      last_window = c;
    }
    for (int i = 0; i < k; ++i) {
      out.predicted(params[i], c) = x[i];
      out.hold_last(params[i], c) = identified(params[i], last_window);
    }
  }
  return out;
}

void CycleTemperatures(const CycleSeries& series, const std::vector<int>& columns, Eigen::MatrixXd* temperatures,
                       std::vector<double>* times_s) {
  temperatures->resize(kinematics::kNumJoints, static_cast<Eigen::Index>(columns.size()));
  times_s->clear();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const Cycle& cycle = series.cycles[columns[c]];
    times_s->push_back(cycle.time_s);
    for (int j = 0; j < kinematics::kNumJoints; ++j) {
      const std::string name = "temp_j" + std::to_string(j + 1);
      const auto it = cycle.extra.find(name);
      if (it == cycle.extra.end()) throw InputError({series.path, 1, name}, "the predictor needs temperature columns");
      (*temperatures)(j, static_cast<Eigen::Index>(c)) = it->second;
    }
  }
}

PredictionScore ScorePredictionOnMonitoring(const MonitoringModel& monitoring, const DriftPrediction& prediction,
                                            const Eigen::MatrixXd& reference) {
  double sq_pred = 0, sq_hold = 0;
  PredictionScore score;
  for (int c = 0; c < monitoring.NumCycles(); ++c) {
    if (prediction.is_window[c]) continue;
    for (int k = 0; k < monitoring.NumPoints(); ++k) {
      sq_pred += (monitoring.Jacobian(k) * (prediction.predicted.col(c) - reference.col(c))).squaredNorm();
      sq_hold += (monitoring.Jacobian(k) * (prediction.hold_last.col(c) - reference.col(c))).squaredNorm();
      ++score.samples;
    }
  }
  if (score.samples > 0) {
    score.predicted_rms_mm = std::sqrt(sq_pred / score.samples);
    score.hold_last_rms_mm = std::sqrt(sq_hold / score.samples);
  }
  return score;
}

}  // namespace ramtk::thermal
