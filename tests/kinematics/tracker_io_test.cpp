#include "ramtk/kinematics/tracker_io.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

using Eigen::AngleAxisd;

// The message of the InputError `f` throws ("" if it throws none).
std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TrackerMeasurements Parse(const std::string& text, const TrackerFormat& format = {}) {
  return ParseTrackerMeasurements(text, "t.csv", format);
}

// Collects the log's warnings while alive.
class WarningLog {
 public:
  WarningLog() {
    SetLogSink([this](LogLevel level, const std::string& m) {
      if (level == LogLevel::kWarning) messages.push_back(m);
    });
  }
  ~WarningLog() { SetLogSink({}); }
  std::vector<std::string> messages;
};

// A double written so that it reads back exactly.
std::string Exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

double MaxDiff(const Mat3& a, const Mat3& b) { return (a - b).cwiseAbs().maxCoeff(); }

// ---------------------------------------------------------------------------------------------
// Dialects and column layouts.

TEST(TrackerIo, DefaultNamesCommaSeparated) {
  const auto m = Parse(
      "# a comment line\n"
      "q1,q2,q3,q4,q5,q6,x,y,z,extra\n"
      "10,-20,30,0,45,90,1000.5,-2.25,3e2,note\n"
      "\n"
      "0,0,0,0,0,-1079,1,2,3,other\n");
  EXPECT_EQ(m.num_joints, 6);
  EXPECT_EQ(m.target_names, std::vector<std::string>{"x"});
  EXPECT_FALSE(m.has_rotation);
  ASSERT_EQ(m.poses.size(), 2u);
  EXPECT_EQ(m.poses[0].line, 3);
  EXPECT_EQ(m.poses[1].line, 5);
  EXPECT_DOUBLE_EQ(m.poses[0].q_rad[0], DegToRad(10));
  EXPECT_DOUBLE_EQ(m.poses[0].q_rad[1], DegToRad(-20));
  EXPECT_DOUBLE_EQ(m.poses[1].q_rad[5], DegToRad(-1079));
  ASSERT_EQ(m.poses[0].targets.size(), 1u);
  EXPECT_EQ(m.poses[0].targets[0].position_mm, Vec3(1000.5, -2.25, 300));
  EXPECT_FALSE(m.poses[0].targets[0].has_covariance);
  EXPECT_FALSE(m.poses[0].tracker_from_tool_rotation.has_value());
  EXPECT_TRUE(m.poses[0].references_mm.empty());
  EXPECT_EQ(m.poses[1].time_s, 0.0);
}

