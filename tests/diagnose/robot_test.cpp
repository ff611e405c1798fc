// Robot/ball diagnosis: hidden-effect draws (the named cause must be the hidden one, and a present
// effect must lose at least half of its held-out excess), the thesis's thermal case, and the
// building blocks against independent truth (finite differences, geometry, the simulator's noise).
#include "ramtk/diagnose/robot/robot.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>

#include "ramtk/core/units.h"
#include "ramtk/diagnose/engine/report.h"
#include "ramtk/diagnose/robot/robot_hidden.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/simulator.h"
#include "ramtk/diagnose/robot/detail/robot_linear.h"

namespace ramtk::diagnose {
namespace {

using kinematics::ParamIndex;
using kinematics::ParamKind;

const kinematics::RobotModel& Kr150() {
  static const kinematics::RobotModel m =
      kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
  return m;
}

// ---- hidden-effect draws: seeds 1..24 hold every robot effect of the catalogue and clean data ----
class HiddenRobotEffect : public ::testing::TestWithParam<int> {};

TEST_P(HiddenRobotEffect, NamesTheHiddenCauseAndRemovesHalfTheExcess) {
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), GetParam());
  const Diagnosis d = DiagnoseRobotData(draw.input, DiagnoseOptions{});
  SCOPED_TRACE("seed " + std::to_string(GetParam()) + ": " + draw.description);
  // Issue 15's rule: `ambiguous` is right when the hidden effect is one of a look-alike pair.
  if (d.cause == kAmbiguous) {
    EXPECT_LE(d.look_alikes.size(), 2u);
    EXPECT_NE(std::find(d.look_alikes.begin(), d.look_alikes.end(), draw.effect), d.look_alikes.end());
    EXPECT_FALSE(d.separate_with.empty());
  } else {
    EXPECT_EQ(d.cause, draw.effect);
  }
  if (draw.effect != kNoEffect) {
    EXPECT_GE(d.excess_removed, 0.5);
    EXPECT_LT(d.rms_after, d.rms_before);
  }
}

INSTANTIATE_TEST_SUITE_P(Draws, HiddenRobotEffect, ::testing::Range(1, 25));

TEST(HiddenRobotEffect, TheDrawsCoverEveryRobotEffectAndCleanData) {
  std::set<std::string> seen;
  for (int seed = 1; seed <= 24; ++seed) {
    HiddenRobotOptions o;
    o.cycles = 4, o.poses = 8;  // the draw of the effect does not depend on the data size
    seen.insert(DrawHiddenRobotEffect(Kr150(), seed, o).effect);
  }
  const std::vector<std::string> drawn = DrawnRobotEffects();
  std::set<std::string> expected(drawn.begin(), drawn.end());
  expected.insert(kNoEffect);
  EXPECT_EQ(seen, expected);
}

// ---- recovered parameters against the hidden truth ----
// The hidden draw of `seed` is `effect`; its estimated parameter lies within 4σ of the truth.
void ExpectRecoveredWithinSigma(int seed, const std::string& effect) {
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), seed);
  ASSERT_EQ(draw.effect, effect);
  const Diagnosis d = DiagnoseRobotData(draw.input, DiagnoseOptions{});
  const auto& [key, truth] = *draw.truth.begin();
  ASSERT_TRUE(d.parameters.count(key)) << key;
  EXPECT_NEAR(d.parameters.at(key), truth, 4.0 * d.sigmas.at(key));
}

TEST(RobotDiagnosis, RecoversAHiddenJointOffsetWithinItsSigma) {
  ExpectRecoveredWithinSigma(39, "joint_offset");  // theta5 offset (seed 3's theta3 offset is a look-alike
                                                   // of a cyclic error of joint 2 in its poses)
}

TEST(RobotDiagnosis, RecoversAHiddenLinkLengthErrorWithinItsSigma) {
  ExpectRecoveredWithinSigma(21, "link_length_error");  // a2 off
}

// ---- the noise floor from successive cycles against the simulator's noise ----
TEST(RobotDiagnosis, EstimatesTheSimulatorsNoiseFromSuccessiveCycles) {
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), 6);  // thermal drift: slow, present
  const robot_detail::RowSet rs = robot_detail::BuildRows(draw.input);
  int pairs = 0;
  const double sigma = robot_detail::EstimateNoiseFromCycles(rs.rows, &pairs);
  const double truth = std::hypot(0.02, 0.015);  // sensor noise and repeatability per axis
  EXPECT_EQ(pairs, 15 * 15);
  // 675 differences: relative standard error of σ ≈ 1/√(2·675) = 2.7 %; 4 of them.
  EXPECT_NEAR(sigma, truth, 0.11 * truth);
}

