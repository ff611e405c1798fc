// Stacking, the Ceres solve, identifiability and held-out validation of the robot calibration.
#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

#include "ramtk/core/ceres_solve.h"
#include "robot_calibration_internal.h"

namespace ramtk::calib::detail {
namespace {

// One pose's whitened residual with its analytic Jacobian over the whole unknown vector.
class PoseCost final : public ceres::CostFunction {
 public:
  PoseCost(const CalibrationProblem* problem, int pose) : problem_(problem), pose_(pose) {
    set_num_residuals(problem->frame.layout.RowsPerPose());
    mutable_parameter_block_sizes()->push_back(problem->frame.layout.size);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int size = problem_->frame.layout.size;
    const Eigen::Map<const Eigen::VectorXd> x(parameters[0], size);
    const PoseInput& pose = problem_->poses[pose_];
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    EvaluatePose(problem_->frame, x, pose, &r, jacobians != nullptr && jacobians[0] != nullptr ? &j : nullptr);
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = pose.whitening * r;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], r.size(), size) =
          pose.whitening * j;
    }
    return true;
  }

 private:
  const CalibrationProblem* problem_;
  int pose_;
};

std::vector<int> AllPoses(const CalibrationProblem& problem, const std::vector<int>& poses) {
  if (!poses.empty()) return poses;
  std::vector<int> all(problem.poses.size());
  std::iota(all.begin(), all.end(), 0);
  return all;
}


std::string Signed(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << (v >= 0 ? "+" : "") << v;
  return s.str();
}

}  // namespace

void StackResiduals(const CalibrationProblem& problem, const Eigen::VectorXd& x, const std::vector<int>& poses_in,
                    Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian) {
  const std::vector<int> poses = AllPoses(problem, poses_in);
  const int rows = problem.frame.layout.RowsPerPose();
  const int m = rows * static_cast<int>(poses.size());
  residual->resize(m);
  if (jacobian != nullptr) jacobian->resize(m, problem.frame.layout.size);
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PoseInput& pose = problem.poses[poses[i]];
    EvaluatePose(problem.frame, x, pose, &r, jacobian != nullptr ? &j : nullptr);
    residual->segment(rows * i, rows) = pose.whitening * r;
    if (jacobian != nullptr) jacobian->middleRows(rows * i, rows) = pose.whitening * j;
  }
}

SolveResult SolveUnknowns(const CalibrationProblem& problem, const std::vector<bool>& free,
                          const std::vector<int>& poses_in, const RobotCalibrationOptions& options, int max_iterations,
                          Eigen::VectorXd* x) {
  const std::vector<int> poses = AllPoses(problem, poses_in);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(problem_options);
  std::unique_ptr<ceres::LossFunction> loss;
  if (options.loss == RobustLoss::kHuber) loss = std::make_unique<ceres::HuberLoss>(options.loss_scale);
  if (options.loss == RobustLoss::kCauchy) loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale);
  for (int p : poses) cp.AddResidualBlock(new PoseCost(&problem, p), loss.get(), x->data());
  std::vector<int> fixed;
  for (int i = 0; i < problem.frame.layout.size; ++i) {
    if (!free[i]) fixed.push_back(i);
  }
  SolveResult result;
  if (static_cast<int>(fixed.size()) == problem.frame.layout.size) {
    result.termination = Termination::kSuccess;
    return result;
  }
  if (!fixed.empty()) cp.SetManifold(x->data(), new ceres::SubsetManifold(problem.frame.layout.size, fixed));
  DenseSolveSettings settings;
  settings.max_iterations = max_iterations;
  settings.function_tolerance = 1e-12;
  settings.parameter_tolerance = 1e-12;
  ceres::Solver::Options o = DenseSolverOptions(settings);
  o.num_threads = options.num_threads;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &cp, &summary);
  result.termination = TerminationFromCeres(summary);
  result.iterations = CeresIterations(summary);
  result.final_cost = summary.final_cost;
  return result;
}

void Recentre(CalibrationProblem* problem, Eigen::VectorXd* x) {
  const UnknownLayout& L = problem->frame.layout;
  problem->frame.base_rotation = ExpSO3(x->segment<3>(L.base)) * problem->frame.base_rotation;
  x->segment<3>(L.base).setZero();
  if (L.rotation) {
    problem->frame.tool_rotation = problem->frame.tool_rotation * ExpSO3(x->segment<3>(L.tool));
    x->segment<3>(L.tool).setZero();
  }
}

std::vector<std::vector<Vec3>> HeldOutResiduals(const CalibrationProblem& problem, const std::vector<bool>& free,
                                                const RobotCalibrationOptions& options, const Eigen::VectorXd& x) {
  const int n = static_cast<int>(problem.poses.size());
  std::vector<int> fold(n);
  for (int i = 0; i < n; ++i) fold[i] = options.split == HoldoutSplit::kBlocks ? i * options.folds / n : i % options.folds;
  if (options.split == HoldoutSplit::kRandom) std::shuffle(fold.begin(), fold.end(), std::mt19937(options.seed));
  const int targets = problem.frame.layout.num_targets;
  std::vector<std::vector<Vec3>> out(n, std::vector<Vec3>(targets, Vec3::Zero()));
  for (int f = 0; f < options.folds; ++f) {
    std::vector<int> train, test;
    for (int i = 0; i < n; ++i) (fold[i] == f ? test : train).push_back(i);
    if (test.empty() || train.empty()) continue;
    Eigen::VectorXd xf = x;
    SolveUnknowns(problem, free, train, options, 30, &xf);
    for (int i : test) {
      Eigen::VectorXd r;
      EvaluatePose(problem.frame, xf, problem.poses[i], &r, nullptr);
      for (int k = 0; k < targets; ++k) out[i][k] = r.segment<3>(3 * k);
    }
    if (options.progress) options.progress({"held-out", static_cast<std::size_t>(f + 1), static_cast<std::size_t>(options.folds)});
  }
  return out;
}

