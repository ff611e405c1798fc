#pragma once
// Compensation of taught poses (thesis §3.1 after eq. 3-10): with the identified drift ΔX the
// warm robot's flange is T_e^b(q; X0 + ΔX); new joint angles q' are found by inverse kinematics
// so that T_e^b(q'; X0 + ΔX) equals the taught (cold) flange pose T_e^b(q; X0).

#include <string>
#include <vector>

#include "ramtk/core/termination.h"
#include "ramtk/kinematics/inverse.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::thermal {

struct CompensationOptions {
  kinematics::InverseKinematicsOptions ik;  // tolerances of the per-pose IK
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const { return ik.Validate(); }
};

struct CompensationSummary {
  Termination termination = Termination::kNotRun;  // kSuccess, or kPartial when poses did not converge
  std::string message = "not run";                 // "converged", "k of n poses not converged"
  int iterations = 0;                              // IK iterations over all poses
  int poses = 0;
  int converged = 0;
  double initial_rms_position_error_mm = 0.0;  // warm model at the taught joints vs taught flange
  double final_rms_position_error_mm = 0.0;    // warm model at the corrected joints vs taught flange
  double worst_final_position_error_mm = 0.0;
  double max_joint_change_deg = 0.0;
  int outliers = 0;  // always 0
  std::string BriefReport() const;
};

// The model with ΔX added to its parameters.
RobotModel ModelWithDrift(const RobotModel& model, const ParamVector& delta_x);

// Corrected controller joints (rad) for each taught pose under the drift ΔX.
std::vector<JointVector> CompensateTaughtPoses(const RobotModel& model, const ParamVector& delta_x,
                                               const std::vector<JointVector>& taught,
                                               const CompensationOptions& options = {},
                                               CompensationSummary* summary = nullptr);

}  // namespace ramtk::thermal