TEST(TrackerIo, SemicolonWithDecimalCommaIsDetected) {
  // As spreadsheets in a comma-decimal locale write them: BOM, CRLF, no final newline.
  const std::string text = "\xEF\xBB\xBFq1;q2;x;y;z\r\n1,5;0;1234,5678;-0,25;7\r\n2;-3,25;1;2;3";
  const auto m = Parse(text);
  EXPECT_EQ(m.num_joints, 2);
  ASSERT_EQ(m.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(m.poses[0].q_rad[0], DegToRad(1.5));
  EXPECT_EQ(m.poses[0].targets[0].position_mm, Vec3(1234.5678, -0.25, 7));
  EXPECT_DOUBLE_EQ(m.poses[1].q_rad[1], DegToRad(-3.25));
  // Given instead of detected: the same.
  TrackerFormat f;
  f.separator = ';';
  f.decimal = ',';
  EXPECT_EQ(Parse(text, f).poses[0].targets[0].position_mm, Vec3(1234.5678, -0.25, 7));
  // `;` with decimal points (no comma in any number cell) is detected as well.
  const auto points = Parse("q1;x;y;z\n1.5;1;2.5;3\n");
  EXPECT_EQ(points.poses[0].targets[0].position_mm, Vec3(1, 2.5, 3));
  // A point in a decimal-comma file is not taken for a decimal mark (it may be a thousands mark).
  EXPECT_EQ(ErrorOf([&] { Parse("q1;x;y;z\n1,5;1.000,5;2;3\n"); }),
            "t.csv:2: field 'x': expected a number, got '1.000,5' (decimal mark ',')");
}

TEST(TrackerIo, TabSeparatedAndQuotedCells) {
  const auto tab = Parse("q1\tq2\tx\ty\tz\n1\t2\t3\t4\t5\n");
  EXPECT_EQ(tab.poses[0].targets[0].position_mm, Vec3(3, 4, 5));
  const auto quoted = Parse("q1,\"x\",y,z,note\n1,2,3,4,\"a, b \"\"c\"\"\"\n");
  EXPECT_EQ(quoted.poses[0].targets[0].position_mm, Vec3(2, 3, 4));
}

TEST(TrackerIo, UnitsMetreAndRadian) {
  TrackerFormat f;
  f.joint_unit = AngleUnit::kRadian;
  f.length_unit = LengthUnit::kMetre;
  f.sigma_columns = {"sx", "sy", "sz"};
  const auto m = Parse("q1,x,y,z,sx,sy,sz\n1.25,1.5,-0.002,0.25,1e-5,2e-5,3e-5\n", f);
  EXPECT_EQ(m.poses[0].q_rad[0], 1.25);
  EXPECT_NEAR((m.poses[0].targets[0].position_mm - Vec3(1500, -2, 250)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(m.poses[0].targets[0].has_covariance);
  EXPECT_NEAR(m.poses[0].targets[0].covariance_mm2(0, 0), 1e-4, 1e-18);  // (0.01 mm)²
  EXPECT_NEAR(m.poses[0].targets[0].covariance_mm2(2, 2), 9e-4, 1e-18);
  EXPECT_EQ(m.poses[0].targets[0].covariance_mm2(0, 1), 0.0);
}

TEST(TrackerIo, SeveralTargetsAsColumnGroups) {
  const auto m = Parse(
      "q1,q2,x1,y1,z1,x2,y2,z2,x3,y3,z3,sx1,sy1,sz1,sx2,sy2,sz2,sx3,sy3,sz3\n"
      "1,2,10,11,12,20,21,22,30,31,32,0.01,0.02,0.03,0.1,0.2,0.3,1,2,3\n");
  EXPECT_EQ(m.target_names, (std::vector<std::string>{"x1", "x2", "x3"}));
  ASSERT_EQ(m.poses.size(), 1u);
  ASSERT_EQ(m.poses[0].targets.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const TargetMeasurement& t = m.poses[0].targets[k];
    EXPECT_EQ(t.target, k);
    EXPECT_EQ(t.position_mm, Vec3(10 * (k + 1), 10 * (k + 1) + 1, 10 * (k + 1) + 2));
    EXPECT_TRUE(t.has_covariance);
    const double s = std::pow(10.0, k - 2);
    EXPECT_NEAR(t.covariance_mm2(1, 1), 4 * s * s, 1e-15);
  }
  // Named groups and a full covariance per target.
  TrackerFormat f;
  f.joint_columns = {"j1"};
  f.position_columns = {"ax", "ay", "az", "bx", "by", "bz"};
  f.covariance_columns = {"a_xx", "a_yy", "a_zz", "a_xy", "a_xz", "a_yz",
                          "b_xx", "b_yy", "b_zz", "b_xy", "b_xz", "b_yz"};
  const std::string header = "j1,ax,ay,az,bx,by,bz,a_xx,a_yy,a_zz,a_xy,a_xz,a_yz,b_xx,b_yy,b_zz,b_xy,b_xz,b_yz\n";
  const auto c = Parse(header + "0,1,2,3,4,5,6,4,9,16,1,-2,3,1,1,1,0,0,0\n", f);
  EXPECT_EQ(c.target_names, (std::vector<std::string>{"ax", "bx"}));
  Mat3 expected;
  expected << 4, 1, -2, 1, 9, 3, -2, 3, 16;
  EXPECT_EQ(c.poses[0].targets[0].covariance_mm2, expected);
  EXPECT_EQ(c.poses[0].targets[1].covariance_mm2, Mat3::Identity());
  // A covariance that is not positive definite (correlation 1.5).
  EXPECT_EQ(ErrorOf([&] { Parse(header + "0,1,2,3,4,5,6,4,9,16,9,0,0,1,1,1,0,0,0\n", f); }),
            "t.csv:2: field 'a_xy': the covariance is not positive definite (a correlation of magnitude >= 1)");
}

TEST(TrackerIo, OneTargetPerRowGroupedByPose) {
  TrackerFormat f;
  f.target_column = "target";
  const std::string header = "pose,target,q1,q2,x,y,z\n";
  const auto m = Parse(header +
                           "1,A,10,20,1,2,3\n"
                           "1,B,10,20,4,5,6\n"
                           "2,B,11,20,7,8,9\n"
                           "2,C,11,20,10,11,12\n"
                           "2,A,11,20,13,14,15\n"
                           "1,A,10,20,16,17,18\n",  // pose 1 again, not consecutive: a new pose
                       f);
  EXPECT_EQ(m.target_names, (std::vector<std::string>{"A", "B", "C"}));
  ASSERT_EQ(m.poses.size(), 3u);
  EXPECT_EQ(m.poses[0].line, 2);
  EXPECT_EQ(m.poses[1].line, 4);
  EXPECT_EQ(m.poses[2].line, 7);
  ASSERT_EQ(m.poses[1].targets.size(), 3u);
  EXPECT_EQ(m.poses[1].targets[0].target, 1);  // B
  EXPECT_EQ(m.poses[1].targets[1].target, 2);  // C
  EXPECT_EQ(m.poses[1].targets[2].target, 0);  // A
  EXPECT_EQ(m.poses[1].targets[2].position_mm, Vec3(13, 14, 15));
  EXPECT_DOUBLE_EQ(m.poses[1].q_rad[0], DegToRad(11));
  EXPECT_EQ(m.poses[2].targets.size(), 1u);

  // Joints of one pose must agree.
  EXPECT_EQ(ErrorOf([&] { Parse(header + "1,A,10,20,1,2,3\n1,B,10,20.001,4,5,6\n", f); }),
            "t.csv:3: field 'q2': joint differs from the same pose's first row (line 2): the rows of one pose must "
            "have the same joints");
  EXPECT_EQ(ErrorOf([&] { Parse(header + "1,A,10,20,1,2,3\n1,A,10,20,4,5,6\n", f); }),
            "t.csv:3: field 'target': target 'A' appears twice in the pose starting at line 2");
  // A named pose column; without one the rows cannot be grouped.
  f.pose_column = "station";
  EXPECT_EQ(Parse("station,target,q1,x,y,z\ns1,T,0,1,2,3\ns1,U,0,1,2,3\n", f).poses.size(), 1u);
  EXPECT_EQ(ErrorOf([&] { Parse("target,q1,x,y,z\nT,0,1,2,3\n", f); }),
            "t.csv:1: field 'station': missing column (pose_column: the rows of one pose share it; the header has 5 "
            "columns)");
}

TEST(TrackerIo, CycleColumnSplitsPoses) {
  TrackerFormat f;
  f.target_column = "target";
  const auto m = Parse("cycle,pose,target,q1,x,y,z\n0,1,A,0,1,2,3\n1,1,A,0,1,2,3\n1,1,B,0,1,2,3\n", f);
  ASSERT_EQ(m.poses.size(), 2u);
  EXPECT_EQ(m.poses[0].cycle, 0);
  EXPECT_EQ(m.poses[1].cycle, 1);
  EXPECT_EQ(m.poses[1].targets.size(), 2u);
  EXPECT_EQ(ErrorOf([] { Parse("cycle,q1,x,y,z\n1.5,0,1,2,3\n"); }),
            "t.csv:2: field 'cycle': expected an integer, got '1.5'");
}

// ---------------------------------------------------------------------------------------------
// 6-D poses: each form against a rotation built without the reader's code.

TEST(TrackerIo, QuaternionAgainstHandComputedRotation) {
  // A rotation of θ about the unit axis u: q = (cos θ/2, sin θ/2 · u), and Rodrigues' formula
  // R = I + sin θ [u]× + (1 − cos θ) [u]×², written out by hand.
  const double theta = 0.7;
  const Vec3 u = Vec3(1, 2, 2) / 3.0;
  const double w = std::cos(theta / 2), s = std::sin(theta / 2);
  Mat3 k;
  k << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  const Mat3 expected = Mat3::Identity() + std::sin(theta) * k + (1 - std::cos(theta)) * k * k;
  TrackerFormat f;
  f.rotation = RotationForm::kQuaternion;
  // Scaled by 1.05: normalised on reading.
  const double g = 1.05;
  const std::string text = "q1,x,y,z,qx,qy,qz,qw\n0,1,2,3," + Exact(g * s * u.x()) + "," + Exact(g * s * u.y()) + "," +
                           Exact(g * s * u.z()) + "," + Exact(g * w) + "\n";
  const auto m = Parse(text, f);
  EXPECT_TRUE(m.has_rotation);
  ASSERT_TRUE(m.poses[0].tracker_from_tool_rotation.has_value());
  EXPECT_LT(MaxDiff(*m.poses[0].tracker_from_tool_rotation, expected), 1e-12);
  EXPECT_EQ(m.poses[0].targets[0].position_mm, Vec3(1, 2, 3));  // the 6-D pose's position
  // Named columns in a different order in the file; the format gives qx,qy,qz,qw order.
  f.rotation_columns = {"i", "j", "k", "r"};
  const auto named = Parse("r,k,j,i,q1,x,y,z\n" + Exact(w) + "," + Exact(s * u.z()) + "," + Exact(s * u.y()) + "," +
                               Exact(s * u.x()) + ",0,1,2,3\n",
                           f);
  EXPECT_LT(MaxDiff(*named.poses[0].tracker_from_tool_rotation, expected), 1e-12);
  // |q| = 1.2 is no unit quaternion.
  EXPECT_EQ(ErrorOf([&] { Parse("r,k,j,i,q1,x,y,z\n1.2,0,0,0,0,1,2,3\n", f); }),
            "t.csv:2: field 'i,j,k,r': quaternion norm 1.200000 is not near 1 (expected 0.9..1.1)");
}

TEST(TrackerIo, KukaAbcAgainstAngleAxisProduct) {
  const double a = 0.3, b = -1.1, c = 2.5;
  const Mat3 expected =
      (AngleAxisd(a, Vec3::UnitZ()) * AngleAxisd(b, Vec3::UnitY()) * AngleAxisd(c, Vec3::UnitX())).toRotationMatrix();
  TrackerFormat f;
  f.rotation = RotationForm::kKukaAbc;
  const auto deg = Parse(
      "q1,x,y,z,a,b,c\n0,1,2,3," + Exact(RadToDeg(a)) + "," + Exact(RadToDeg(b)) + "," + Exact(RadToDeg(c)) + "\n", f);
  EXPECT_LT(MaxDiff(*deg.poses[0].tracker_from_tool_rotation, expected), 1e-12);
  f.rotation_unit = AngleUnit::kRadian;
  const auto rad = Parse("q1,x,y,z,a,b,c\n0,1,2,3," + Exact(a) + "," + Exact(b) + "," + Exact(c) + "\n", f);
  EXPECT_LT(MaxDiff(*rad.poses[0].tracker_from_tool_rotation, expected), 1e-12);
}

TEST(TrackerIo, EulerXyzAgainstAngleAxisProduct) {
  // About the new axes (scipy's 'XYZ'): R = Rx(rx)·Ry(ry)·Rz(rz).
  const double rx = -1.578, ry = -1.045, rz = -1.586;
  const Mat3 expected = (AngleAxisd(rx, Vec3::UnitX()) * AngleAxisd(ry, Vec3::UnitY()) * AngleAxisd(rz, Vec3::UnitZ()))
                            .toRotationMatrix();
  TrackerFormat f;
  f.rotation = RotationForm::kEulerXyz;
  const auto m = Parse("q1,x,y,z,rx,ry,rz\n0,1,2,3," + Exact(RadToDeg(rx)) + "," + Exact(RadToDeg(ry)) + "," +
                           Exact(RadToDeg(rz)) + "\n",
                       f);
  EXPECT_LT(MaxDiff(*m.poses[0].tracker_from_tool_rotation, expected), 1e-12);
  // Not the fixed-axes order Rz·Ry·Rx.
  const Mat3 fixed = (AngleAxisd(rz, Vec3::UnitZ()) * AngleAxisd(ry, Vec3::UnitY()) * AngleAxisd(rx, Vec3::UnitX()))
                         .toRotationMatrix();
  EXPECT_GT(MaxDiff(*m.poses[0].tracker_from_tool_rotation, fixed), 0.1);
}

TEST(TrackerIo, MatrixIsCheckedAndProjected) {
  const Mat3 r = (AngleAxisd(0.4, Vec3(1, -1, 3).normalized()) * AngleAxisd(-2.0, Vec3::UnitY())).toRotationMatrix();
  TrackerFormat f;
  f.rotation = RotationForm::kMatrix;
  auto text = [&](const Mat3& m) {
    std::string t = "q1,x,y,z,r11,r12,r13,r21,r22,r23,r31,r32,r33\n0,1,2,3";
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) t += "," + Exact(m(i, j));
    }
    return t + "\n";
  };
  EXPECT_LT(MaxDiff(*Parse(text(r), f).poses[0].tracker_from_tool_rotation, r), 1e-12);
  // Six printed digits: projected back onto a rotation, within the printing error.
  Mat3 rounded = r;
  rounded(0, 1) += 4e-6;
  rounded(2, 2) -= 3e-6;
  const Mat3 projected = *Parse(text(rounded), f).poses[0].tracker_from_tool_rotation;
  EXPECT_LT((projected.transpose() * projected - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(projected.determinant(), 1.0, 1e-12);
  EXPECT_LT(MaxDiff(projected, r), 1e-5);
  // A scaled matrix is no rotation.
  EXPECT_EQ(ErrorOf([&] { Parse(text(1.01 * r), f); })
                .rfind("t.csv:2: field 'r11,r12,r13,r21,r22,r23,r31,r32,r33': not a rotation matrix: orthonormality "
                       "error 0.0303",
                       0),
            0u);
}

// ---------------------------------------------------------------------------------------------
// Time.

TEST(TrackerIo, UnixSecondsIsoAndCompactTimes) {
  // Unix seconds, beyond 1e9 and up to 1e10 and more.
  const auto unix_s = Parse("time_s,q1,x,y,z\n1594744744.25,0,1,2,3\n1594744754.5,0,1,2,3\n");
  EXPECT_EQ(unix_s.first_time_unix_s, 1594744744.25);
  EXPECT_NEAR(unix_s.poses[1].time_s, 10.25, 1e-6);
  const auto far = Parse("time_s,q1,x,y,z\n1e10,0,1,2,3\n2e11,0,1,2,3\n");
  EXPECT_EQ(far.first_time_unix_s, 1e10);
  EXPECT_EQ(far.poses[1].time_s, 2e11 - 1e10);
  // Relative seconds: no absolute time.
  const auto relative = Parse("time_s,q1,x,y,z\n5,0,1,2,3\n7.5,0,1,2,3\n");
  EXPECT_EQ(relative.first_time_unix_s, 0.0);
  EXPECT_EQ(relative.poses[0].time_s, 0.0);
  EXPECT_EQ(relative.poses[1].time_s, 2.5);

  // ISO 8601: 2020-07-14T16:39:04Z is unix 1594744744 (Python's datetime agrees).
  TrackerFormat f;
  f.time_column = "when";
  const auto iso = Parse(
      "when,q1,x,y,z\n"
      "2020-07-14T16:39:04,0,1,2,3\n"
      "2020-07-14T16:39:05.125Z,0,1,2,3\n"
      "2020-07-14T18:39:06+02:00,0,1,2,3\n"
      "2020-07-14 14:39:07.5-0200,0,1,2,3\n"
      "2021-01-01T00:00:00Z,0,1,2,3\n",
      f);
  EXPECT_EQ(iso.first_time_unix_s, 1594744744.0);
  EXPECT_DOUBLE_EQ(iso.poses[1].time_s, 1.125);
  EXPECT_DOUBLE_EQ(iso.poses[2].time_s, 2.0);
  EXPECT_DOUBLE_EQ(iso.poses[3].time_s, 3.5);
  EXPECT_DOUBLE_EQ(iso.poses[4].time_s, 1609459200.0 - 1594744744.0);

  // Compact yyyymmddHHMMSS (Series A of the IPA data): across midnight and a month end.
  f.time_column = "Timestamp";
  const auto compact = Parse(
      "Timestamp,q1,x,y,z\n20200714163904,0,1,2,3\n20200715050127,0,1,2,3\n"
      "20200801000000,0,1,2,3\n",
      f);
  EXPECT_EQ(compact.first_time_unix_s, 1594744744.0);
  EXPECT_EQ(compact.poses[1].time_s, 44543.0);
  EXPECT_EQ(compact.poses[2].time_s, 1596240000.0 - 1594744744.0);

  // Bad cells name the line and column.
  EXPECT_EQ(ErrorOf([&] { Parse("Timestamp,q1,x,y,z\n20200714163904,0,1,2,3\n20201314163904,0,1,2,3\n", f); }),
            "t.csv:3: field 'Timestamp': expected a yyyymmddHHMMSS time (20200714163904), got '20201314163904'");
  f.time_column = "when";
  EXPECT_EQ(ErrorOf([&] { Parse("when,q1,x,y,z\n2020-07-14T16:39:04,0,1,2,3\n2020-02-30T00:00:00,0,1,2,3\n", f); }),
            "t.csv:3: field 'when': expected an ISO 8601 time (2020-07-14T16:39:04[.fff][Z|+hh:mm]), got "
            "'2020-02-30T00:00:00'");
  EXPECT_EQ(ErrorOf([] { Parse("time_s,q1,x,y,z\n2e12,0,1,2,3\n"); }),
            "t.csv:2: field 'time_s': value 2e12 is beyond the plausible range +-1e+12 s (kTrackerMaxAbsTimeS)");
  // An explicitly named time column must exist.
  EXPECT_EQ(ErrorOf([&] { Parse("q1,x,y,z\n0,1,2,3\n", f); }),
            "t.csv:1: field 'when': missing column (time_column; the header has 4 columns)");
}

TEST(TrackerIo, TimeGoingBackwardsIsAWarning) {
  WarningLog log;
  const auto m = Parse("time_s,q1,x,y,z\n10,0,1,2,3\n12,0,1,2,3\n11,0,1,2,3\n13,0,1,2,3\n9,0,1,2,3\n");
  EXPECT_EQ(m.poses[2].time_s, 1.0);
  EXPECT_EQ(m.poses[4].time_s, -1.0);
  ASSERT_EQ(log.messages.size(), 1u);
  EXPECT_EQ(log.messages[0], "t.csv:4: column 'time_s': the time goes backwards (2 times in the file)");
}

TEST(TrackerIo, StampRoundedBySpreadsheet) {
  // Series B/C/D of the IPA data: 20201104123456 became 2,02011E+13 (six digits): the time is gone.
  const std::string text = "Timestamp;q1;x;y;z\n2,02011E+13;0;1;2;3\n2,02011E+13;0;1;2;3\n";
  TrackerFormat f;
  f.time_column = "Timestamp";
  {
    WarningLog log;
    const auto m = Parse(text, f);  // time_form auto: a warning, times 0
    ASSERT_EQ(m.poses.size(), 2u);
    EXPECT_EQ(m.poses[1].time_s, 0.0);
    EXPECT_EQ(m.first_time_unix_s, 0.0);
    ASSERT_EQ(log.messages.size(), 1u);
    EXPECT_NE(log.messages[0].find("t.csv:2: column 'Timestamp': '2,02011E+13' looks like a yyyymmddHHMMSS"),
              std::string::npos);
  }
  f.time_form = "yyyymmddhhmmss";  // asked for: an error
  EXPECT_EQ(ErrorOf([&] { Parse(text, f); }),
            "t.csv:2: field 'Timestamp': expected a yyyymmddHHMMSS time (20200714163904), got '2,02011E+13': a "
            "spreadsheet rounded the stamp to a number and the seconds are lost");
  f.time_form = "seconds";
  EXPECT_NE(ErrorOf([&] { Parse(text, f); }).find("beyond the plausible range"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Malformed files.

TEST(TrackerIo, MalformedFilesNameFileLineAndColumn) {
  EXPECT_EQ(ErrorOf([] { Parse(""); }), "t.csv: empty file: expected a header row");
  EXPECT_EQ(ErrorOf([] { Parse("# only a comment\n\n"); }), "t.csv: empty file: expected a header row");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n"); }), "t.csv:1: no data rows after the header");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,2,3\n0,1,2\n"); }),
            "t.csv:3: expected 4 cells as in the header, got 3 (separator ',')");
  EXPECT_EQ(ErrorOf([] { Parse("q1;x;y;z\n0;1;2;3;4\n"); }),
            "t.csv:2: expected 4 cells as in the header, got 5 (separator ';')");
  EXPECT_EQ(ErrorOf([] { Parse("a,x,y,z\n0,1,2,3\n"); }),
            "t.csv:1: field 'q1': missing column: no joint columns (q1..qN by default; name them with joint_columns)");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y\n0,1,2\n"); }),
            "t.csv:1: field 'z': missing column (position_columns; the header has 3 columns)");
  TrackerFormat f;
  f.joint_columns = {"j1", "j2"};
  EXPECT_EQ(ErrorOf([&] { Parse("j1,x,y,z\n0,1,2,3\n", f); }),
            "t.csv:1: field 'j2': missing column (joint_columns; the header has 4 columns)");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,zz,3\n"); }), "t.csv:2: field 'y': expected a number, got 'zz'");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,,3\n"); }), "t.csv:2: field 'y': expected a number, got an empty cell");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,nan,3\n"); }), "t.csv:2: field 'y': expected a finite number, got 'nan'");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,inf,3\n"); }), "t.csv:2: field 'y': expected a finite number, got 'inf'");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n0,1,100001,3\n"); }),
            "t.csv:2: field 'y': value 100001 is beyond the plausible range +-100000 mm (kTrackerMaxAbsPositionMm)");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z\n1080.1,1,2,3\n"); }),
            "t.csv:2: field 'q1': value 1080.1 is beyond the plausible range +-18.8496 rad (kTrackerMaxAbsJointRad)");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z,sx,sy,sz\n0,1,2,3,0.1,0,0.1\n"); }),
            "t.csv:2: field 'sy': a standard deviation must be > 0, got 0");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z,sx,sy\n0,1,2,3,0.1,0.1\n"); }),
            "t.csv:1: field 'sz': missing column: the default sigma columns come as a set");
  EXPECT_EQ(ErrorOf([] { Parse("q1,x,y,z,x\n0,1,2,3,4\n"); }),
            "t.csv:1: field 'x': column name appears twice in the header");
  // A reference beyond the limit, in metres.
  TrackerFormat m;
  m.length_unit = LengthUnit::kMetre;
  m.reference_columns = {"rx", "ry", "rz"};
  EXPECT_EQ(ErrorOf([&] { Parse("q1,x,y,z,rx,ry,rz\n0,1,2,3,0,101,0\n", m); }),
            "t.csv:2: field 'ry': value 101 is beyond the plausible range +-100000 mm (kTrackerMaxAbsPositionMm)");
  // Invalid options are named before the file is read.
  TrackerFormat bad;
  bad.position_columns = {"x", "y"};
  EXPECT_EQ(ErrorOf([&] { Parse("q1,x,y\n0,1,2\n", bad); }),
            "field 'position_columns': expected three columns (x,y,z) per target, got 2");
}