// ---- aliasing: what the set-up nuisance absorbs, from the geometry ----
TEST(RobotDiagnosis, SensorAndBallAbsorbD1Theta1AndD6) {
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), 2);
  const robot_detail::RowSet rs = robot_detail::BuildRows(draw.input);
  const robot_detail::Design base = robot_detail::NuisanceDesign(rs.rows);
  // d1 moves the whole arm along base Z, θ1 turns it about base Z (a rigid motion of the sensor
  // frame); d6 moves the ball along the flange axis (a change of ball_in_flange).
  const std::vector<int> params = {ParamIndex(ParamKind::kD, 0), ParamIndex(ParamKind::kTheta, 0),
                                   ParamIndex(ParamKind::kD, 5), ParamIndex(ParamKind::kA, 1),
                                   ParamIndex(ParamKind::kTheta, 2)};
  std::vector<robot_detail::Mat3X> cols;
  for (const auto& r : rs.rows) {
    robot_detail::Mat3X m(3, params.size());
    for (size_t k = 0; k < params.size(); ++k) m.col(k) = r.j_param.col(params[k]);
    cols.push_back(m);
  }
  EXPECT_EQ(robot_detail::IndependentColumns(base.stat, cols), (std::vector<int>{3, 4}));
}

// ---- gravity torque against the derivative of the potential energy ----
TEST(RobotDiagnosis, GravityTorqueIsMinusTheGradientOfThePotentialEnergy) {
  const kinematics::RobotModel& model = Kr150();
  const Eigen::Vector3d ball(43.08, -5.64, 306.7);
  kinematics::JointVector q;
  q << 0.3, -1.2, 1.9, 0.4, 0.8, -0.5;
  // V = Σ m g z over the same lumped masses: 0.1 kg/mm between frame origins, 20 kg at the ball.
  auto potential = [&](const kinematics::RobotModel& m) {
    const auto f = kinematics::ComputeChainFrames(m, q);
    double v = 0;
    for (int k = 1; k <= 6; ++k) {
      const Eigen::Vector3d a = f.base_from_link[k - 1].translation(), b = f.base_from_link[k].translation();
      v += 0.1 * (b - a).norm() * 9.81 * 0.5 * (a.z() + b.z());
    }
    return (v + 20.0 * 9.81 * (f.base_from_link[6] * ball).z()) / 1000.0;  // N·m
  };
  const Eigen::Matrix<double, 6, 1> tau = robot_detail::GravityTorques(model, q, ball);
  for (int j = 0; j < 6; ++j) {
    const double h = 1e-6;
    kinematics::RobotModel plus = model, minus = model;
    plus.links[j].theta0 += h, minus.links[j].theta0 -= h;
    const double dv = (potential(plus) - potential(minus)) / (2 * h);
    EXPECT_NEAR(tau[j], -dv, 1e-4 * (1.0 + std::abs(dv))) << "joint " << j + 1;
  }
}

// The diagnosis input of a simulated thesis experiment, judged with the traditional (length-only)
// thermal model.
RobotDiagnoseInput ThesisInput(const thermal::ThermalSimResult& sim, const std::string& label) {
  RobotDiagnoseInput in;
  in.model = Kr150();
  in.setup = sim.setup, in.has_setup = true;
  in.ball = sim.ball, in.ball_path = label;
  in.thermal_params = thermal::TraditionalParams(in.model), in.thermal_label = "traditional";
  return in;
}

// ---- the thesis case (§3, §5.1): the traditional length-only model against angular drift ----
TEST(RobotDiagnosis, ThesisCaseNamesAngleDriftAndTheAnglesToAdd) {
  const thermal::ThermalSimOptions o = thermal::ThesisPreset(1);
  const thermal::ThermalSimResult sim = thermal::SimulateThermal(Kr150(), o);
  RobotDiagnoseInput in = ThesisInput(sim, "thesis seed 1");
  in.monitoring = sim.monitoring, in.has_monitoring = true, in.monitoring_path = "monitoring";
  const Diagnosis d = DiagnoseRobotData(in, DiagnoseOptions{});
  EXPECT_EQ(d.cause, "thermal_angle_drift");
  // The simulator's angular drift is α3, α4, β2 (ThesisPreset): exactly these are added.
  std::set<std::string> added;
  for (const auto& [k, v] : d.parameters)
    if (k.find("_deg") != std::string::npos) added.insert(k.substr(0, k.find("_drift")));
  EXPECT_EQ(added, (std::set<std::string>{"alpha3", "alpha4", "beta2"})) << ::testing::PrintToString(d.findings);
  // The size of each added drift against the simulator's truth (range over the 90 cycles). The
  // drift is fitted as a quadratic in time, which cannot follow the kink where heating stops
  // (110 min) and shares part of each angle with the per-cycle lengths; 20 % allows for that.
  for (const std::string& name : added) {
    const Eigen::VectorXd truth = sim.true_delta_x.row(kinematics::ParamIndexFromName(name)).transpose();
    const double truth_range_deg = RadToDeg(truth.maxCoeff() - truth.minCoeff());
    EXPECT_NEAR(d.parameters.at(name + "_drift_range_deg"), truth_range_deg, 0.2 * truth_range_deg) << name;
  }
  EXPECT_GE(d.excess_removed, 0.8);
  bool lambda_reported = false;
  for (const std::string& f : d.findings) lambda_reported |= f.find("λ (thesis") != std::string::npos;
  EXPECT_TRUE(lambda_reported);
}

