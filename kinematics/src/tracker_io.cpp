#include "ramtk/kinematics/tracker_io.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <unordered_map>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"
#include "ramtk/core/yaml.h"
#include "tracker_internal.h"

namespace ramtk::kinematics {

using tracker_detail::Cells;
using tracker_detail::Columns;
using tracker_detail::DecideTimeForm;
using tracker_detail::DetectDecimal;
using tracker_detail::Layout;
using tracker_detail::LooksLikeRoundedCompact;
using tracker_detail::ParseCompact;
using tracker_detail::ParseIso8601;
using tracker_detail::ReadRotation;
using tracker_detail::ReadTarget;
using tracker_detail::ResolveColumns;
using tracker_detail::SplitTable;
using tracker_detail::Stamp;
using tracker_detail::Table;
using tracker_detail::TimeForm;

// ---------------------------------------------------------------------------------------------
// The measurements.

TrackerMeasurements ReadTrackerMeasurements(const std::string& path, const TrackerFormat& format) {
  ThrowIfInvalid(format.Validate(), "format");  // before reading a large file
  return ParseTrackerMeasurements(ReadTextFile(path), path, format);
}

namespace {

// Reads the rows of one table through its layout: times, joints, the start of each pose.
struct RowReader {
  const Table& t;
  const Layout& l;
  const Cells& cells;
  const TrackerFormat& format;
  TimeForm time_form = TimeForm::kNone;
  double joint_scale = 1.0;    // file unit to rad
  double length = 1.0;         // file unit to mm
  std::vector<Stamp> stamps;   // per pose, when the file has times

  Stamp Time(std::size_t r) const {
    Stamp s;
    const std::string& cell = t.rows[r][l.time];
    switch (time_form) {
      case TimeForm::kSeconds:
        s.fraction = cells.Bounded(r, l.time, 1.0, kTrackerMaxAbsTimeS, "s", "kTrackerMaxAbsTimeS");
        break;
      case TimeForm::kIso8601:
        if (!ParseIso8601(cell, &s)) {
          throw InputError(cells.At(r, l.time),
                           "expected an ISO 8601 time (2020-07-14T16:39:04[.fff][Z|+hh:mm]), got '" + cell + "'");
        }
        break;
      case TimeForm::kCompact:
        if (!ParseCompact(cell, &s)) {
          throw InputError(cells.At(r, l.time),
                           "expected a yyyymmddHHMMSS time (20200714163904), got '" + cell + "'" +
                               (LooksLikeRoundedCompact(cell, cells.decimal)
                                    ? ": a spreadsheet rounded the stamp to a number and the seconds are lost"
                                    : ""));
        }
        break;
      case TimeForm::kNone:
      case TimeForm::kUnusable:
        break;
    }
    return s;
  }

  std::vector<double> Joints(std::size_t r) const {
    std::vector<double> q(l.joints.size());
    for (std::size_t j = 0; j < l.joints.size(); ++j) {
      q[j] = cells.Bounded(r, l.joints[j], joint_scale, kTrackerMaxAbsJointRad, "rad", "kTrackerMaxAbsJointRad");
    }
    return q;
  }