TEST(TrackerIo, ReadsFromFile) {
  const std::string path = ::testing::TempDir() + "/tracker_io_test.csv";
  WriteFileAtomically(path, "q1,x,y,z\n1,2,3,4\n");
  const auto m = ReadTrackerMeasurements(path);
  EXPECT_EQ(m.poses[0].targets[0].position_mm, Vec3(2, 3, 4));
  WriteFileAtomically(path, "q1,x,y,z\n1,2,zz,4\n");
  EXPECT_EQ(ErrorOf([&] { ReadTrackerMeasurements(path); }), path + ":2: field 'y': expected a number, got 'zz'");
  std::remove(path.c_str());
}

// ---------------------------------------------------------------------------------------------
// The format file.

TEST(TrackerIo, FormatYamlAllKeys) {
  const TrackerFormat f = ParseTrackerFormat(
      "separator: \";\"\n"
      "decimal: \",\"\n"
      "joint_columns: [j1, j2]\n"
      "joint_unit: rad\n"
      "position_columns: [px, py, pz]\n"
      "length_unit: m\n"
      "target_column: name\n"
      "pose_column: station\n"
      "rotation: quaternion\n"
      "rotation_columns: [a, b, c, d]\n"
      "rotation_unit: rad\n"
      "covariance_columns: [c1, c2, c3, c4, c5, c6]\n"
      "reference_columns: [r1, r2, r3, r4, r5, r6]\n"
      "time_column: Timestamp\n"
      "time_form: yyyymmddhhmmss\n"
      "cycle_column: run\n",
      "f.yaml");
  EXPECT_EQ(f.separator, ';');
  EXPECT_EQ(f.decimal, ',');
  EXPECT_EQ(f.joint_columns, (std::vector<std::string>{"j1", "j2"}));
  EXPECT_EQ(f.joint_unit, AngleUnit::kRadian);
  EXPECT_EQ(f.position_columns, (std::vector<std::string>{"px", "py", "pz"}));
  EXPECT_EQ(f.length_unit, LengthUnit::kMetre);
  EXPECT_EQ(f.target_column, "name");
  EXPECT_EQ(f.pose_column, "station");
  EXPECT_EQ(f.rotation, RotationForm::kQuaternion);
  EXPECT_EQ(f.rotation_columns.size(), 4u);
  EXPECT_EQ(f.rotation_unit, AngleUnit::kRadian);
  EXPECT_EQ(f.covariance_columns.size(), 6u);
  EXPECT_EQ(f.reference_columns.size(), 6u);
  EXPECT_EQ(f.time_column, "Timestamp");
  EXPECT_EQ(f.time_form, "yyyymmddhhmmss");
  EXPECT_EQ(f.cycle_column, "run");
  EXPECT_EQ(ParseTrackerFormat("separator: tab\nsigma_columns: [a, b, c]\n", "f.yaml").separator, '\t');
  EXPECT_EQ(ParseTrackerFormat("", "f.yaml").separator, 0);  // all defaults
  EXPECT_EQ(ParseTrackerFormat("rotation: kuka_abc\n", "f.yaml").rotation, RotationForm::kKukaAbc);
  EXPECT_EQ(ParseTrackerFormat("rotation: euler_xyz\n", "f.yaml").rotation, RotationForm::kEulerXyz);
  EXPECT_EQ(ParseTrackerFormat("rotation: matrix\n", "f.yaml").rotation, RotationForm::kMatrix);
}

