// Geometric sphere fit with Ceres: residual (|p - c| - R) / sigma per point (analytic Jacobian),
// optional Huber or Cauchy loss, radius free or held constant; all points in one residual block.

#include <ceres/ceres.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "ramtk/core/ceres_solve.h"
#include "ramtk/vision/sphere/detail/sphere_fit_internal.h"

namespace ramtk::vision::sphere_internal {
namespace {

// Distance along the normal over sigma, and its gradient with respect to (centre, radius).
double NormalResidual(const Eigen::Vector3d& p, double sigma, const Eigen::Vector3d& c, double radius,
                      Eigen::Vector4d* gradient) {
  const Eigen::Vector3d d = p - c;
  const double n = d.norm();
  if (!(n > 0)) return std::numeric_limits<double>::quiet_NaN();
  if (gradient) *gradient << -d / (n * sigma), -1.0 / sigma;
  return (n - radius) / sigma;
}

// All points in one residual block: one evaluation call per iteration instead of one per point
// (Ceres spent ~2 000 instructions per single-residual block evaluation). Residuals along the
// normal, or along the rays from `viewpoint` when given. With a robust `loss` each residual r
// is entered as sign(r) sqrt(rho(r^2)), rho the loss's own Evaluate: half the sum of squares is
// then Ceres' robust cost (1/2) sum rho(r^2), the minimum that of one block per point with the
// loss on each; the Jacobian is rho'(r^2) |r| / sqrt(rho(r^2)) times r's (sqrt(rho'(0)) at 0).
class PointResiduals final : public ceres::CostFunction {
 public:
  PointResiduals(const std::vector<Eigen::Vector3f>& points, const double* sigma, const std::vector<int>& indices,
                 const Eigen::Vector3d* viewpoint, const ceres::LossFunction* loss = nullptr)
      : points_(points), sigma_(sigma), indices_(indices), along_ray_(viewpoint != nullptr), loss_(loss) {
    if (viewpoint) viewpoint_ = *viewpoint;
    set_num_residuals(static_cast<int>(indices.size()));
    mutable_parameter_block_sizes()->push_back(3);
    mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Vector3d c(parameters[0][0], parameters[0][1], parameters[0][2]);
    const double radius = parameters[1][0];
    // Each residual and its row of the Jacobian depend on their point alone: ranges of points
    // run in parallel (a ball's 40 k points, ~5 evaluations per fit) with the same results.
    std::atomic<bool> finite{true};
    ForEachIndex(indices_.size(), [&](std::size_t k) {
      if (!finite) return;
      const int i = indices_[k];
      Eigen::Vector4d g;
      double r = along_ray_ ? AlongRayResidual(points_[i].cast<double>(), sigma_[i], viewpoint_, c, radius, &g)
                            : NormalResidual(points_[i].cast<double>(), sigma_[i], c, radius, &g);
      if (!std::isfinite(r)) {
        finite = false;
        return;
      }
      if (loss_) {
        double rho[3];
        loss_->Evaluate(r * r, rho);
        const double rt = std::sqrt(std::max(0.0, rho[0]));
        g *= rt > 0 ? rho[1] * std::abs(r) / rt : std::sqrt(std::max(0.0, rho[1]));
        r = r < 0 ? -rt : rt;
      }
      residuals[k] = r;
      if (jacobians != nullptr) {
        if (jacobians[0] != nullptr)
          for (int a = 0; a < 3; ++a) jacobians[0][3 * k + a] = g[a];
        if (jacobians[1] != nullptr) jacobians[1][k] = g[3];
      }
    });
    return finite;
  }