  // The part of a pose read from its (first) row: joints, rotation, references, cycle, time.
  TrackerPose StartPose(std::size_t r) {
    TrackerPose p;
    p.line = t.lines[r];
    p.q_rad = Joints(r);
    if (format.rotation != RotationForm::kNone) p.tracker_from_tool_rotation = ReadRotation(cells, r, l, format);
    for (std::size_t k = 0; k < l.references.size(); k += 3) {
      Vec3 v;
      for (int i = 0; i < 3; ++i) {
        v[i] =
            cells.Bounded(r, l.references[k + i], length, kTrackerMaxAbsPositionMm, "mm", "kTrackerMaxAbsPositionMm");
      }
      p.references_mm.push_back(v);
    }
    if (l.cycle >= 0) p.cycle = cells.Integer(r, l.cycle);
    if (l.time >= 0) stamps.push_back(Time(r));
    return p;
  }
};

// The time form, from the first row's cell when "auto".
TimeForm TimeFormOf(const Table& t, const Layout& l, const TrackerFormat& format, char decimal) {
  if (l.time < 0) return TimeForm::kNone;
  const TimeForm form = DecideTimeForm(format.time_form, t.rows[0][l.time], decimal);
  if (form == TimeForm::kUnusable) {
    RAMTK_LOG(kWarning) << t.path << ":" << t.lines[0] << ": column '" << t.header[l.time] << "': '"
                        << t.rows[0][l.time]
                        << "' looks like a yyyymmddHHMMSS time stamp that a spreadsheet rounded to a number; "
                           "the seconds are lost, so the times are left at 0";
  }
  return form;
}

// Every target of a pose on its row.
void ReadPosePerRow(RowReader* reader, TrackerMeasurements* out) {
  const Table& t = reader->t;
  out->poses.reserve(t.rows.size());
  const int num_targets = static_cast<int>(reader->l.positions.size() / 3);
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    TrackerPose p = reader->StartPose(r);
    for (int k = 0; k < num_targets; ++k) {
      p.targets.push_back(ReadTarget(reader->cells, r, reader->l, k, reader->length));
      p.targets.back().target = k;
    }
    out->poses.push_back(std::move(p));
  }
}

// One target per row: consecutive rows with the same pose (and cycle) cell form one pose.
void ReadTargetPerRow(RowReader* reader, TrackerMeasurements* out) {
  const Table& t = reader->t;
  const Layout& l = reader->l;
  const Cells& cells = reader->cells;
  std::unordered_map<std::string, int> target_index;
  std::size_t first_row = 0;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const bool same_pose = r > 0 && t.rows[r][l.pose] == t.rows[first_row][l.pose] &&
                           (l.cycle < 0 || t.rows[r][l.cycle] == t.rows[first_row][l.cycle]);
    if (!same_pose) {
      first_row = r;
      out->poses.push_back(reader->StartPose(r));
    } else {
      const std::vector<double> q = reader->Joints(r);
      const std::vector<double>& q0 = out->poses.back().q_rad;
      for (std::size_t j = 0; j < q.size(); ++j) {
        if (std::abs(q[j] - q0[j]) > 1e-9) {
          throw InputError(cells.At(r, l.joints[j]), "joint differs from the same pose's first row (line " +
                                                         std::to_string(t.lines[first_row]) +
                                                         "): the rows of one pose must have the same joints");
        }
      }
    }
    TrackerPose& p = out->poses.back();
    const std::string& name = t.rows[r][l.target];
    if (name.empty()) throw InputError(cells.At(r, l.target), "empty target name");
    const auto [it, inserted] = target_index.emplace(name, static_cast<int>(out->target_names.size()));
    if (inserted) out->target_names.push_back(name);
    for (const TargetMeasurement& m : p.targets) {
      if (m.target == it->second) {
        throw InputError(cells.At(r, l.target), "target '" + name + "' appears twice in the pose starting at line " +
                                                    std::to_string(p.line));
      }
    }
    TargetMeasurement m = ReadTarget(cells, r, l, 0, reader->length);
    m.target = it->second;
    p.targets.push_back(m);
  }
}

// Times relative to the first row; a clock going backwards is worth a warning, not an error
// (a tracker clock reset, rows merged from two files).
void SetRelativeTimes(const RowReader& reader, TrackerMeasurements* out) {
  const std::vector<Stamp>& stamps = reader.stamps;
  if (stamps.empty() || reader.time_form == TimeForm::kUnusable) return;
  const Stamp s0 = stamps[0];
  if (reader.time_form != TimeForm::kSeconds) {
    out->first_time_unix_s = static_cast<double>(s0.whole) + s0.fraction;
  } else if (s0.fraction >= 1e8) {  // from 1973 on: unix seconds, not seconds since a start
    out->first_time_unix_s = s0.fraction;
  }
  int backwards = 0, first_backwards_line = 0;
  for (std::size_t i = 0; i < out->poses.size(); ++i) {
    out->poses[i].time_s = static_cast<double>(stamps[i].whole - s0.whole) + (stamps[i].fraction - s0.fraction);
    if (i > 0 && out->poses[i].time_s < out->poses[i - 1].time_s) {
      if (backwards++ == 0) first_backwards_line = out->poses[i].line;
    }
  }
  if (backwards > 0) {
    RAMTK_LOG(kWarning) << reader.t.path << ":" << first_backwards_line << ": column '"
                        << reader.t.header[reader.l.time] << "': the time goes backwards (" << backwards << " time"
                        << (backwards > 1 ? "s" : "") << " in the file)";
  }
}

}  // namespace

