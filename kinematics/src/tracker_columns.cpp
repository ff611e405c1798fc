// The columns of a tracker file: the format's names (or the defaults) resolved against the
// header, and one row's rotation and targets read through them.
#include "tracker_internal.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "ramtk/core/units.h"

namespace ramtk::kinematics::tracker_detail {
namespace {

// Default names of `count` groups: {a,b,c} for one group ("sx","sy","sz"), {a1,b1,c1,a2,...} else.
std::vector<std::string> GroupNames(const std::vector<std::string>& stems, int count) {
  std::vector<std::string> out;
  for (int k = 1; k <= count; ++k) {
    for (const std::string& s : stems) out.push_back(count == 1 ? s : s + std::to_string(k));
  }
  return out;
}

// Default optional columns: all of `names` when all are present, none when none is, an error naming
// the first missing one otherwise.
std::vector<std::string> AllOrNone(const Columns& cols, const Table& t, const std::vector<std::string>& names,
                                   const std::string& role) {
  int found = 0;
  std::string missing;
  for (const std::string& n : names) {
    if (cols.Has(n)) {
      ++found;
    } else if (missing.empty()) {
      missing = n;
    }
  }
  if (found == 0) return {};
  if (found < static_cast<int>(names.size())) {
    throw InputError({t.path, t.header_line, missing},
                     "missing column: the default " + role + " columns come as a set");
  }
  return names;
}

}  // namespace

int RotationColumnCount(RotationForm form) {
  switch (form) {
    case RotationForm::kNone:
      return 0;
    case RotationForm::kQuaternion:
      return 4;
    case RotationForm::kKukaAbc:
    case RotationForm::kEulerXyz:
      return 3;
    case RotationForm::kMatrix:
      return 9;
  }
  return 0;
}

namespace {

std::vector<std::string> DefaultRotationColumns(RotationForm form) {
  switch (form) {
    case RotationForm::kNone:
      return {};
    case RotationForm::kQuaternion:
      return {"qx", "qy", "qz", "qw"};
    case RotationForm::kKukaAbc:
      return {"a", "b", "c"};
    case RotationForm::kEulerXyz:
      return {"rx", "ry", "rz"};
    case RotationForm::kMatrix:
      return {"r11", "r12", "r13", "r21", "r22", "r23", "r31", "r32", "r33"};
  }
  return {};
}

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

}  // namespace

Layout ResolveColumns(const Table& t, const Columns& cols, const TrackerFormat& f) {
  Layout l;
  // Joints.
  std::vector<std::string> joints = f.joint_columns;
  if (joints.empty()) {
    for (int k = 1; k <= 12 && cols.Has("q" + std::to_string(k)); ++k) joints.push_back("q" + std::to_string(k));
    if (joints.empty()) {
      throw InputError({t.path, t.header_line, "q1"},
                       "missing column: no joint columns (q1..qN by default; name them with joint_columns)");
    }
  }
  l.joints = cols.RequireAll(joints, "joint_columns");

  // Targets.
  std::vector<std::string> positions = f.position_columns;
  if (positions.empty()) {
    if (cols.Has("x") || !f.target_column.empty() || !cols.Has("x1")) {
      positions = {"x", "y", "z"};
    } else {
      for (int k = 1; cols.Has("x" + std::to_string(k)); ++k) {
        for (const char* c : {"x", "y", "z"}) positions.push_back(c + std::to_string(k));
      }
    }
  }
  l.positions = cols.RequireAll(positions, "position_columns");
  const int num_targets = static_cast<int>(positions.size() / 3);
  if (!f.target_column.empty()) {
    l.target = cols.Require(f.target_column, "target_column");
    const std::string pose = f.pose_column.empty() ? "pose" : f.pose_column;
    l.pose = cols.Require(pose, "pose_column: the rows of one pose share it");
  } else {
    for (int k = 0; k < num_targets; ++k) l.target_names.push_back(positions[3 * k]);
  }

  // Rotation.
  if (f.rotation != RotationForm::kNone) {
    const std::vector<std::string> names =
        f.rotation_columns.empty() ? DefaultRotationColumns(f.rotation) : f.rotation_columns;
    l.rotation = cols.RequireAll(names, "rotation_columns");
    l.rotation_field = Join(names);
  }

  // Uncertainty: explicit columns, else the default names when present.
  std::vector<std::string> sigma = f.sigma_columns, covariance = f.covariance_columns;
  if (sigma.empty() && covariance.empty()) {
    sigma = AllOrNone(cols, t, GroupNames({"sx", "sy", "sz"}, num_targets), "sigma");
    covariance = AllOrNone(
        cols, t, GroupNames({"cov_xx", "cov_yy", "cov_zz", "cov_xy", "cov_xz", "cov_yz"}, num_targets), "covariance");
    if (!sigma.empty() && !covariance.empty()) {
      throw InputError({t.path, t.header_line, "sx"},
                       "both sigma (sx,...) and covariance (cov_xx,...) columns: "
                       "name the ones to use with sigma_columns or covariance_columns");
    }
  }
  if (!sigma.empty() && sigma.size() != positions.size()) {
    throw InputError({t.path, t.header_line, "sigma_columns"}, "expected " + std::to_string(positions.size()) +
                                                                   " columns (3 per target), got " +
                                                                   std::to_string(sigma.size()));
  }
  if (!covariance.empty() && covariance.size() != 2 * positions.size()) {
    throw InputError({t.path, t.header_line, "covariance_columns"}, "expected " + std::to_string(2 * positions.size()) +
                                                                        " columns (6 per target), got " +
                                                                        std::to_string(covariance.size()));
  }
  l.sigma = cols.RequireAll(sigma, "sigma_columns");
  l.covariance = cols.RequireAll(covariance, "covariance_columns");

  // References: explicit, else ref_x1,ref_y1,ref_z1,ref_x2,... when present.
  std::vector<std::string> references = f.reference_columns;
  if (references.empty()) {
    for (int k = 1; cols.Has("ref_x" + std::to_string(k)); ++k) {
      for (const char* c : {"ref_x", "ref_y", "ref_z"}) references.push_back(c + std::to_string(k));
    }
  }
  l.references = cols.RequireAll(references, "reference_columns");

  if (!f.time_column.empty()) {
    l.time = cols.Require(f.time_column, "time_column");
  } else {
    l.time = cols.Find("time_s");
  }
  if (!f.cycle_column.empty()) {
    l.cycle = cols.Require(f.cycle_column, "cycle_column");
  } else {
    l.cycle = cols.Find("cycle");
  }
  return l;
}

char DetectDecimal(const Table& t, const Layout& l) {
  if (t.separator != ';') return '.';
  std::vector<int> numeric = l.joints;
  for (const auto* v : {&l.positions, &l.rotation, &l.sigma, &l.covariance, &l.references}) {
    numeric.insert(numeric.end(), v->begin(), v->end());
  }
  for (const auto& row : t.rows) {
    for (int c : numeric) {
      if (row[c].find(',') != std::string::npos) return ',';
    }
    // A time in seconds (or a rounded stamp) may be the only number with a decimal; an ISO 8601
    // time's fraction may be written with a comma too, and says nothing about the other cells.
    if (l.time >= 0 && row[l.time].find(',') != std::string::npos && row[l.time].find(':') == std::string::npos) {
      return ',';
    }
  }
  return '.';
}

Mat3 ReadRotation(const Cells& cells, std::size_t r, const Layout& l, const TrackerFormat& f) {
  double v[9];
  for (std::size_t i = 0; i < l.rotation.size(); ++i) v[i] = cells.Number(r, l.rotation[i]);
  const double angle = f.rotation_unit == AngleUnit::kDegree ? kRadPerDeg : 1.0;
  const InputLocation where{cells.t.path, cells.t.lines[r], l.rotation_field};
  switch (f.rotation) {
    case RotationForm::kQuaternion: {
      const Eigen::Quaterniond q(v[3], v[0], v[1], v[2]);
      const double norm = q.norm();
      if (!(norm >= 0.9 && norm <= 1.1)) {
        throw InputError(where, "quaternion norm " + std::to_string(norm) + " is not near 1 (expected 0.9..1.1)");
      }
      return q.normalized().toRotationMatrix();
    }
    case RotationForm::kKukaAbc:
      return RotationFromKukaAbc({v[0] * angle, v[1] * angle, v[2] * angle});
    case RotationForm::kEulerXyz:
      return RotX(v[0] * angle) * RotY(v[1] * angle) * RotZ(v[2] * angle);
    case RotationForm::kMatrix: {
      Mat3 m;
      m << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
      const double error = OrthonormalityError(m);
      if (!(error <= 1e-3)) {
        throw InputError(where,
                         "not a rotation matrix: orthonormality error " + std::to_string(error) + " (at most 1e-3)");
      }
      return NearestRotation(m);
    }
    case RotationForm::kNone:
      break;
  }
  return Mat3::Identity();
}

TargetMeasurement ReadTarget(const Cells& cells, std::size_t r, const Layout& l, int k, double length) {
  TargetMeasurement m;
  for (int i = 0; i < 3; ++i) {
    m.position_mm[i] =
        cells.Bounded(r, l.positions[3 * k + i], length, kTrackerMaxAbsPositionMm, "mm", "kTrackerMaxAbsPositionMm");
  }
  if (!l.sigma.empty()) {
    for (int i = 0; i < 3; ++i) {
      const int c = l.sigma[3 * k + i];
      const double s = cells.Number(r, c) * length;
      if (!(s > 0.0)) throw InputError(cells.At(r, c), "a standard deviation must be > 0, got " + cells.t.rows[r][c]);
      m.covariance_mm2(i, i) = s * s;
    }
    m.has_covariance = true;
  } else if (!l.covariance.empty()) {
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = cells.Number(r, l.covariance[6 * k + i]) * length * length;
    for (int i = 0; i < 3; ++i) {
      if (!(v[i] > 0.0)) {
        throw InputError(cells.At(r, l.covariance[6 * k + i]),
                         "a variance must be > 0, got " + cells.t.rows[r][l.covariance[6 * k + i]]);
      }
    }
    m.covariance_mm2 << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
    if (Eigen::LLT<Mat3>(m.covariance_mm2).info() != Eigen::Success) {
      throw InputError(cells.At(r, l.covariance[6 * k + 3]),
                       "the covariance is not positive definite (a correlation of magnitude >= 1)");
    }
    m.has_covariance = true;
  }
  return m;
}

}  // namespace ramtk::kinematics::tracker_detail