 private:
  const std::vector<Eigen::Vector3f>& points_;
  const double* sigma_;  // indexed like points_
  const std::vector<int>& indices_;
  bool along_ray_;
  const ceres::LossFunction* loss_;
  Eigen::Vector3d viewpoint_ = Eigen::Vector3d::Zero();
};

// Solves a sphere problem over (centre, radius) and collects the result. A start-and-classify
// pass stops at 1e-7 relative change of the cost; a `precise` (final) fit runs to rounding level
// (noise-free data must come back exact).
GeometricFit SolveSphere(ceres::Problem* problem, double* centre, double* radius, bool fix_radius, int max_iterations,
                         bool precise) {
  if (fix_radius) problem->SetParameterBlockConstant(radius);
  const ceres::Solver::Options solver_options = DenseSolverOptions(
      {max_iterations, precise ? 1e-12 : 1e-7, precise ? 1e-12 : 1e-8, precise ? 1e-14 : 1e-10, true});
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, problem, &summary);
  GeometricFit fit;
  fit.centre = Eigen::Vector3d(centre[0], centre[1], centre[2]);
  fit.radius = *radius;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.initial_cost = summary.initial_cost;
  fit.final_cost = summary.final_cost;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  return fit;
}

}  // namespace

double AlongRayResidual(const Eigen::Vector3d& p, double sigma, const Eigen::Vector3d& viewpoint,
                        const Eigen::Vector3d& centre, double radius, Eigen::Vector4d* gradient) {
  // Ray x(t) = v + t u; |x(t) - c| = R at t = b - sqrt(b^2 - |w|^2 + R^2), w = c - v, b = u.w.
  const Eigen::Vector3d ray = p - viewpoint;
  const double length = ray.norm();
  const Eigen::Vector3d u = ray / length;
  const Eigen::Vector3d w = centre - viewpoint;
  const double b = u.dot(w);
  const double disc = b * b - w.squaredNorm() + radius * radius;
  if (disc <= 0) {  // the ray misses the sphere: its nearest point to the centre (continuous at 0)
    if (gradient) *gradient << -u / sigma, 0.0;
    return (length - b) / sigma;
  }
  const double root = std::sqrt(disc);
  const double t = b - root;
  if (gradient) {
    // dt/dc = u - (b u - w) / root, dt/dR = -R / root; the residual is (length - t) / sigma.
    const Eigen::Vector3d dt_dc = u - (b * u - w) / root;
    *gradient << -dt_dc / sigma, radius / (root * sigma);
  }
  return (length - t) / sigma;
}

GeometricFit FitAlongRay(const std::vector<Eigen::Vector3f>& points, const double* sigma,
                         const std::vector<int>& indices, const Eigen::Vector3d& viewpoint,
                         const Eigen::Vector3d& centre0, double radius0, bool fix_radius, int max_iterations) {
  double centre[3] = {centre0.x(), centre0.y(), centre0.z()};
  double radius = radius0;
  ceres::Problem problem;
  problem.AddResidualBlock(new PointResiduals(points, sigma, indices, &viewpoint), nullptr, centre, &radius);
  return SolveSphere(&problem, centre, &radius, fix_radius, max_iterations, true);
}

GeometricFit FitGeometric(const std::vector<Eigen::Vector3f>& points, const double* sigma,
                          const std::vector<int>& indices, const Eigen::Vector3d& centre0, double radius0,
                          bool fix_radius, SphereLoss loss, double loss_scale, int max_iterations, bool precise) {
  double centre[3] = {centre0.x(), centre0.y(), centre0.z()};
  double radius = radius0;
  // The loss object outlives the problem (its residual block holds a reference).
  std::unique_ptr<ceres::LossFunction> loss_function;
  if (loss == SphereLoss::kHuber) loss_function = std::make_unique<ceres::HuberLoss>(loss_scale);
  if (loss == SphereLoss::kCauchy) loss_function = std::make_unique<ceres::CauchyLoss>(loss_scale);
  ceres::Problem problem;
  problem.AddResidualBlock(new PointResiduals(points, sigma, indices, nullptr, loss_function.get()), nullptr, centre,
                           &radius);
  return SolveSphere(&problem, centre, &radius, fix_radius, max_iterations, precise);
}

}  // namespace ramtk::vision::sphere_internal