TEST(TrackerIo, FormatYamlErrorsNameLineAndKey) {
  auto error = [](const std::string& yaml) { return ErrorOf([&] { ParseTrackerFormat(yaml, "f.yaml"); }); };
  EXPECT_EQ(error("joint_unit: rad\njoint_colums: [a]\n"),
            "f.yaml:2: field 'joint_colums': unknown key (expected separator, decimal, joint_columns, joint_unit, "
            "position_columns, length_unit, target_column, pose_column, rotation, rotation_columns, rotation_unit, "
            "sigma_columns, covariance_columns, reference_columns, time_column, time_form, cycle_column)");
  EXPECT_EQ(error("\njoint_unit: grad\n"), "f.yaml:2: field 'joint_unit': expected 'deg' or 'rad', got 'grad'");
  EXPECT_EQ(error("length_unit: inch\n"), "f.yaml:1: field 'length_unit': expected 'mm' or 'm', got 'inch'");
  EXPECT_EQ(error("rotation: rpy\n"),
            "f.yaml:1: field 'rotation': expected none, quaternion, kuka_abc, euler_xyz or matrix, got 'rpy'");
  EXPECT_EQ(error("joint_columns: q1\n"), "f.yaml:1: field 'joint_columns': expected a list of column names");
  EXPECT_EQ(error("separator: \"::\"\n"), "f.yaml:1: field 'separator': expected ',', ';', tab, '|' or auto, got '::'");
  // Validate's problems are placed at their key's line.
  EXPECT_EQ(error("rotation: quaternion\nrotation_columns: [a, b, c]\n"),
            "f.yaml:2: field 'rotation_columns': expected 4 columns for this rotation form, got 3");
  EXPECT_EQ(error("separator: \",\"\ndecimal: \",\"\n"),
            "f.yaml:2: field 'decimal': the decimal mark ',' cannot also be the separator");
  EXPECT_EQ(error("time_form: unix\n"),
            "f.yaml:1: field 'time_form': expected auto, seconds, iso8601 or yyyymmddhhmmss, got 'unix'");
  EXPECT_EQ(error("- a\n- b\n"), "f.yaml:1: expected a YAML mapping at the top level");
  EXPECT_EQ(error("joint_columns: [a, b\n").rfind("f.yaml:", 0), 0u);
  EXPECT_NE(error("joint_columns: [a, b\n").find("YAML syntax error"), std::string::npos);
}

