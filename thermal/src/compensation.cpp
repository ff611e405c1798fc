#include "ramtk/thermal/compensation.h"

#include <cmath>
#include <cstdio>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::thermal {

std::string CompensationSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "compensation %s: %d poses, %d IK iterations, flange RMS %.4f -> %.2e mm (worst %.2e), "
                "max joint change %.4f deg",
                message.c_str(), poses, iterations, initial_rms_position_error_mm, final_rms_position_error_mm,
                worst_final_position_error_mm, max_joint_change_deg);
  return buf;
}

RobotModel ModelWithDrift(const RobotModel& model, const ParamVector& delta_x) {
  RobotModel warm = model;
  warm.SetParams(model.Params() + delta_x);
  return warm;
}

std::vector<JointVector> CompensateTaughtPoses(const RobotModel& model, const ParamVector& delta_x,
                                               const std::vector<JointVector>& taught,
                                               const CompensationOptions& options, CompensationSummary* summary) {
  ThrowIfInvalid(options.Validate(), "CompensationOptions");
  const RobotModel warm = ModelWithDrift(model, delta_x);
  std::vector<JointVector> out;
  CompensationSummary s;
  double initial_sq = 0.0, final_sq = 0.0;
  for (const JointVector& q : taught) {
    const Isometry3 target = kinematics::BaseFromFlange(model, q);
    const kinematics::InverseKinematicsSummary ik = kinematics::SolveInverseKinematics(warm, target, q, options.ik);
    out.push_back(ik.q_controller);
    ++s.poses;
    s.iterations += ik.iterations;
    if (ik.Converged()) ++s.converged;
    initial_sq += std::pow((kinematics::BaseFromFlange(warm, q).translation() - target.translation()).norm(), 2);
    const double final_err =
        (kinematics::BaseFromFlange(warm, ik.q_controller).translation() - target.translation()).norm();
    final_sq += final_err * final_err;
    s.worst_final_position_error_mm = std::max(s.worst_final_position_error_mm, final_err);
    s.max_joint_change_deg = std::max(s.max_joint_change_deg, RadToDeg((ik.q_controller - q).cwiseAbs().maxCoeff()));
  }
  if (s.poses > 0) {
    s.initial_rms_position_error_mm = std::sqrt(initial_sq / s.poses);
    s.final_rms_position_error_mm = std::sqrt(final_sq / s.poses);
  }
  s.termination = s.converged == s.poses ? Termination::kSuccess : Termination::kPartial;
  s.message = s.converged == s.poses
                  ? "converged"
                  : std::to_string(s.poses - s.converged) + " of " + std::to_string(s.poses) + " poses not converged";
  if (summary != nullptr) *summary = s;
  return out;
}

}  // namespace ramtk::thermal
