#include "ramtk/thermal/monitoring.h"

#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/jacobian.h"

namespace ramtk::thermal {

std::string LambdaOptions::Validate() const {
  if (!(threshold_mm > 0.0)) return "threshold_mm must be > 0";
  return "";
}

MonitoringModel::MonitoringModel(const RobotModel& model, const ThermalSetup& setup, const CycleSeries& monitoring)
    : series_(monitoring) {
  if (!setup.has_tool_sensor) {
    throw InputError({"", 0, "flange_from_tool_sensor"}, "the setup has no tool sensor; monitoring points need it");
  }
  const int n = monitoring.NumPoses();
  const int cycles = monitoring.NumCycles();
  Eigen::MatrixXd base(3 * n, cycles);
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < n; ++k) {
      const Cycle& cyc = monitoring.cycles[c];
      base.block<3, 1>(3 * k, c) =
          kinematics::BaseFromFlange(model, cyc.q_controller[k]) * (setup.flange_from_tool_sensor * cyc.position_mm[k]);
    }
  }
  nominal_ = base.colwise() - base.col(0);
  jacobians_.reserve(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 point_in_flange = setup.flange_from_tool_sensor * monitoring.cycles[0].position_mm[k];
    jacobians_.push_back(kinematics::ComputePointParamJacobian(model, monitoring.taught[k], point_in_flange));
  }
}

Eigen::MatrixXd MonitoringModel::Residuals(const Eigen::MatrixXd& delta_x) const {
  Eigen::MatrixXd r = nominal_;
  for (int k = 0; k < NumPoints(); ++k) {
    r.middleRows(3 * k, 3) += jacobians_[k] * (delta_x.colwise() - delta_x.col(0));
  }
  return r;
}

Eigen::VectorXd CompensatedMonitoringSigma(const MonitoringModel& monitoring, const DriftModel& drift_model,
                                           const IdentificationOptions& id, double sigma_y_mm) {
  const Eigen::MatrixXd cov = drift_model.Covariance(id, sigma_y_mm);
  std::vector<int> params = id.params;
  if (params.empty()) params = drift_model.model().FreeParams();
  Eigen::VectorXd out(3 * monitoring.NumPoints());
  for (int k = 0; k < monitoring.NumPoints(); ++k) {
    Eigen::MatrixXd j(3, params.size());
    for (std::size_t c = 0; c < params.size(); ++c) j.col(c) = monitoring.Jacobian(k).col(params[c]);
    const Eigen::Matrix3d pc = j * cov * j.transpose();
    for (int a = 0; a < 3; ++a) out[3 * k + a] = std::sqrt(std::max(0.0, pc(a, a)));
  }
  return out;
}

std::vector<Mat3> CompensatedPointCovariances(const MonitoringModel& monitoring, const std::vector<int>& params,
                                              const Eigen::MatrixXd& covariance) {
  const Eigen::Index k = static_cast<Eigen::Index>(params.size());
  if (covariance.rows() != k || covariance.cols() != k) {
    throw InputError({"", 0, "covariance"}, "is " + std::to_string(covariance.rows()) + " x " +
                                                std::to_string(covariance.cols()) + ", the parameters " +
                                                std::to_string(k));
  }
  std::vector<Mat3> out;
  out.reserve(static_cast<std::size_t>(monitoring.NumPoints()));
  for (int p = 0; p < monitoring.NumPoints(); ++p) {
    Eigen::MatrixXd j(3, k);
    for (Eigen::Index c = 0; c < k; ++c) j.col(c) = monitoring.Jacobian(p).col(params[c]);
    out.push_back(j * covariance * j.transpose());
  }
  return out;
}

Eigen::VectorXd DirectionStatistic(const Eigen::MatrixXd& residuals, LambdaStatistic statistic) {
  const int warm = static_cast<int>(residuals.cols()) - 1;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(residuals.rows());
  if (warm <= 0) return out;
  const auto block = residuals.rightCols(warm);
  if (statistic == LambdaStatistic::kRms) {
    out = (block.array().square().rowwise().sum() / warm).sqrt();
  } else {
    out = block.cwiseAbs().rowwise().maxCoeff();
  }
  return out;
}

double Lambda(const Eigen::MatrixXd& residuals, const LambdaOptions& options) {
  const Eigen::VectorXd stat = DirectionStatistic(residuals, options.statistic);
  if (stat.size() == 0) return 0.0;
  return 100.0 * static_cast<double>((stat.array() < options.threshold_mm).count()) / stat.size();
}

ThermalExperiment MakeExperiment(const RobotModel& model, const ThermalSetup& setup, CycleSeries ball,
                                 CycleSeries monitoring) {
  ThermalExperiment e{model, setup, std::move(ball), std::move(monitoring), {}};
  if (e.ball.cycles.empty() || e.monitoring.cycles.empty() || e.ball.cycles[0].cycle != e.monitoring.cycles[0].cycle) {
    throw InputError({e.monitoring.path, 0, "cycle"},
                     "the monitoring file and the ball file must share the cold reference cycle");
  }
  for (const Cycle& c : e.monitoring.cycles) {
    const int col = e.ball.Find(c.cycle);
    if (col < 0) {
      throw InputError({e.monitoring.path, 0, "cycle"},
                       "monitoring cycle " + std::to_string(c.cycle) + " has no ball measurements in " + e.ball.path);
    }
    e.ball_column.push_back(col);
  }
  return e;
}

Eigen::MatrixXd IdentifyForMonitoring(const ThermalExperiment& experiment, const DriftModel& drift_model,
                                      const IdentificationOptions& options, IdentificationSummary* summary) {
  const Eigen::MatrixXd x =
      drift_model.Solve(experiment.ball.DifferencesFromReference(options.poses), options, summary);
  Eigen::MatrixXd out(x.rows(), static_cast<Eigen::Index>(experiment.ball_column.size()));
  for (std::size_t c = 0; c < experiment.ball_column.size(); ++c) out.col(c) = x.col(experiment.ball_column[c]);
  return out;
}

}  // namespace ramtk::thermal
