#pragma once
// Measurement files as real trackers and controllers write them (docs/formats.md, "Tracker
// files"): one row per robot pose with the controller's joints and what the tracker measured
// there, in any column naming, `,` or `;` separated, with `.` or `,` as the decimal mark.
//
// What a row may hold besides the joints:
//  * one or several targets on the tool, each a 3-D point (x1,y1,z1,x2,y2,z2,... or one target per
//    row with a `target` column naming it, rows of one pose sharing the pose column);
//  * a 6-D pose of the tool (position plus quaternion, KUKA A,B,C, Euler X-Y-Z about the new axes,
//    or a row-major 3×3 rotation);
//  * fixed reference targets re-measured at every pose (tracker drift, removed on reading when
//    asked);
//  * per-coordinate standard deviations or a 3×3 covariance per target;
//  * an absolute time stamp (unix seconds, ISO 8601, or the compact yyyymmddHHMMSS), kept relative
//    to the first row.
// The column names are given by a TrackerFormat (a YAML file or options); the defaults read the
// plain names q1..qN, x,y,z. Lengths in the file are in mm unless the format says m; angles in
// degrees unless it says rad. In memory: mm and radians.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/measurements_io.h"

namespace ramtk::kinematics {

enum class AngleUnit { kDegree, kRadian };
enum class LengthUnit { kMillimetre, kMetre };

// How a 6-D pose's rotation is written.
enum class RotationForm {
  kNone,        // no rotation columns: points only
  kQuaternion,  // qx,qy,qz,qw (normalised on reading; |q| far from 1 is an error)
  kKukaAbc,     // A,B,C: R = RotZ(A)·RotY(B)·RotX(C)
  kEulerXyz,    // rx,ry,rz about the new axes: R = RotX(rx)·RotY(ry)·RotZ(rz) (Leica T-Mac exports)
  kMatrix,      // r11,r12,r13,r21,...,r33 row-major (orthonormality checked)
};

// Names the columns of a tracker file. Empty lists mean "use the default names when present".
struct TrackerFormat {
  // Field separator: 0 = detect from the header line (`;` if it holds one, else `,`, else tab).
  char separator = 0;
  // Decimal mark: 0 = detect (`,` when the separator is `;` and a number cell holds a comma).
  char decimal = 0;
  // Joint columns in joint order; default q1..qN (N = how many of q1, q2, ... exist, 1..12).
  std::vector<std::string> joint_columns;
  AngleUnit joint_unit = AngleUnit::kDegree;
  // Target position columns, three per target; default x,y,z, else x1,y1,z1,x2,... .
  std::vector<std::string> position_columns;
  LengthUnit length_unit = LengthUnit::kMillimetre;
  // When one target per row: the column naming the target (rows of one pose are consecutive and
  // share `pose_column`). Empty: each row is one pose.
  std::string target_column;
  std::string pose_column;  // default "pose" when present
  // Rotation of a 6-D pose (the tool frame in the tracker frame) and its columns, in the order
  // the form lists them.
  RotationForm rotation = RotationForm::kNone;
  std::vector<std::string> rotation_columns;
  AngleUnit rotation_unit = AngleUnit::kDegree;  // A,B,C and Euler angles
  // Standard deviation columns per target coordinate (sx,sy,sz per target, same order as the
  // positions), in the length unit; or six covariance columns per target
  // (cov_xx,cov_yy,cov_zz,cov_xy,cov_xz,cov_yz) in the length unit squared. At most one of the two.
  std::vector<std::string> sigma_columns;
  std::vector<std::string> covariance_columns;
  // Fixed reference targets measured at every pose, three columns each, in the length unit.
  std::vector<std::string> reference_columns;
  // Time column (empty: `time_s` when present, else none) and its form: "seconds" (relative or
  // unix seconds), "iso8601", "yyyymmddhhmmss", or "auto" (decided from the first cell).
  std::string time_column;
  std::string time_form = "auto";
  // A column whose integer value selects the rows kept together as one series or cycle
  // (default `cycle` when present).
  std::string cycle_column;