TEST(TrackerIo, ValidateNamesTheField) {
  TrackerFormat f;
  EXPECT_EQ(f.Validate(), "");
  f.sigma_columns = {"a", "b", "c"};
  f.covariance_columns = {"1", "2", "3", "4", "5", "6"};
  EXPECT_EQ(f.Validate(), "sigma_columns: give sigma_columns or covariance_columns, not both");
  f = {};
  f.pose_column = "pose";
  EXPECT_EQ(f.Validate(), "pose_column: only used with target_column (one target per row)");
  f = {};
  f.rotation_columns = {"a", "b", "c"};
  EXPECT_EQ(f.Validate(), "rotation_columns: given without a rotation form (rotation: none)");
  f = {};
  f.target_column = "t";
  f.position_columns = {"x1", "y1", "z1", "x2", "y2", "z2"};
  EXPECT_EQ(f.Validate(), "position_columns: one target per row (target_column) takes exactly three columns");
  f = {};
  f.separator = ' ';
  EXPECT_EQ(f.Validate(), "separator: expected ',', ';', tab, '|' or 0 (detect)");
}

// ---------------------------------------------------------------------------------------------
// Drift.

// Simulated poses: fixed references and tool targets in the true tracker frame, each pose seen
// through its own rigid drift (a few arc-seconds, tens of µm).
struct DriftCase {
  std::vector<Vec3> references;
  std::vector<std::vector<Vec3>> targets;  // per pose, the truth
  std::vector<Mat3> rotations;             // per pose, the truth
  TrackerMeasurements measured;
};

