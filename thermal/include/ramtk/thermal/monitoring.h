#pragma once
// Monitoring points and the compensation score λ (thesis §3.2, §5.1).
//
// A tool-mounted sensor measures points on a car body (34 in the thesis) once per cycle. A
// point is recomputed in the base frame with the robot's joints and a parameter set:
//   point_in_base = T_e^b(q; X0 + ΔX) · flange_from_tool_sensor · point_in_tool_sensor.
// Its residual in cycle c is the difference from the cold reference cycle's value. A
// "monitoring direction" is one base-frame coordinate (x, y, z) of one point; λ is the share
// (%) of directions whose residual over the cycles stays below a threshold (0.1 mm).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/thermal/cycles.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/setup.h"

namespace ramtk::thermal {

enum class LambdaStatistic {
  kRms,  // a direction passes when the RMS of its residual over the warm cycles is below the threshold
  kMax,  // ... when its largest |residual| over the warm cycles is
};

struct LambdaOptions {
  double threshold_mm = 0.1;                          // thesis: 0.1 mm
  LambdaStatistic statistic = LambdaStatistic::kRms;  // how a direction's residuals are summarised
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// The recomputed monitoring points of a CycleSeries, linearised in ΔX (second-order terms are
// below 1e-4 mm for drifts under 1 mm / 1e-3 rad).
class MonitoringModel {
 public:
  // InputError if the setup has no tool sensor.
  MonitoringModel(const RobotModel& model, const ThermalSetup& setup, const CycleSeries& monitoring);

  int NumPoints() const { return static_cast<int>(jacobians_.size()); }
  int NumCycles() const { return static_cast<int>(nominal_.cols()); }
  const CycleSeries& series() const { return series_; }
  // Points recomputed with the nominal model, minus the reference cycle: 3·points × cycles.
  const Eigen::MatrixXd& Uncompensated() const { return nominal_; }
  // Residuals with ΔX per cycle (30 × cycles; column c for monitoring cycle c).
  Eigen::MatrixXd Residuals(const Eigen::MatrixXd& delta_x) const;
  // ∂(point_in_base)/∂X of point k at its taught pose (3 × 30).
  const Eigen::Matrix<double, 3, kinematics::kNumParams>& Jacobian(int k) const { return jacobians_[k]; }

 private:
  CycleSeries series_;
  Eigen::MatrixXd nominal_;
  std::vector<Eigen::Matrix<double, 3, kinematics::kNumParams>> jacobians_;
};

// Standard deviation of each monitoring direction (3·points) of a compensated position that the
// identification's noise causes: the point's Jacobian over the identified parameters times
// Σ_x = drift_model.Covariance(id, sigma_y_mm), J Σ_x Jᵀ per point. sigma_y_mm: the noise of one
// coordinate of a ball-centre difference (ResidualSigmaY of the identification, or
// sqrt(2(σ_sensor² + σ_repeatability²)) when known). The uncertainty the compensation adds, for
// one cycle; the tool sensor's own noise and unmodelled drift come on top.
Eigen::VectorXd CompensatedMonitoringSigma(const MonitoringModel& monitoring, const DriftModel& drift_model,
                                           const IdentificationOptions& id, double sigma_y_mm);

// Covariance (base frame, mm²) of each monitoring point's compensated position that the
// identification's noise causes: J_k Σ J_kᵀ with J_k the point's Jacobian over `params` and Σ
// their covariance (params × params, mm / rad; IdentificationSummary::covariance of one cycle).
std::vector<Mat3> CompensatedPointCovariances(const MonitoringModel& monitoring, const std::vector<int>& params,
                                              const Eigen::MatrixXd& covariance);

// Per direction (3·points) summary statistic over the columns except the reference (column 0).
Eigen::VectorXd DirectionStatistic(const Eigen::MatrixXd& residuals, LambdaStatistic statistic);
// λ in percent.
double Lambda(const Eigen::MatrixXd& residuals, const LambdaOptions& options);

// A ball series and a monitoring series of the same experiment.
struct ThermalExperiment {
  RobotModel model;
  ThermalSetup setup;
  CycleSeries ball;
  CycleSeries monitoring;
  // For each monitoring cycle, the position of the same cycle number in ball.cycles.
  std::vector<int> ball_column;
};

// Checks that both start at the same reference cycle and that every monitoring cycle has a ball
// cycle; InputError naming the monitoring file otherwise.
ThermalExperiment MakeExperiment(const RobotModel& model, const ThermalSetup& setup, CycleSeries ball,
                                 CycleSeries monitoring);

// Identifies ΔX per ball cycle (options: params, poses) and maps it onto the monitoring cycles:
// 30 × monitoring cycles.
Eigen::MatrixXd IdentifyForMonitoring(const ThermalExperiment& experiment, const DriftModel& drift_model,
                                      const IdentificationOptions& options, IdentificationSummary* summary = nullptr);

}  // namespace ramtk::thermal
