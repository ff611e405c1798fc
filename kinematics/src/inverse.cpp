#include "ramtk/kinematics/inverse.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Error twist that takes the current flange pose to the target, in base coordinates:
// [target position - position; log(R_target · Rᵀ)].
Vec6 PoseError(const Isometry3& target, const Isometry3& current) {
  Vec6 e;
  e.head<3>() = target.translation() - current.translation();
  e.tail<3>() = LogSO3(target.linear() * current.linear().transpose());
  return e;
}

double ScaledCost(const Vec6& e, double length_scale) {
  return e.head<3>().squaredNorm() + length_scale * length_scale * e.tail<3>().squaredNorm();
}

// The words of the report for the three ways the solver ends.
const char* IkTerminationText(Termination t) {
  switch (t) {
    case Termination::kSuccess:
      return "converged";
    case Termination::kNoResult:
      return "unreachable";
    case Termination::kNoConvergence:
      return "max iterations";
    default:
      return ramtk::TerminationName(t);
  }
}

}  // namespace

std::string InverseKinematicsOptions::Validate() const {
  if (!(position_tolerance_mm > 0)) return "position_tolerance_mm must be > 0";
  if (!(rotation_tolerance_rad > 0)) return "rotation_tolerance_rad must be > 0";
  if (!(reach_position_tolerance_mm >= position_tolerance_mm))
    return "reach_position_tolerance_mm must be >= position_tolerance_mm";
  if (!(reach_rotation_tolerance_rad >= rotation_tolerance_rad))
    return "reach_rotation_tolerance_rad must be >= rotation_tolerance_rad";
  if (!(length_scale_mm > 0)) return "length_scale_mm must be > 0";
  if (!(min_damping > 0 && min_damping <= initial_damping && initial_damping <= max_damping))
    return "need 0 < min_damping <= initial_damping <= max_damping";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(max_step_rad > 0)) return "max_step_rad must be > 0";
  if (max_restarts < 0) return "max_restarts must be >= 0";
  if (!(restart_spread_rad >= 0)) return "restart_spread_rad must be >= 0";
  return {};
}

std::string InverseKinematicsSummary::BriefReport() const {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "IK %s after %d iterations (%d restarts): position %.3g -> %.3g mm, rotation %.3g -> %.3g deg",
                IkTerminationText(termination), iterations, restarts, initial_position_error_mm,
                final_position_error_mm, RadToDeg(initial_rotation_error_rad), RadToDeg(final_rotation_error_rad));
  return buf;
}

namespace {

// One damped least-squares descent from `start`.
InverseKinematicsSummary Descend(const RobotModel& model, const Isometry3& target, const JointVector& start,
                                 const InverseKinematicsOptions& options) {
  InverseKinematicsSummary summary;
  JointVector q = start;
  Vec6 e = PoseError(target, BaseFromFlange(model, q));
  double cost = ScaledCost(e, options.length_scale_mm);
  summary.initial_position_error_mm = e.head<3>().norm();
  summary.initial_rotation_error_rad = e.tail<3>().norm();

  Vec6 w;  // row weights: rotation rows scaled to millimetres
  w << 1, 1, 1, options.length_scale_mm, options.length_scale_mm, options.length_scale_mm;
  double lambda = options.initial_damping;
  bool stalled = false;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    if (e.head<3>().norm() < options.position_tolerance_mm && e.tail<3>().norm() < options.rotation_tolerance_rad) {
      break;
    }
    const Mat6 j = w.asDiagonal() * ComputeJointJacobian(model, q);
    const Vec6 r = w.asDiagonal() * e;
    const Mat6 jtj = j.transpose() * j;
    const Vec6 g = j.transpose() * r;
    const double scale = jtj.diagonal().maxCoeff();
    bool accepted = false;
    while (!accepted) {
      Mat6 a = jtj;
      a.diagonal().array() += lambda * scale;
      Vec6 dq = a.ldlt().solve(g);
      const double biggest = dq.cwiseAbs().maxCoeff();
      if (biggest > options.max_step_rad) dq *= options.max_step_rad / biggest;
      const JointVector q_new = q + dq;
      const Vec6 e_new = PoseError(target, BaseFromFlange(model, q_new));
      const double cost_new = ScaledCost(e_new, options.length_scale_mm);
      if (cost_new < cost) {
        q = q_new;
        e = e_new;
        cost = cost_new;
        lambda = std::max(options.min_damping, lambda / 10.0);
        accepted = true;
      } else if (lambda >= options.max_damping) {
        break;  // no damping gives a descent step: a stationary point of the cost
      } else {
        lambda = std::min(options.max_damping, lambda * 10.0);
      }
    }
    if (!accepted) {
      stalled = true;
      break;
    }
  }
  summary.q_controller = q;
  summary.iterations = it;
  summary.final_position_error_mm = e.head<3>().norm();
  summary.final_rotation_error_rad = e.tail<3>().norm();
  const bool within_reach = summary.final_position_error_mm <= options.reach_position_tolerance_mm &&
                            summary.final_rotation_error_rad <= options.reach_rotation_tolerance_rad;
  if (within_reach) {
    summary.termination = Termination::kSuccess;
  } else if (stalled) {
    summary.termination = Termination::kNoResult;
  } else {
    summary.termination = Termination::kNoConvergence;
  }
  return summary;
}

double FinalCost(const InverseKinematicsSummary& s, const InverseKinematicsOptions& options) {
  const double rot_mm = options.length_scale_mm * s.final_rotation_error_rad;
  return s.final_position_error_mm * s.final_position_error_mm + rot_mm * rot_mm;
}

}  // namespace

InverseKinematicsSummary SolveInverseKinematics(const RobotModel& model, const Isometry3& target,
                                                const JointVector& seed, const InverseKinematicsOptions& options) {
  if (const std::string problem = options.Validate(); !problem.empty()) {
    throw std::invalid_argument("InverseKinematicsOptions: " + problem);
  }
  InverseKinematicsSummary best = Descend(model, target, seed, options);
  const double initial_position = best.initial_position_error_mm;
  const double initial_rotation = best.initial_rotation_error_rad;
  int iterations = best.iterations;
  int restart = 0;
  // Fixed offsets (a Weyl sequence on [-1, 1]) so restarts are reproducible without a generator.
  for (; restart < options.max_restarts && !best.Converged(); ++restart) {
    JointVector start = seed;
    for (int i = 0; i < kNumJoints; ++i) {
      const double frac = std::fmod(0.5 + (restart + 1) * 0.6180339887498949 * (i + 1) + 0.1 * i, 1.0);
      start[i] += options.restart_spread_rad * (2.0 * frac - 1.0);
    }
    InverseKinematicsSummary attempt = Descend(model, target, start, options);
    iterations += attempt.iterations;
    if (attempt.Converged() || FinalCost(attempt, options) < FinalCost(best, options)) best = attempt;
  }
  // Keep each joint within ±pi of its seed so the answer is on the seed's branch of the angle.
  for (int i = 0; i < kNumJoints; ++i) {
    best.q_controller[i] = seed[i] + std::remainder(best.q_controller[i] - seed[i], 2.0 * kPi);
  }
  best.initial_position_error_mm = initial_position;
  best.initial_rotation_error_rad = initial_rotation;
  best.iterations = iterations;
  best.restarts = restart;
  return best;
}

}  // namespace ramtk::kinematics