TrackerMeasurements ParseTrackerMeasurements(const std::string& text, const std::string& path,
                                             const TrackerFormat& format) {
  ThrowIfInvalid(format.Validate(), "format");
  const Table t = SplitTable(text, path, format.separator);
  const Columns cols(t);
  const Layout l = ResolveColumns(t, cols, format);
  const char decimal = format.decimal != 0 ? format.decimal : DetectDecimal(t, l);
  if (decimal == t.separator) {
    throw InputError({path, t.header_line, ""}, std::string("the decimal mark '") + decimal +
                                                    "' is also the separator: give another decimal or separator");
  }
  const Cells cells{t, decimal};
  RowReader reader{t, l, cells, format};
  reader.time_form = TimeFormOf(t, l, format, decimal);
  reader.joint_scale = format.joint_unit == AngleUnit::kDegree ? kRadPerDeg : 1.0;
  reader.length = format.length_unit == LengthUnit::kMetre ? 1000.0 : 1.0;

  TrackerMeasurements out;
  out.num_joints = static_cast<int>(l.joints.size());
  out.target_names = l.target_names;
  out.has_rotation = format.rotation != RotationForm::kNone;
  if (l.target < 0) {
    ReadPosePerRow(&reader, &out);
  } else {
    ReadTargetPerRow(&reader, &out);
  }
  SetRelativeTimes(reader, &out);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Drift.

namespace {

struct Rigid {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 operator*(const Vec3& v) const { return rotation * v + translation; }
};

// The rigid motion (translation only with fewer than 3 points) taking `from` onto `to` in the
// least-squares sense.
Rigid FitRigid(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
  const double n = static_cast<double>(from.size());
  Vec3 cf = Vec3::Zero(), ct = Vec3::Zero();
  for (std::size_t k = 0; k < from.size(); ++k) {
    cf += from[k] / n;
    ct += to[k] / n;
  }
  Rigid r;
  if (from.size() >= 3) {
    Mat3 m = Mat3::Zero();
    for (std::size_t k = 0; k < from.size(); ++k) m += (to[k] - ct) * (from[k] - cf).transpose();
    r.rotation = NearestRotation(m);
  }
  r.translation = ct - r.rotation * cf;
  return r;
}

}  // namespace

double RemoveTrackerDrift(TrackerMeasurements* measurements) {
  std::vector<TrackerPose>& poses = measurements->poses;
  if (poses.empty() || poses[0].references_mm.empty()) return 0.0;
  const std::size_t n = poses[0].references_mm.size();
  for (const TrackerPose& p : poses) {
    if (p.references_mm.size() != n) {
      throw InputError({"", p.line, "references"}, "every pose needs the same " + std::to_string(n) +
                                                       " reference targets, this one has " +
                                                       std::to_string(p.references_mm.size()));
    }
  }
  // The anchor: the references' mean over all poses.
  std::vector<Vec3> anchor(n, Vec3::Zero());
  for (const TrackerPose& p : poses) {
    for (std::size_t k = 0; k < n; ++k) anchor[k] += p.references_mm[k] / static_cast<double>(poses.size());
  }
  if (n >= 3) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& a : anchor) c += a / static_cast<double>(n);
    Mat3 spread = Mat3::Zero();
    for (const Vec3& a : anchor) spread += (a - c) * (a - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(spread);
    if (!(eig.eigenvalues()[1] > 1e-12 * eig.eigenvalues()[2])) {
      throw InputError({"", poses[0].line, "references"},
                       "the reference targets lie on a line: the rotation about it is undetermined");
    }
  }
  std::vector<Rigid> correction(poses.size());
  // The mean of drifting rigid sets is not itself rigid (by the square of the drift angle): register
  // every pose onto the mean, and take the mean of the registered sets as the new anchor until it
  // stops changing. It is then one rigid shape, and all poses' corrected targets share one frame.
  for (int iteration = 0; iteration < 50; ++iteration) {
    for (std::size_t i = 0; i < poses.size(); ++i) correction[i] = FitRigid(poses[i].references_mm, anchor);
    if (n < 3) break;  // a translation-only fit onto the plain mean is exact
    std::vector<Vec3> next(n, Vec3::Zero());
    for (std::size_t i = 0; i < poses.size(); ++i) {
      for (std::size_t k = 0; k < n; ++k)
        next[k] += correction[i] * poses[i].references_mm[k] / static_cast<double>(poses.size());
    }
    double change = 0.0, size = 1.0;
    for (std::size_t k = 0; k < n; ++k) {
      change = std::max(change, (next[k] - anchor[k]).norm());
      size = std::max(size, anchor[k].norm());
    }
    anchor = next;
    if (change <= 1e-14 * size) break;
  }
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    TrackerPose& p = poses[i];
    const Rigid& c = correction[i];
    for (TargetMeasurement& m : p.targets) {
      const Vec3 corrected = c * m.position_mm;
      sum += (corrected - m.position_mm).squaredNorm();
      ++count;
      m.position_mm = corrected;
      if (m.has_covariance) m.covariance_mm2 = c.rotation * m.covariance_mm2 * c.rotation.transpose();
    }
    if (p.tracker_from_tool_rotation) p.tracker_from_tool_rotation = c.rotation * *p.tracker_from_tool_rotation;
    for (Vec3& r : p.references_mm) r = c * r;
  }
  return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

RobotMeasurementSet BallSetFromTracker(const TrackerMeasurements& data, const std::string& path) {
  if (data.num_joints != kNumJoints) {
    throw InputError({path, 0, "joints"}, "ball measurements need 6 joints; the file has " +
                                              std::to_string(data.num_joints) + " joint columns");
  }
  RobotMeasurementSet set;
  set.kind = MeasurementKind::kBall;
  for (std::size_t i = 0; i < data.poses.size(); ++i) {
    const TrackerPose& p = data.poses[i];
    RobotMeasurement m;
    m.cycle = p.cycle;
    m.time_s = p.time_s;
    m.index = static_cast<int>(i);
    for (int j = 0; j < kNumJoints; ++j) m.q_controller[j] = p.q_rad[j];
    m.position_mm = p.targets.front().position_mm;
    m.line = p.line;
    set.rows.push_back(m);
  }
  return set;
}

}  // namespace ramtk::kinematics
