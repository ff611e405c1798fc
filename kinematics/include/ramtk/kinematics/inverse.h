#pragma once
// Numerical inverse kinematics: damped least squares (Levenberg–Marquardt) from a seed. Solves
// for the controller joint angles that put the flange at a target pose under a given (possibly
// modified) parameter set; the compensator uses it to correct taught poses.

#include <string>

#include "ramtk/core/termination.h"
#include "ramtk/kinematics/jacobian.h"

namespace ramtk::kinematics {

struct InverseKinematicsOptions {
  // Stop when the position error is below this (mm) ...
  double position_tolerance_mm = 1e-9;
  // ... and the orientation error below this (rad).
  double rotation_tolerance_rad = 1e-12;
  // A target is reported unreachable when the best pose found is farther than these.
  double reach_position_tolerance_mm = 1e-6;
  double reach_rotation_tolerance_rad = 1e-8;
  // Length (mm) that converts rotation errors to the scale of position errors in the
  // least-squares cost: cost = |Δp|² + (length_scale_mm·|Δφ|)².
  double length_scale_mm = 1000.0;
  // Initial damping λ (relative to the largest diagonal entry of JᵀJ) and its bounds.
  double initial_damping = 1e-6;
  double min_damping = 1e-15;
  double max_damping = 1e6;
  // Iterations (accepted or rejected steps) before giving up.
  int max_iterations = 200;
  // Joint steps are limited to this (rad) so far seeds do not jump across branches.
  double max_step_rad = 0.35;
  // When the solver stalls short of the target (typically at a singular configuration), it
  // restarts up to this many times from the seed moved by a fixed pseudo-random offset of at most
  // restart_spread_rad per joint. Deterministic: the same inputs give the same answer.
  int max_restarts = 4;
  double restart_spread_rad = 0.2;

  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

struct InverseKinematicsSummary {
  // kSuccess: within the tolerances; kNoResult: unreachable (the solver stalled at a pose farther
  // from the target than the reach tolerances); kNoConvergence: out of iterations while improving.
  Termination termination = Termination::kNoConvergence;
  JointVector q_controller = JointVector::Zero();  // rad; the best solution found
  int iterations = 0;                              // over all starts
  int restarts = 0;                                // starts after the first
  double initial_position_error_mm = 0.0;
  double initial_rotation_error_rad = 0.0;
  double final_position_error_mm = 0.0;
  double final_rotation_error_rad = 0.0;

  bool Converged() const { return termination == Termination::kSuccess; }
  // One line: termination, iterations, initial -> final errors (mm, deg).
  std::string BriefReport() const;
};

// Solves base_from_flange(model, q) = target starting from `seed` (controller joints, rad).
InverseKinematicsSummary SolveInverseKinematics(const RobotModel& model, const Isometry3& target_base_from_flange,
                                                const JointVector& seed, const InverseKinematicsOptions& options = {});

}  // namespace ramtk::kinematics
