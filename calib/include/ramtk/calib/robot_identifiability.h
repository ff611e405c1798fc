#pragma once
// The identifiability analysis of the robot calibration (robot_calibration.h), public so that
// pose planning decides the identifiable unknowns exactly as CalibrateRobot does: the names of
// the unknowns, which are offered, their order of preference, and the greedy orthogonalisation of
// the unit-norm Jacobian columns with its observability indices.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/calib/robot_calibration.h"
#include "ramtk/calib/robot_model_eval.h"
#include "ramtk/kinematics/chain.h"

namespace ramtk::calib {

// "d1", "theta2", "base_rx", "target1_x", "tool_rz", "cyc_s1_j2", "compliance_j3" per unknown of x.
std::vector<std::string> UnknownNames(const UnknownLayout& layout);

// Link unknowns offered (chain order, 5N): those not structural zeros of the file, and β where
// the axes of a link are within options.parallel_axes_deg of parallel.
std::vector<bool> LinkCandidates(const kinematics::RobotChain& chain, const RobotCalibrationOptions& options);

// Order of preference: set-up, then θ a α β of each joint, then every d, then the terms; only the
// unknowns with candidate[i] true.
std::vector<int> PreferenceOrder(const UnknownLayout& layout, const std::vector<bool>& candidate);

// Identifiability of the candidate unknowns.
struct IdentifiabilityAnalysis {
  std::vector<bool> keep;             // per unknown (layout.size)
  std::vector<double> independence;   // fraction of the unit column outside the span before it
  std::vector<std::string> status;    // "" kept, "not_identifiable", "weak"
  std::vector<std::string> combination;
  double condition_number = 0.0;
  double observability_index = 0.0;
  double noise_amplification_index = 0.0;
};

// Each column of `jacobian` (whitened, every pose stacked) in `order`, made unit norm and
// orthogonalised against the kept ones before it: kept when at least weak_tolerance of it is
// left, "weak" below that, "not_identifiable" below structural_tolerance (with the combination
// of kept unknowns it acts as).
IdentifiabilityAnalysis AnalyseIdentifiability(const Eigen::MatrixXd& jacobian, const std::vector<int>& order,
                                               const std::vector<std::string>& names, double structural_tolerance,
                                               double weak_tolerance);

// Indices of the columns of a whitened Jacobian (each column scaled to unit norm first): its
// condition number, the observability index O1 = (Π σ_i)^(1/p)/√m (m rows) and the noise
// amplification index σ_min²/σ_max.
struct ObservabilityIndices {
  double condition_number = 0.0;
  double observability_index = 0.0;
  double noise_amplification_index = 0.0;
};
ObservabilityIndices ComputeObservabilityIndices(const Eigen::MatrixXd& jacobian);

}  // namespace ramtk::calib