DriftCase SimulateDrift(int num_references, bool rotate) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random_unit = [&] { return Vec3(u(rng), u(rng), u(rng)).normalized(); };
  DriftCase c;
  const std::vector<Vec3> all_references = {Vec3(3000, -1200, 150), Vec3(2500, 1800, -300), Vec3(-800, 2600, 900),
                                            Vec3(1500, 400, 2100)};
  c.references.assign(all_references.begin(), all_references.begin() + num_references);
  for (int p = 0; p < 20; ++p) {
    const Isometry3 drift = [&] {
      Isometry3 d = Isometry3::Identity();
      if (rotate)
        d.linear() = AngleAxisd(DegToRad(3.0 / 3600.0) * (0.5 + 0.5 * u(rng)), random_unit()).toRotationMatrix();
      d.translation() = 0.05 * random_unit();  // 50 µm in a direction of its own
      return d;
    }();
    TrackerPose pose;
    pose.q_rad = {0.1 * p};
    pose.line = p + 2;
    std::vector<Vec3> truth;
    for (int k = 0; k < 2; ++k) {
      truth.push_back(Vec3(1000 * u(rng), 1000 * u(rng), 500 + 500 * u(rng)));
      TargetMeasurement t;
      t.target = k;
      t.position_mm = drift * truth.back();
      t.covariance_mm2 = Vec3(1e-4, 4e-4, 9e-4).asDiagonal();
      t.has_covariance = true;
      pose.targets.push_back(t);
    }
    const Mat3 rotation = AngleAxisd(2 * u(rng), random_unit()).toRotationMatrix();
    pose.tracker_from_tool_rotation = drift.linear() * rotation;
    for (const Vec3& r : c.references) pose.references_mm.push_back(drift * r);
    c.targets.push_back(truth);
    c.rotations.push_back(rotation);
    c.measured.poses.push_back(pose);
  }
  c.measured.num_joints = 1;
  c.measured.has_rotation = true;
  c.measured.target_names = {"A", "B"};
  return c;
}

