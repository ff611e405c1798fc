// Geometric sphere fit with Ceres: residual (|p - c| - R) / sigma per point (analytic Jacobian),
// optional Huber or Cauchy loss, radius free or held constant.

#include <ceres/ceres.h>

#include <memory>

#include "sphere_fit_internal.h"

namespace ramtk::vision::sphere_internal {
namespace {

class SphereResidual final : public ceres::SizedCostFunction<1, 3, 1> {
 public:
  SphereResidual(const Eigen::Vector3d& p, double inv_sigma) : p_(p), inv_sigma_(inv_sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Vector3d d = p_ - Eigen::Map<const Eigen::Vector3d>(parameters[0]);
    const double n = d.norm();
    if (!(n > 0)) return false;
    residuals[0] = (n - parameters[1][0]) * inv_sigma_;
    if (jacobians != nullptr) {
      if (jacobians[0] != nullptr) {
        Eigen::Map<Eigen::Vector3d> dc(jacobians[0]);
        dc = -d * (inv_sigma_ / n);
      }
      if (jacobians[1] != nullptr) jacobians[1][0] = -inv_sigma_;
    }
    return true;
  }

 private:
  Eigen::Vector3d p_;
  double inv_sigma_;
};

}  // namespace

GeometricFit FitGeometric(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& sigma,
                          const std::vector<int>& indices, const Eigen::Vector3d& centre0, double radius0,
                          bool fix_radius, SphereLoss loss, double loss_scale, int max_iterations) {
  double centre[3] = {centre0.x(), centre0.y(), centre0.z()};
  double radius = radius0;
  // One loss object shared by all residuals; it outlives the problem, which does not own it.
  std::unique_ptr<ceres::LossFunction> loss_function;
  if (loss == SphereLoss::kHuber) loss_function = std::make_unique<ceres::HuberLoss>(loss_scale);
  if (loss == SphereLoss::kCauchy) loss_function = std::make_unique<ceres::CauchyLoss>(loss_scale);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (int i : indices)
    problem.AddResidualBlock(new SphereResidual(points[i], 1.0 / sigma[i]), loss_function.get(), centre, &radius);
  if (fix_radius) problem.SetParameterBlockConstant(&radius);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  GeometricFit fit;
  fit.centre = Eigen::Vector3d(centre[0], centre[1], centre[2]);
  fit.radius = radius;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.initial_cost = summary.initial_cost;
  fit.final_cost = summary.final_cost;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  return fit;
}

}  // namespace ramtk::vision::sphere_internal
