// Adding a robot cause outside the table (docs/architecture.md, "Where to add things"): a test-only
// cause registered from this file, planted by the hidden-effect generator, named by the diagnosis
// with its coefficient recovered. Its own executable: the registration is process-wide.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"
#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/diagnose/robot/extra_cause.h"
#include "ramtk/diagnose/robot/robot.h"
#include "ramtk/diagnose/robot/robot_hidden.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::diagnose {
namespace {

constexpr double kCoefficientDeg = 0.03;  // planted: θ2 error = c·sin(q1)·cos(q4)

// A joint-2 error that follows joints 1 and 4 (no table cause has this shape): Δθ2 = c·sin q1·cos q4.
const RobotColumnCause& CrossCoupling() {
  static const RobotColumnCause cause = [] {
    RobotColumnCause c;
    c.info = {"test_cross_coupling", DataKind::kRobot, "joint 2 errs with sin(q1)·cos(q4) (test-only)", "c_deg",
              "none"};
    c.keys = {"c_deg"};
    c.factors = {180.0 / M_PI};
    const int theta2 = kinematics::ParamIndex(kinematics::ParamKind::kTheta, 1);
    c.columns = [theta2](const RobotCauseRow& r) {
      Eigen::Matrix<double, 3, Eigen::Dynamic> m(3, 1);
      m.col(0) = r.j_param.col(theta2) * std::sin(r.q[0]) * std::cos(r.q[3]);
      return m;
    };
    c.truth = {{"c_deg", kCoefficientDeg}};
    c.displacement = [](const RobotPlantRow& r) {
      kinematics::RobotModel bent = *r.model;
      bent.links[1].theta0 += kCoefficientDeg * M_PI / 180.0 * std::sin(r.q[0]) * std::cos(r.q[3]);
      return Eigen::Vector3d(kinematics::BaseFromFlange(bent, r.q) * r.ball_in_flange -
                             kinematics::BaseFromFlange(*r.model, r.q) * r.ball_in_flange);
    };
    return c;
  }();
  return cause;
}

const kinematics::RobotModel& Kr150() {
  static const kinematics::RobotModel m =
      kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
  return m;
}

TEST(RobotExtension, ARegisteredCauseIsPlantedNamedAndRecovered) {
  RegisterRobotCause(CrossCoupling());
  EXPECT_TRUE(IsKnownCause("test_cross_coupling"));
  HiddenRobotOptions o;
  o.effect = "test_cross_coupling";
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(Kr150(), 5, o);
  ASSERT_EQ(draw.effect, "test_cross_coupling");
  const Diagnosis d = DiagnoseRobotData(draw.input, DiagnoseOptions{});
  EXPECT_EQ(d.cause, "test_cross_coupling");
  ASSERT_TRUE(d.parameters.count("c_deg"));
  EXPECT_NEAR(d.parameters.at("c_deg"), kCoefficientDeg, 4.0 * d.sigmas.at("c_deg"));
  EXPECT_GE(d.excess_removed, 0.5);
  // The same draw without the cause planted: the diagnosis does not claim it.
  o.effect.clear();
  o.none_probability = 1.0;
  const Diagnosis clean = DiagnoseRobotData(DrawHiddenRobotEffect(Kr150(), 5, o).input, DiagnoseOptions{});
  EXPECT_EQ(clean.cause, kNoEffect);
}

TEST(RobotExtension, RegisteringANameTwiceOrAnInvalidCauseIsAnError) {
  RobotColumnCause twice = CrossCoupling();
  twice.info.name = "joint_offset";
  EXPECT_THROW(RegisterRobotCause(twice), InputError);
  RobotColumnCause bad = CrossCoupling();
  bad.info.name = "test_without_columns";
  bad.columns = nullptr;
  EXPECT_THROW(RegisterRobotCause(bad), InputError);
}

// A robot the project does not ship: one YAML file (a KR120-class arm, the KR150's layout with other
// dimensions) is all the diagnosis needs.
TEST(RobotExtension, ANewRobotIsOneYamlFile) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "ramtk_test_kr120_like.yaml";
  std::ofstream(path) << "name: test KR120-class arm\n"
                         "convention: mdh\n"
                         "joints:\n"
                         "  - {d: 650,  theta0: 0,   a: 320,  alpha: -90, beta: 0, sign: -1, offset: 0}\n"
                         "  - {d: 0,    theta0: 0,   a: 1150, alpha: 0,   beta: 0, sign: 1,  offset: 0}\n"
                         "  - {d: 0,    theta0: -90, a: 35,   alpha: -90, beta: 0, sign: 1,  offset: 0}\n"
                         "  - {d: 1200, theta0: 0,   a: 0,    alpha: 90,  beta: 0, sign: 1,  offset: 0}\n"
                         "  - {d: 0,    theta0: 0,   a: 0,    alpha: -90, beta: 0, sign: 1,  offset: 0}\n"
                         "  - {d: 215,  theta0: 0,   a: 0,    alpha: 0,   beta: 0, sign: 1,  offset: 0}\n"
                         "structural_zeros: [beta1, d2, beta3, beta4, beta5, beta6]\n";
  const kinematics::RobotModel robot = kinematics::ReadRobotModel(path.string());
  HiddenRobotOptions o;
  o.effect = "joint_offset";
  const HiddenRobotDraw draw = DrawHiddenRobotEffect(robot, 3, o);
  const Diagnosis d = DiagnoseRobotData(draw.input, DiagnoseOptions{});
  SCOPED_TRACE(draw.description);
  EXPECT_EQ(d.cause, "joint_offset");
  const auto& [key, truth] = *draw.truth.begin();
  ASSERT_TRUE(d.parameters.count(key)) << key;
  EXPECT_NEAR(d.parameters.at(key), truth, 4.0 * d.sigmas.at(key));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ramtk::diagnose