TEST(TrackerIo, RemoveRigidDriftWithFourReferences) {
  DriftCase c = SimulateDrift(4, true);
  const double rms = RemoveTrackerDrift(&c.measured);
  EXPECT_GT(rms, 0.01);  // the drift moved the targets by tens of µm...
  EXPECT_LT(rms, 0.2);
  // ...and after removal all poses share one frame: a single rigid motion G (found by Eigen's
  // Umeyama fit of the true references onto the corrected ones) maps every true target onto its
  // corrected measurement. G is near the identity (the mean drift).
  Eigen::Matrix3Xd from(3, 4), to(3, 4);
  for (int k = 0; k < 4; ++k) {
    from.col(k) = c.references[k];
    to.col(k) = c.measured.poses[0].references_mm[k];
  }
  Isometry3 g;
  g.matrix() = Eigen::umeyama(from, to, false);
  EXPECT_LT(g.translation().norm(), 0.2);
  EXPECT_LT(AngleAxisd(g.linear()).angle(), DegToRad(5.0 / 3600.0));
  double worst = 0.0, worst_rotation = 0.0;
  for (std::size_t p = 0; p < c.measured.poses.size(); ++p) {
    const TrackerPose& pose = c.measured.poses[p];
    for (int k = 0; k < 4; ++k) worst = std::max(worst, (pose.references_mm[k] - g * c.references[k]).norm());
    for (int k = 0; k < 2; ++k) {
      worst = std::max(worst, (pose.targets[k].position_mm - g * c.targets[p][k]).norm());
      // The covariance turns with the correction (by arc-seconds): its trace is unchanged.
      EXPECT_NEAR(pose.targets[k].covariance_mm2.trace(), 14e-4, 1e-15);
    }
    worst_rotation = std::max(worst_rotation, MaxDiff(*pose.tracker_from_tool_rotation, g.linear() * c.rotations[p]));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_rotation, 1e-12);
}

