#pragma once
// The pieces of CalibrateRobot: stacking the whitened Jacobian, the Ceres solve over a subset of
// poses and unknowns, the identifiability analysis and the held-out validation.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/calib/robot_calibration.h"
#include "ramtk/calib/robot_identifiability.h"
#include "ramtk/calib/robot_model_eval.h"

namespace ramtk::calib::detail {

struct CalibrationProblem {
  ModelFrame frame;
  std::vector<PoseInput> poses;
};

// Whitened residuals and Jacobian of the poses listed (all when `poses` is empty); the Jacobian
// only when `jacobian` is not null. Rows: pose by pose, RowsPerPose each.
void StackResiduals(const CalibrationProblem& problem, const Eigen::VectorXd& x, const std::vector<int>& poses,
                    Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian);

struct SolveResult {
  Termination termination = Termination::kNotRun;
  int iterations = 0;
  double final_cost = 0.0;
};

// Levenberg–Marquardt (Ceres) over the unknowns with free[i] true, on the poses listed (all when
// empty). x is updated.
SolveResult SolveUnknowns(const CalibrationProblem& problem, const std::vector<bool>& free, const std::vector<int>& poses,
                          const RobotCalibrationOptions& options, int max_iterations, Eigen::VectorXd* x);

// Moves the small rotation unknowns into the reference rotations (φ, ψ back to zero), so the
// Jacobian is exact there.
void Recentre(CalibrationProblem* problem, Eigen::VectorXd* x);

// The identifiability analysis (public in robot_identifiability.h).
using Elimination = IdentifiabilityAnalysis;
using calib::AnalyseIdentifiability;

// k-fold held-out residuals (positions of every target, mm) per pose, from fits that start at x.
std::vector<std::vector<Vec3>> HeldOutResiduals(const CalibrationProblem& problem, const std::vector<bool>& free,
                                                const RobotCalibrationOptions& options, const Eigen::VectorXd& x);

ResidualStats StatsOf(const std::vector<std::vector<Vec3>>& residuals, const std::vector<double>& rotation_deg = {});

}  // namespace ramtk::calib::detail
