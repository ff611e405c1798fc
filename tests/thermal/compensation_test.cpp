// Compensation of taught poses (IK under the identified drift) scored with the simulator's truth:
// what the tool sensor would read at the corrected joints on the true warm robot.
#include "ramtk/thermal/compensation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "thermal_fixture.h"

namespace ramtk::thermal {
namespace {

using testing::Kr150;
using testing::SimulatedExperiment;
using testing::Thesis;

struct Scores {
  double before = 0.0;  // RMS 3-D reading change at the taught joints
  double after = 0.0;   // at the corrected joints
};

Scores Score(const SimulatedExperiment& e, const Eigen::MatrixXd& identified, const std::vector<int>& cycles) {
  double sq_before = 0.0, sq_after = 0.0;
  int n = 0;
  const auto& taught = e.experiment.monitoring.taught;
  for (int c : cycles) {
    const kinematics::RobotModel warm = ModelWithDrift(Kr150(), e.sim.true_delta_x.col(c));
    CompensationSummary cs;
    const auto corrected = CompensateTaughtPoses(Kr150(), identified.col(c), taught, {}, &cs);
    EXPECT_EQ(cs.converged, cs.poses) << cs.BriefReport();
    EXPECT_LT(cs.worst_final_position_error_mm, 1e-6);
    for (std::size_t k = 0; k < taught.size(); ++k) {
      const Vec3& point = e.sim.monitoring_points_in_base[k];
      const Vec3 cold = ToolSensorReading(Kr150(), e.sim.setup, taught[k], point);
      sq_before += (ToolSensorReading(warm, e.sim.setup, taught[k], point) - cold).squaredNorm();
      sq_after += (ToolSensorReading(warm, e.sim.setup, corrected[k], point) - cold).squaredNorm();
      ++n;
    }
  }
  return {std::sqrt(sq_before / n), std::sqrt(sq_after / n)};
}

TEST(ThermalCompensation, TrueDriftRestoresEveryReadingExactly) {
  const auto& e = Thesis(1);
  const Scores s = Score(e, e.sim.true_delta_x, {45, 89});
  EXPECT_GT(s.before, 0.1);
  EXPECT_LT(s.after, 1e-6);
}

// Identified drift (screened set): the corrected joints leave the noise-propagated error of ΔX,
// J·Cov·Jᵀ summed over the points, far below the uncompensated drift.
void CheckIdentified(int budget) {
  const auto& e = Thesis(1);
  const DriftModel dm(Kr150(), e.sim.setup, e.experiment.ball.taught);
  const std::vector<int> params = e.sim.drifting_params;
  IdentificationOptions id;
  id.params = params;
  if (budget < 20) id.poses = SelectPoses(dm, params, budget);
  std::vector<int> poses = id.poses;
  if (poses.empty()) {
    for (int i = 0; i < 20; ++i) poses.push_back(i);
  }
  const Eigen::MatrixXd x = dm.Solve(e.experiment.ball.DifferencesFromReference(id.poses), id);
  const std::vector<int> cycles = {30, 45, 60, 89};
  const Scores s = Score(e, x, cycles);
  // Expected RMS from the noise model: tool-sensor reading error ≈ R·J_k·δX (rotation-invariant).
  Eigen::MatrixXd a(3 * budget, params.size());
  for (int i = 0; i < budget; ++i) {
    for (std::size_t c = 0; c < params.size(); ++c)
      a.block(3 * i, c, 3, 1) = dm.FullSensitivity().block(3 * poses[i], params[c], 3, 1);
  }
  const double s2 = 2 * (std::pow(e.options.sensor_noise_mm, 2) + std::pow(e.options.repeatability_mm, 2));
  const Eigen::MatrixXd cov = s2 * (a.transpose() * a).inverse();
  const MonitoringModel mon(Kr150(), e.sim.setup, e.experiment.monitoring);
  double expected_sq = 0.0;
  for (int k = 0; k < mon.NumPoints(); ++k) {
    Eigen::MatrixXd j(3, params.size());
    for (std::size_t c = 0; c < params.size(); ++c) j.col(c) = mon.Jacobian(k).col(params[c]);
    expected_sq += (j * cov * j.transpose()).trace();
  }
  const double expected = std::sqrt(expected_sq / mon.NumPoints());
  std::cout << budget << " poses: reading change RMS before " << s.before << " mm, after " << s.after
            << " mm, noise-propagated " << expected << " mm\n";
  EXPECT_LT(s.after, 2.5 * expected);
  EXPECT_LT(s.after, 0.35 * s.before);
}

TEST(ThermalCompensation, IdentifiedDriftTwentyPoses) { CheckIdentified(20); }
TEST(ThermalCompensation, IdentifiedDriftSixPoseBudget) { CheckIdentified(6); }

// Recomputed monitoring points (the thesis's §5.1.3 check) with the true drift leave only the
// measurement noise: √2·√(σ_tool² + σ_rep²) per coordinate (cold and warm reading each noisy).
TEST(ThermalCompensation, RecomputedPointsWithTrueDriftAreAtTheNoiseFloor) {
  const auto& e = Thesis(2);
  const MonitoringModel mon(Kr150(), e.sim.setup, e.experiment.monitoring);
  const int cycles = mon.NumCycles(), points = mon.NumPoints();
  Eigen::MatrixXd r = mon.Uncompensated();
  // Truth at each monitoring instant.
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < points; ++k) {
      const Eigen::VectorXd d =
          e.sim.true_delta_x_monitoring.col(c * points + k) - e.sim.true_delta_x_monitoring.col(k);
      r.block<3, 1>(3 * k, c) += mon.Jacobian(k) * d;
    }
  }
  const double rms = std::sqrt(r.rightCols(cycles - 1).squaredNorm() / (r.rows() * (cycles - 1)));
  const double expected =
      std::sqrt(2.0 * (std::pow(e.options.tool_sensor_noise_mm, 2) + std::pow(e.options.repeatability_mm, 2)));
  EXPECT_NEAR(rms, expected, 0.1 * expected);
  EXPECT_GT(std::sqrt(mon.Uncompensated().squaredNorm() / mon.Uncompensated().size()), 3 * expected);
}

}  // namespace
}  // namespace ramtk::thermal
