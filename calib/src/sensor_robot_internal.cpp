#include "sensor_robot_internal.h"

#include <algorithm>
#include <cmath>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::calib::internal {

void FillResiduals(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                   SensorRobotCalibration* c) {
  c->residuals_mm.clear();
  double sum2 = 0.0;
  c->max_residual_mm = 0.0;
  for (const BallObservation& o : obs) {
    const Vec3 r =
        o.ball_in_sensor - PredictBallInSensor(model, c->sensor_from_base, c->ball_in_flange, o.q_controller);
    c->residuals_mm.push_back(r);
    sum2 += r.squaredNorm();
    c->max_residual_mm = std::max(c->max_residual_mm, r.norm());
  }
  c->rms_mm = obs.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(obs.size()));
}

void FillSummaryResiduals(const SensorRobotCalibration& c, double outlier_factor, SensorRobotSummary* s) {
  s->rms_mm = c.rms_mm;
  s->max_residual_mm = c.max_residual_mm;
  s->outliers.clear();
  std::vector<double> norms;
  for (const Vec3& r : c.residuals_mm) norms.push_back(r.norm());
  std::vector<double> sorted = norms;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  for (int i = 0; i < static_cast<int>(norms.size()); ++i) {
    if (norms[i] == c.max_residual_mm) s->worst_pose = i;
    if (norms[i] > outlier_factor * median) s->outliers.push_back(i);
  }
}

PoseSetDiagnostics CheckPoseSetOrThrow(const kinematics::RobotModel& model, const std::vector<BallObservation>& obs,
                                       const PoseSetCheckOptions& checks) {
  ThrowIfInvalid(checks.Validate(), "checks");
  Vec3 ball = Vec3::Zero();
  if (static_cast<int>(obs.size()) >= std::max(checks.min_poses, 4)) {
    ball = SolveSensorRobotLinear(model, obs).ball_in_flange;
    if (!ball.allFinite()) ball = Vec3::Zero();
  }
  PoseSetDiagnostics d = DiagnosePoseSet(model, obs, ball, checks);
  if (!d.error.empty()) throw InputError({"", 0, "poses"}, d.error);
  for (const std::string& w : d.warnings) RAMTK_LOG(kWarning) << "sensor-robot calibration: " << w;
  return d;
}

}  // namespace ramtk::calib::internal