TEST(TrackerIo, RemoveTranslationDriftWithOneReference) {
  DriftCase c = SimulateDrift(1, false);
  // With one reference the anchor is its mean position: the mean drift stays, the rest goes.
  Vec3 mean_drift = Vec3::Zero();
  for (const TrackerPose& p : c.measured.poses) mean_drift += (p.references_mm[0] - c.references[0]) / 20.0;
  RemoveTrackerDrift(&c.measured);
  double worst = 0.0;
  for (std::size_t p = 0; p < c.measured.poses.size(); ++p) {
    for (int k = 0; k < 2; ++k) {
      worst = std::max(worst, (c.measured.poses[p].targets[k].position_mm - (c.targets[p][k] + mean_drift)).norm());
    }
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(TrackerIo, RemoveDriftEdgeCases) {
  TrackerMeasurements none = Parse("q1,x,y,z\n0,1,2,3\n");
  EXPECT_EQ(RemoveTrackerDrift(&none), 0.0);
  EXPECT_EQ(none.poses[0].targets[0].position_mm, Vec3(1, 2, 3));
  // References read from the file, on one line: the rotation about it is unknown.
  TrackerFormat f;
  f.reference_columns = {"a1", "b1", "c1", "a2", "b2", "c2", "a3", "b3", "c3"};
  TrackerMeasurements line = Parse("q1,x,y,z,a1,b1,c1,a2,b2,c2,a3,b3,c3\n0,1,2,3,0,0,0,100,0,0,300,0,0\n", f);
  ASSERT_EQ(line.poses[0].references_mm.size(), 3u);
  EXPECT_EQ(line.poses[0].references_mm[2], Vec3(300, 0, 0));
  EXPECT_EQ(ErrorOf([&] { RemoveTrackerDrift(&line); }),
            "field 'references': the reference targets lie on a line: the rotation about it is undetermined");
  // Default reference names ref_x1,ref_y1,ref_z1,...
  const auto defaults = Parse("q1,x,y,z,ref_x1,ref_y1,ref_z1,ref_x2,ref_y2,ref_z2\n0,1,2,3,4,5,6,7,8,9\n");
  ASSERT_EQ(defaults.poses[0].references_mm.size(), 2u);
  EXPECT_EQ(defaults.poses[0].references_mm[1], Vec3(7, 8, 9));
}

// ---------------------------------------------------------------------------------------------
// The public UR10 laser-tracker data (IPA, MIT licence), read with the format files of docs/.

const std::string kIpaDir = std::string(RAMTK_SHARED_DIR) + "/data/ipa-robot-accuracy";
const std::string kDocsDir = std::string(RAMTK_DATASETS_DIR) + "/../docs/examples";

TEST(TrackerIo, IpaSeriesAGrid) {
  const std::string path = kIpaDir + "/Series_A/measurements_grid.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  const TrackerFormat f = ReadTrackerFormat(kDocsDir + "/ipa_tmac_format.yaml");
  WarningLog log;
  const auto start = std::chrono::steady_clock::now();
  const TrackerMeasurements m = ReadTrackerMeasurements(path, f);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("read_seconds", std::to_string(seconds));
  std::printf("Series A: %zu rows read in %.3f s\n", m.poses.size(), seconds);
  EXPECT_LT(seconds, 2.0);            // well under a second on a free core; room for a loaded machine
  ASSERT_EQ(m.poses.size(), 11911u);  // 11 912 lines, the last without a newline (wc -l says 11 911)
  EXPECT_EQ(m.num_joints, 6);
  EXPECT_TRUE(m.has_rotation);
  // Row 1: 20200714163904;...;-1,5708;-1,5708;0,0;-1,5708;0,0;0,0;23,68...;2361,9831;-1368,5474;
  // 119,39713;-90,409151;-59,885105;-90,887438
  const TrackerPose& p = m.poses[0];
  EXPECT_EQ(p.line, 2);
  EXPECT_EQ(p.q_rad, (std::vector<double>{-1.5708, -1.5708, 0.0, -1.5708, 0.0, 0.0}));
  EXPECT_EQ(p.targets[0].position_mm, Vec3(2361.9831, -1368.5474, 119.39713));
  EXPECT_FALSE(p.targets[0].has_covariance);
  const Mat3 expected =
      (AngleAxisd(DegToRad(-90.409151), Vec3::UnitX()) * AngleAxisd(DegToRad(-59.885105), Vec3::UnitY()) *
       AngleAxisd(DegToRad(-90.887438), Vec3::UnitZ()))
          .toRotationMatrix();
  EXPECT_LT(MaxDiff(*p.tracker_from_tool_rotation, expected), 1e-12);
  // Times: 20200714163904 is unix 1594744744; the last row, 20200715050127, 44543 s later. The
  // file's clock steps back 9 times: one warning.
  EXPECT_EQ(m.first_time_unix_s, 1594744744.0);
  EXPECT_EQ(m.poses.back().time_s, 44543.0);
  EXPECT_EQ(m.poses.back().line, 11912);
  ASSERT_EQ(log.messages.size(), 1u);
  EXPECT_NE(log.messages[0].find("the time goes backwards (9 times in the file)"), std::string::npos);
}

TEST(TrackerIo, IpaSeriesBJointConfigurations) {
  const std::string path = kIpaDir + "/Series_B/measurements_joint_configurations.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  const TrackerFormat f = ReadTrackerFormat(kDocsDir + "/ipa_tmac_sigma_format.yaml");
  WarningLog log;
  const TrackerMeasurements m = ReadTrackerMeasurements(path, f);
  ASSERT_EQ(m.poses.size(), 1495u);
  // Row 1: 2,02011E+13;...;-3,14159;-1,5708;0;-1,5708;0;0;21,86750031;383,76294;0,031674;
  // -3240,8734;0,013252;201,93157;0,0037622;-90,179302;...;-20,118749;...;-90,169308;...
  const TrackerPose& p = m.poses[0];
  EXPECT_EQ(p.q_rad, (std::vector<double>{-3.14159, -1.5708, 0.0, -1.5708, 0.0, 0.0}));
  EXPECT_EQ(p.targets[0].position_mm, Vec3(383.76294, -3240.8734, 201.93157));
  ASSERT_TRUE(p.targets[0].has_covariance);
  EXPECT_EQ(p.targets[0].covariance_mm2.diagonal(),
            Vec3(0.031674 * 0.031674, 0.013252 * 0.013252, 0.0037622 * 0.0037622));
  const Mat3 expected =
      (AngleAxisd(DegToRad(-90.179302), Vec3::UnitX()) * AngleAxisd(DegToRad(-20.118749), Vec3::UnitY()) *
       AngleAxisd(DegToRad(-90.169308), Vec3::UnitZ()))
          .toRotationMatrix();
  EXPECT_LT(MaxDiff(*p.tracker_from_tool_rotation, expected), 1e-12);
  // The rounded stamps: one warning, times 0.
  EXPECT_EQ(m.poses.back().time_s, 0.0);
  EXPECT_EQ(m.first_time_unix_s, 0.0);
  ASSERT_EQ(log.messages.size(), 1u);
  EXPECT_NE(log.messages[0].find("'2,02011E+13' looks like a yyyymmddHHMMSS time stamp"), std::string::npos);
}

}  // namespace
}  // namespace ramtk::kinematics
