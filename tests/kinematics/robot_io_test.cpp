// Robot model files: the shipped models against the thesis's table, round trips, and malformed
// files that must fail with the file, line and field named.
#include "ramtk/kinematics/robot_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "kdl_peer.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using testing::LoadShippedRobot;

TEST(RobotIo, Bx200lIsThesisTable21) {
  const RobotModel bx = LoadShippedRobot("kawasaki_bx200l.yaml");
  // Table 2-1 typed again here: d, θ0, a, α per joint.
  const double table[6][4] = {{530, 90, 200, -90}, {0, -90, 1160, 180}, {0, 0, 230, 90},
                              {1250, 0, 0, -90},   {0, 180, 0, -90},    {225, -90, 0, 0}};
  EXPECT_EQ(bx.convention, Convention::kDh);
  for (int j = 0; j < kNumJoints; ++j) {
    EXPECT_EQ(bx.links[j].d, table[j][0]);
    EXPECT_NEAR(RadToDeg(bx.links[j].theta0), table[j][1], 1e-12);
    EXPECT_EQ(bx.links[j].a, table[j][2]);
    EXPECT_NEAR(RadToDeg(bx.links[j].alpha), table[j][3], 1e-12);
    EXPECT_EQ(bx.links[j].beta, 0.0);
  }
  EXPECT_EQ(bx.mapping[0].sign, -1.0);
  EXPECT_EQ(bx.FreeParams().size(), 24u);  // DH: every β is structurally zero
}

TEST(RobotIo, ShippedKr150AndUr10Load) {
  const RobotModel kr = LoadShippedRobot("kuka_kr150_r3100.yaml");
  EXPECT_EQ(kr.convention, Convention::kMdh);
  EXPECT_EQ(kr.links[0].d, 675.0);
  EXPECT_EQ(kr.links[0].a, 350.0);
  EXPECT_EQ(kr.links[1].a, 1350.0);
  EXPECT_EQ(kr.links[2].a, 41.0);
  EXPECT_EQ(kr.links[3].d, 1400.0);
  EXPECT_EQ(kr.links[5].d, 240.0);
  const RobotModel ur = LoadShippedRobot("ur10.yaml");
  EXPECT_EQ(ur.links[1].a, -612.0);
  EXPECT_EQ(ur.links[3].d, 163.941);
}

TEST(RobotIo, WriteReadRoundTrip) {
  const RobotModel kr = testing::PerturbedModel(LoadShippedRobot("kuka_kr150_r3100.yaml"), 4, 1.0, 0.01);
  const std::string path = ::testing::TempDir() + "/kr_roundtrip.yaml";
  WriteRobotModel(kr, path);
  const RobotModel back = ReadRobotModel(path);
  std::remove(path.c_str());
  EXPECT_EQ(back.name, kr.name);
  EXPECT_LT((back.Params() - kr.Params()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(back.structural_zero, kr.structural_zero);
}

// Writes `text` to a file and returns the InputError message ReadRobotModel raises.
std::string ErrorFor(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name + ".yaml";
  {
    std::ofstream out(path);
    out << text;
  }
  try {
    ReadRobotModel(path);
  } catch (const InputError& e) {
    std::remove(path.c_str());
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << "file not named: " << e.what();
    return e.what();
  }
  std::remove(path.c_str());
  ADD_FAILURE() << "no error for " << name;
  return {};
}

const char* kGoodHeader = "name: test\nconvention: dh\njoints:\n";
const char* kJoint = "  - {d: 1, theta0: 0, a: 2, alpha: 90}\n";

std::string Joints(int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += kJoint;
  return s;
}

TEST(RobotIo, MalformedFilesNameFileLineAndField) {
  // Missing field: joint 3 without `a` (line 6 of the file).
  std::string text = std::string(kGoodHeader) + Joints(2) + "  - {d: 1, theta0: 0, alpha: 90}\n" + Joints(3);
  std::string msg = ErrorFor("missing_a", text);
  EXPECT_NE(msg.find(":6: field 'joints[3].a': missing"), std::string::npos) << msg;

  // Wrong joint count.
  msg = ErrorFor("five_joints", std::string(kGoodHeader) + Joints(5));
  EXPECT_NE(msg.find("field 'joints'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 6 joints, got 5"), std::string::npos) << msg;

  // Non-numeric value (line 8: joint 5).
  text = std::string(kGoodHeader) + Joints(4) + "  - {d: 1, theta0: 0, a: 2mm, alpha: 90}\n" + Joints(1);
  msg = ErrorFor("non_numeric", text);
  EXPECT_NE(msg.find(":8: field 'joints[5].a': expected a number, got '2mm'"), std::string::npos) << msg;

  // Unknown convention, missing name, bad sign, YAML syntax.
  msg = ErrorFor("convention", "name: t\nconvention: xyz\njoints:\n" + Joints(6));
  EXPECT_NE(msg.find(":2: field 'convention'"), std::string::npos) << msg;
  msg = ErrorFor("no_name", "convention: dh\njoints:\n" + Joints(6));
  EXPECT_NE(msg.find("field 'name': missing"), std::string::npos) << msg;
  msg = ErrorFor("sign", std::string(kGoodHeader) + "  - {d: 1, theta0: 0, a: 2, alpha: 90, sign: 2}\n" + Joints(5));
  EXPECT_NE(msg.find("field 'joints[1].sign': must be 1 or -1"), std::string::npos) << msg;
  msg = ErrorFor("syntax", "name: [unclosed\n");
  EXPECT_NE(msg.find("YAML syntax error"), std::string::npos) << msg;

  // MDH without the structural-zero list, with an unknown name, and with a non-zero β at a
  // structural zero.
  const std::string mdh = "name: t\nconvention: mdh\njoints:\n" + Joints(6);
  msg = ErrorFor("mdh_no_zeros", mdh);
  EXPECT_NE(msg.find("field 'structural_zeros': missing"), std::string::npos) << msg;
  msg = ErrorFor("mdh_bad_name", mdh + "structural_zeros: [beta1, gamma2]\n");
  EXPECT_NE(msg.find("field 'structural_zeros[1]': unknown parameter 'gamma2'"), std::string::npos) << msg;
  msg = ErrorFor("mdh_nonzero", "name: t\nconvention: mdh\njoints:\n  - {d: 1, theta0: 0, a: 2, alpha: 90, beta: 0.5}\n" +
                                    Joints(5) + "structural_zeros: [beta1]\n");
  EXPECT_NE(msg.find("field 'joints[1].beta': beta1 is a structural zero"), std::string::npos) << msg;
}

TEST(RobotIo, MissingFile) {
  try {
    ReadRobotModel("/nonexistent/robot.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/robot.yaml: cannot open robot model file: cannot open file: No such file or directory");
  }
}

}  // namespace
}  // namespace ramtk::kinematics