ResidualStats StatsOf(const std::vector<std::vector<Vec3>>& residuals, const std::vector<double>& rotation_deg) {
  ResidualStats s;
  s.poses = static_cast<int>(residuals.size());
  double sum = 0.0;
  int count = 0;
  for (const auto& pose : residuals) {
    for (const Vec3& r : pose) {
      sum += r.squaredNorm();
      s.max_3d_mm = std::max(s.max_3d_mm, r.norm());
      ++count;
    }
  }
  if (count > 0) {
    s.rms_3d_mm = std::sqrt(sum / count);
    s.rms_per_coordinate_mm = std::sqrt(sum / (3.0 * count));
  }
  if (!rotation_deg.empty()) {
    double rs = 0.0;
    for (double a : rotation_deg) rs += a * a;
    s.rms_rotation_deg = std::sqrt(rs / rotation_deg.size());
  }
  return s;
}

}  // namespace ramtk::calib::detail

namespace ramtk::calib {

IdentifiabilityAnalysis AnalyseIdentifiability(const Eigen::MatrixXd& jacobian, const std::vector<int>& order,
                                               const std::vector<std::string>& names, double structural_tolerance,
                                               double weak_tolerance) {
  const int size = static_cast<int>(jacobian.cols());
  IdentifiabilityAnalysis e;
  e.keep.assign(size, false);
  e.independence.assign(size, 0.0);
  e.status.assign(size, "");
  e.combination.assign(size, "");
  Eigen::VectorXd norms = jacobian.colwise().norm();
  std::vector<Eigen::VectorXd> basis;  // orthonormal, of the kept unit columns
  std::vector<int> kept;
  for (int c : order) {
    if (norms[c] == 0.0) {
      e.status[c] = "not_identifiable";
      e.combination[c] = "does not move any measurement";
      continue;
    }
    Eigen::VectorXd v = jacobian.col(c) / norms[c];
    for (int pass = 0; pass < 2; ++pass) {
      for (const Eigen::VectorXd& b : basis) v -= b.dot(v) * b;
    }
    const double fraction = v.norm();
    e.independence[c] = fraction;
    if (fraction >= weak_tolerance) {
      e.keep[c] = true;
      basis.push_back(v / fraction);
      kept.push_back(c);
      continue;
    }
    e.status[c] = fraction < structural_tolerance ? "not_identifiable" : "weak";
    // Which kept unknowns it moves like: least squares of its column on theirs, in the
    // unknowns' own units (a unit change of c acts as Σ coefficient·unit change of each).
    Eigen::MatrixXd a(jacobian.rows(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) a.col(k) = jacobian.col(kept[k]);
    const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(jacobian.col(c));
    std::vector<int> idx(kept.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::sort(idx.begin(), idx.end(), [&](int i, int j) {
      return std::abs(coef[i]) * norms[kept[i]] > std::abs(coef[j]) * norms[kept[j]];
    });
    std::string text = "acts as";
    for (std::size_t k = 0; k < idx.size() && k < 4; ++k) {
      if (std::abs(coef[idx[k]]) * norms[kept[idx[k]]] < 0.05 * norms[c]) break;
      text += " " + detail::Signed(coef[idx[k]]) + "·" + names[kept[idx[k]]];
    }
    e.combination[c] = text;
  }
  if (!kept.empty()) {
    Eigen::MatrixXd a(jacobian.rows(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) a.col(k) = jacobian.col(kept[k]);
    const ObservabilityIndices indices = ComputeObservabilityIndices(a);
    e.condition_number = indices.condition_number;
    e.observability_index = indices.observability_index;
    e.noise_amplification_index = indices.noise_amplification_index;
  }
  return e;
}

ObservabilityIndices ComputeObservabilityIndices(const Eigen::MatrixXd& jacobian) {
  ObservabilityIndices out;
  const int p = static_cast<int>(jacobian.cols());
  if (p == 0 || jacobian.rows() < p) return out;
  Eigen::MatrixXd a = jacobian;
  for (int k = 0; k < p; ++k) {
    const double norm = a.col(k).norm();
    if (norm > 0.0) a.col(k) /= norm;
  }
  const Eigen::MatrixXd r = a.householderQr().matrixQR().topRows(p).triangularView<Eigen::Upper>();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(r).singularValues();
  const double smax = sv[0], smin = sv[sv.size() - 1];
  out.condition_number = smin > 0 ? smax / smin : std::numeric_limits<double>::infinity();
  out.observability_index = std::exp(sv.array().log().mean()) / std::sqrt(static_cast<double>(jacobian.rows()));
  out.noise_amplification_index = smin * smin / smax;
  return out;
}

}  // namespace ramtk::calib