  std::string Validate() const;  // "" if usable
};

// Reads a TrackerFormat from YAML (keys as the member names, units as "deg"/"rad", "mm"/"m",
// rotation as "none"/"quaternion"/"kuka_abc"/"euler_xyz"/"matrix"). InputError names file, line and key.
TrackerFormat ReadTrackerFormat(const std::string& path);
TrackerFormat ParseTrackerFormat(const std::string& yaml_text, const std::string& path);

// Plausibility limits of ReadTrackerMeasurements: a value beyond one is an InputError naming the
// file, line and column, so that a corrupt cell never reaches the solvers as a measurement.
inline constexpr double kTrackerMaxAbsPositionMm = 1e5;  // per coordinate: 100 m holds any robot cell
inline constexpr double kTrackerMaxAbsJointRad = 6.0 * 3.14159265358979323846;  // three turns
// Seconds: unix seconds fit with a wide margin, while unix milliseconds and a yyyymmddHHMMSS stamp
// rounded to a number by a spreadsheet (2,02011E+13) do not pass as seconds.
inline constexpr double kTrackerMaxAbsTimeS = 1e12;

// One target measured at one pose.
struct TargetMeasurement {
  int target = 0;                   // 0-based target index (column group, or order of first appearance)
  Vec3 position_mm = Vec3::Zero();  // in the tracker frame
  // Covariance (mm²) when the file gives σ or a covariance; has_covariance false otherwise.
  Mat3 covariance_mm2 = Mat3::Zero();
  bool has_covariance = false;
};

// One robot pose and what was measured there.
struct TrackerPose {
  std::vector<double> q_rad;               // controller joints, N values
  std::vector<TargetMeasurement> targets;  // at least one
  // The tool frame's rotation in the tracker frame when the file has a 6-D pose (the position of
  // that pose is targets[0]).
  std::optional<Mat3> tracker_from_tool_rotation;
  std::vector<Vec3> references_mm;  // fixed reference targets at this pose (may be empty)
  double time_s = 0.0;              // relative to the first row's time (0 without a time column)
  int cycle = 0;                    // the cycle column, 0 without one
  int line = 0;                     // 1-based line of the (first) row in the file
};

struct TrackerMeasurements {
  int num_joints = 0;
  // One per target index: the target column's text, or a column group's x column name.
  std::vector<std::string> target_names;
  bool has_rotation = false;              // every pose carries tracker_from_tool_rotation
  double first_time_unix_s = 0.0;         // absolute time of the first row (0 when relative or none)
  std::vector<TrackerPose> poses;
};

// Reads a tracker file. Every malformed cell is an InputError naming the file, line and column.
TrackerMeasurements ReadTrackerMeasurements(const std::string& path, const TrackerFormat& format = {});
TrackerMeasurements ParseTrackerMeasurements(const std::string& text, const std::string& path,
                                             const TrackerFormat& format = {});

// Removes tracker drift using the reference targets: each pose's references are registered
// rigidly (3 or more; translation only with 1 or 2) onto their mean over all poses, and the same
// correction is applied to that pose's targets, covariances, rotation and references. With 3 or
// more the mean is that of the registered sets, iterated until it stops changing: the mean of
// drifting sets is not rigid by the square of the drift angle, the converged one is, so that all
// corrected poses share one frame. References on one line are an InputError. Returns the RMS correction (mm);
// does nothing and returns 0 when the poses have no references.
double RemoveTrackerDrift(TrackerMeasurements* measurements);

// The first target of every pose as ball measurements (kind kBall: `pose` = the pose's index,
// its cycle, time and line): the form `diagnose`, `calib sensor-robot` and `thermal` read.
// InputError naming `path` unless the data has 6 joints.
RobotMeasurementSet BallSetFromTracker(const TrackerMeasurements& data, const std::string& path);

}  // namespace ramtk::kinematics
