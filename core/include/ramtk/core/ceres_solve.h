#pragma once
// The Ceres set-up shared by ramtk's small dense least-squares problems (sensor-to-robot
// calibration, hand-eye refinement, sphere fits, laser-device fits): Levenberg–Marquardt with a
// dense QR (or normal-Cholesky) solve, one thread (callers parallelise over problems), silent; and
// the Summary fields every ramtk Summary copies. Header-only: include it only from a module that
// links Ceres (it is not part of any installed module's interface).

#include <ceres/ceres.h>

#include "ramtk/core/termination.h"

namespace ramtk {

struct DenseSolveSettings {
  int max_iterations = 100;
  double function_tolerance = 1e-12;   // relative cost change
  double parameter_tolerance = 1e-12;  // relative step
  double gradient_tolerance = 1e-14;   // max-norm of the projected gradient
  bool normal_cholesky = false;        // DENSE_NORMAL_CHOLESKY instead of DENSE_QR (well-conditioned, many residuals)
};

inline ceres::Solver::Options DenseSolverOptions(const DenseSolveSettings& s) {
  ceres::Solver::Options o;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = s.normal_cholesky ? ceres::DENSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  o.max_num_iterations = s.max_iterations;
  o.function_tolerance = s.function_tolerance;
  o.parameter_tolerance = s.parameter_tolerance;
  o.gradient_tolerance = s.gradient_tolerance;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  return o;
}

// Ceres's termination in ramtk's words: CONVERGENCE and USER_SUCCESS → kSuccess, NO_CONVERGENCE →
// kNoConvergence, USER_FAILURE → kCancelled, FAILURE → kFailure.
inline Termination TerminationFromCeres(const ceres::Solver::Summary& s) {
  switch (s.termination_type) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS:
      return Termination::kSuccess;
    case ceres::NO_CONVERGENCE:
      return Termination::kNoConvergence;
    case ceres::USER_FAILURE:
      return Termination::kCancelled;
    default:
      return Termination::kFailure;
  }
}

// Iterations taken (Ceres lists iteration 0, the initial point, too).
inline int CeresIterations(const ceres::Solver::Summary& s) {
  return s.iterations.empty() ? 0 : static_cast<int>(s.iterations.size()) - 1;
}

}  // namespace ramtk
