// The thesis method for sensor_from_base and ball_in_flange, eqs. (3-11)..(3-19), as printed,
// with the two misprints of eq. (3-15) corrected (see docs/calib.md): B is 3×12, and the block
// multiplying P_e is −(R_1 − R_2), as eq. (3-14) requires.
#include <ceres/ceres.h>

#include <cmath>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/ceres_solve.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/forward.h"
#include "sensor_robot_internal.h"

namespace ramtk::calib {
namespace {

// B_i·ΔK − b_i for one pose pair (eq. 3-15); ΔK = [r_s11 .. r_s33 (R_sᵀ row-major), x_e, y_e, z_e].
struct DifferenceEquation {
  Eigen::Matrix<double, 3, 12> b_matrix;
  Vec3 b_vector;
  template <typename T>
  bool operator()(const T* k, T* residual) const {
    for (int r = 0; r < 3; ++r) {
      T sum = T(-b_vector[r]);
      for (int c = 0; c < 12; ++c) sum += b_matrix(r, c) * k[c];
      residual[r] = sum;
    }
    return true;
  }
};

// sqrt(M)·f_i of eq. (3-17), so that the squared norm adds M·Σf_i² to the cost (3-18).
struct OrthogonalityPenalty {
  double sqrt_m;
  template <typename T>
  bool operator()(const T* k, T* residual) const {
    auto row = [&](int i, int j) {
      return k[3 * i] * k[3 * j] + k[3 * i + 1] * k[3 * j + 1] + k[3 * i + 2] * k[3 * j + 2];
    };
    residual[0] = sqrt_m * (row(0, 0) - T(1));
    residual[1] = sqrt_m * (row(1, 1) - T(1));
    residual[2] = sqrt_m * (row(2, 2) - T(1));
    residual[3] = sqrt_m * row(0, 1);
    residual[4] = sqrt_m * row(0, 2);
    residual[5] = sqrt_m * row(1, 2);
    return true;
  }
};

}  // namespace

std::string ThesisCalibrationOptions::Validate() const {
  if (!(penalty_factor > 0.0) || !std::isfinite(penalty_factor)) return "penalty_factor must be positive";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(function_tolerance > 0.0) || !(parameter_tolerance > 0.0)) return "tolerances must be positive";
  return checks.Validate();
}

SensorRobotCalibration CalibrateSensorRobotThesis(const kinematics::RobotModel& model,
                                                  const std::vector<BallObservation>& obs,
                                                  const ThesisCalibrationOptions& options,
                                                  SensorRobotSummary* summary) {
  ThrowIfInvalid(options.Validate(), "ThesisCalibrationOptions");
  SensorRobotSummary local;
  SensorRobotSummary& s = summary ? *summary : local;
  s = SensorRobotSummary();
  s.method = "thesis";
  s.diagnostics = internal::CheckPoseSetOrThrow(model, obs, options.checks);
  s.warnings = s.diagnostics.warnings;

  const int n1 = static_cast<int>(obs.size());  // n + 1 poses
  std::vector<Isometry3> flange(n1);
  for (int i = 0; i < n1; ++i) flange[i] = kinematics::BaseFromFlange(model, obs[i].q_controller);

  // B' and b' (eq. 3-16): the first pose against every other.
  std::vector<DifferenceEquation> equations;
  for (int i = 1; i < n1; ++i) {
    DifferenceEquation e;
    e.b_matrix.setZero();
    const Vec3 dp = obs[0].ball_in_sensor - obs[i].ball_in_sensor;
    const Mat3 dr = flange[0].linear() - flange[i].linear();
    for (int r = 0; r < 3; ++r) {
      e.b_matrix.block<1, 3>(r, 3 * r) = dp.transpose();
      e.b_matrix.block<1, 3>(r, 9) = -dr.row(r);
    }
    e.b_vector = flange[0].translation() - flange[i].translation();
    equations.push_back(e);
  }
  // Start: the unconstrained linear least-squares solution of B'·ΔK = b' (the thesis gives no
  // starting point).
  Eigen::MatrixXd big_b(3 * (n1 - 1), 12);
  Eigen::VectorXd big_rhs(3 * (n1 - 1));
  for (int i = 0; i < n1 - 1; ++i) {
    big_b.block<3, 12>(3 * i, 0) = equations[i].b_matrix;
    big_rhs.segment<3>(3 * i) = equations[i].b_vector;
  }
  Eigen::Matrix<double, 12, 1> k = big_b.colPivHouseholderQr().solve(big_rhs);

  ceres::Problem problem;
  for (const DifferenceEquation& e : equations) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DifferenceEquation, 3, 12>(new DifferenceEquation(e)),
                             nullptr, k.data());
  }
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<OrthogonalityPenalty, 6, 12>(
                               new OrthogonalityPenalty{std::sqrt(options.penalty_factor)}),
                           nullptr, k.data());
  ceres::Solver::Summary cs;
  ceres::Solve(
      DenseSolverOptions({options.max_iterations, options.function_tolerance, options.parameter_tolerance, 1e-20}),
      &problem, &cs);
  s.iterations = CeresIterations(cs);
  s.initial_cost = cs.initial_cost;
  s.final_cost = cs.final_cost;
  s.termination = TerminationFromCeres(cs);

  Mat3 rs_t;
  rs_t << k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8];
  const Mat3 rs = rs_t.transpose();
  SensorRobotCalibration c;
  c.ball_in_flange = k.tail<3>();
  // Eq. (3-19): t_si = P_si − R_s·R_i·P_e − R_s·t_i, averaged over all n + 1 poses.
  Vec3 ts = Vec3::Zero();
  for (int i = 0; i < n1; ++i) {
    ts += (obs[i].ball_in_sensor - rs * flange[i].linear() * c.ball_in_flange - rs * flange[i].translation()) / n1;
  }
  c.sensor_from_base.linear() = rs;
  c.sensor_from_base.translation() = ts;
  c.orthonormality_error = OrthonormalityError(rs);
  internal::FillResiduals(model, obs, &c);
  internal::FillSummaryResiduals(c, 4.0, &s);
  return c;
}

}  // namespace ramtk::calib