TEST(RobotDiagnosis, WritesTheResidualPictures) {
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), 10);  // thermal angle drift
  DiagnoseOptions o;
  o.output_folder = std::string(RAMTK_TEST_OUTPUT_DIR) + "/robot_pictures";
  std::filesystem::remove_all(o.output_folder);
  const Diagnosis d = DiagnoseRobotData(draw.input, o);
  for (const char* f : {"residual_vs_time.png", "residual_vs_pose.png", "residual_vs_q2.png", "residual_vs_temp_j2.png",
                        "heldout_before_after.png", "drift_parameters.png"})
    EXPECT_TRUE(std::filesystem::exists(o.output_folder + "/" + f)) << f;
  EXPECT_GE(d.pictures.size(), 6u);
}

}  // namespace
}  // namespace ramtk::diagnose

namespace ramtk::diagnose {
namespace {

// An effect outside the catalogue: the sensor shifts along its X with a variable logged in an
// extra column (humidity, random from cycle to cycle). No candidate follows it; the report must
// not name a catalogue cause but point at the column.
// A real robot has several static errors at once: a joint zero, a link length and an axis twist
// hidden together are each named, each with its own held-out gain, and together they remove the
// excess (over several draws of which parameters and how much).
TEST(RobotDiagnosis, NamesThreeSimultaneousGeometricErrors) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const HiddenRobotDraw draw = DrawHiddenGeometricErrors(Kr150(), seed);  // a tracker over the workspace
    DiagnoseOptions o;
    o.noise = 0.01;  // the tracker's, known (one cycle: nothing to estimate it from)
    const Diagnosis d = DiagnoseRobotData(draw.input, o);
    std::set<std::string> named;
    for (const CauseStep& c : d.causes) {
      named.insert(c.effect);
      EXPECT_GT(c.excess_removed, 0.0) << c.effect;
      EXPECT_LT(c.rms_after, c.rms_before) << c.effect;
    }
    EXPECT_TRUE(named.count("joint_offset")) << draw.description << ": " << OneLine(d);
    EXPECT_TRUE(named.count("link_length_error")) << draw.description << ": " << OneLine(d);
    EXPECT_TRUE(named.count("axis_misalignment")) << draw.description << ": " << OneLine(d);
    EXPECT_GE(d.excess_removed, 0.9) << OneLine(d);
    EXPECT_NE(d.cause, kUnexplained) << OneLine(d);
  }
}

TEST(RobotDiagnosis, PointsAtTheExtraColumnWhenNoCatalogueEffectExplainsIt) {
  HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), 2);  // clean
  ASSERT_EQ(draw.effect, kNoEffect);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  std::map<int, double> humidity;
  for (auto& m : draw.input.ball.rows) {
    if (!humidity.count(m.cycle)) humidity[m.cycle] = 50.0 + 10.0 * n01(rng);
    m.extra["humidity"] = humidity[m.cycle];
    m.position_mm.x() += 0.01 * (humidity[m.cycle] - 50.0);  // 0.1 mm per 10 % RH
  }
  draw.input.ball.extra_columns.push_back("humidity");
  const Diagnosis d = DiagnoseRobotData(draw.input, DiagnoseOptions{});
  EXPECT_TRUE(d.structure_found);
  EXPECT_EQ(d.cause, kUnexplained);
  EXPECT_EQ(d.explaining_variable, "humidity");
}

}  // namespace
}  // namespace ramtk::diagnose

namespace ramtk::diagnose {
namespace {

// The thesis experiment with length drift only: the traditional model is then right, and the
// diagnosis must say so (5400 residuals per experiment). A rate over twelve seeds, not one chosen
// seed: the diagnoser's tests each run at α = 1e-3 over a few dozen statistics, so an occasional
// false alarm is expected; more than one in twelve (P ≈ 0.6 % at a 1 % per-experiment rate) is not.
TEST(RobotDiagnosis, ThesisCaseWithLengthDriftOnlyIsWhiteAtTheFalseAlarmRate) {
  const int kSeeds = 12;
  int false_alarms = 0;
  std::string report;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    thermal::ThermalSimOptions o = thermal::ThesisPreset(seed);
    std::vector<thermal::ParamDrift> lengths;
    for (const auto& d : o.drifts)
      if (!kinematics::IsAngleParam(d.param)) lengths.push_back(d);
    o.drifts = lengths;
    const thermal::ThermalSimResult sim = thermal::SimulateThermal(Kr150(), o);
    const Diagnosis d = DiagnoseRobotData(ThesisInput(sim, "thesis seed " + std::to_string(seed) + ", lengths only"),
                                          DiagnoseOptions{});
    if (d.cause != kNoEffect || d.structure_found) {
      ++false_alarms;
      report += "seed " + std::to_string(seed) + ": " + d.cause + "\n";
      for (const auto& f : d.findings) report += "  " + f + "\n";
    }
  }
  std::printf("length-drift-only thesis experiments: %d false alarms in %d seeds\n%s", false_alarms, kSeeds,
              report.c_str());
  EXPECT_LE(false_alarms, 1) << report;
}

}  // namespace
}  // namespace ramtk::diagnose
