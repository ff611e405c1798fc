#include "ramtk/kinematics/measurements_io.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

const char* IndexColumn(MeasurementKind kind) { return kind == MeasurementKind::kBall ? "pose" : "point"; }

}  // namespace

RobotMeasurementSet ReadRobotMeasurements(const std::string& path) {
  return ParseRobotMeasurements(ReadTextFile(path), path);
}

RobotMeasurementSet ParseRobotMeasurements(const std::string& text, const std::string& path) {
  const CsvTable t = ParseCsv(text, path);
  RobotMeasurementSet set;
  const int pose_col = t.Column("pose", false);
  const int point_col = t.Column("point", false);
  if ((pose_col < 0) == (point_col < 0)) {
    throw InputError({path, 1, "pose/point"}, "expected exactly one of the columns 'pose' (ball) or 'point' (monitoring)");
  }
  set.kind = pose_col >= 0 ? MeasurementKind::kBall : MeasurementKind::kMonitoring;
  const int index_col = pose_col >= 0 ? pose_col : point_col;
  const int cycle_col = t.Column("cycle");
  const int time_col = t.Column("time_s");
  int q_col[kNumJoints];
  for (int i = 0; i < kNumJoints; ++i) q_col[i] = t.Column("q" + std::to_string(i + 1));
  const int x_col = t.Column("x"), y_col = t.Column("y"), z_col = t.Column("z");
  std::vector<int> known = {index_col, cycle_col, time_col, x_col, y_col, z_col};
  known.insert(known.end(), q_col, q_col + kNumJoints);
  std::vector<int> extra_cols;
  for (int c = 0; c < static_cast<int>(t.header.size()); ++c) {
    bool is_known = false;
    for (int k : known) is_known |= (k == c);
    if (!is_known) {
      extra_cols.push_back(c);
      set.extra_columns.push_back(t.header[c]);
    }
  }
  set.rows.reserve(t.size());
  // Plausibility limits (measurements_io.h): a value beyond them is a corrupt file, and would
  // otherwise reach the solvers (which abort on non-finite steps) as if it were a measurement.
  auto bounded = [&t](std::size_t r, int col, double limit, const char* limit_name) {
    return t.Bounded(r, col, limit, limit_name);
  };
  for (std::size_t r = 0; r < t.size(); ++r) {
    RobotMeasurement m;
    m.cycle = static_cast<int>(t.Integer(r, cycle_col));
    m.time_s = bounded(r, time_col, kMaxAbsTimeS, "kMaxAbsTimeS");
    m.index = static_cast<int>(t.Integer(r, index_col));
    for (int i = 0; i < kNumJoints; ++i) m.q_controller[i] = DegToRad(bounded(r, q_col[i], kMaxAbsJointDeg, "kMaxAbsJointDeg"));
    const double x = bounded(r, x_col, kMaxAbsPositionMm, "kMaxAbsPositionMm");  // in column order
    const double y = bounded(r, y_col, kMaxAbsPositionMm, "kMaxAbsPositionMm");
    const double z = bounded(r, z_col, kMaxAbsPositionMm, "kMaxAbsPositionMm");
    m.position_mm = Vec3(x, y, z);
    for (int c : extra_cols) {
      const std::string& name = t.header[c];
      const bool must_be_number = name.rfind("cov_", 0) == 0 || name.rfind("temp_", 0) == 0;
      if (must_be_number) {
        m.extra[name] = t.Number(r, c);
      } else {
        try {
          m.extra[name] = t.Number(r, c);
        } catch (const InputError&) {
          m.extra_text[name] = t.Text(r, c);
        }
      }
    }
    m.line = t.line_numbers[r];
    set.rows.push_back(std::move(m));
  }
  return set;
}

std::string FormatRobotMeasurements(const RobotMeasurementSet& set) {
  std::vector<std::string> header = {"cycle", "time_s", IndexColumn(set.kind)};
  for (int i = 0; i < kNumJoints; ++i) header.push_back("q" + std::to_string(i + 1));
  header.insert(header.end(), {"x", "y", "z"});
  header.insert(header.end(), set.extra_columns.begin(), set.extra_columns.end());
  std::vector<std::vector<std::string>> rows;
  rows.reserve(set.rows.size());
  for (const RobotMeasurement& m : set.rows) {
    std::vector<std::string> cells = {std::to_string(m.cycle), FormatFixed(m.time_s, 3), std::to_string(m.index)};
    for (int i = 0; i < kNumJoints; ++i) cells.push_back(FormatFixed(RadToDeg(m.q_controller[i]), 9));
    for (int i = 0; i < 3; ++i) cells.push_back(FormatFixed(m.position_mm[i], 6));
    for (const std::string& name : set.extra_columns) {
      const auto it = m.extra.find(name);
      const auto text = m.extra_text.find(name);
      if (text != m.extra_text.end()) {
        cells.push_back(text->second);  // FormatCsv quotes it if needed
      } else if (it == m.extra.end()) {
        cells.push_back("nan");
      } else {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.10g", it->second);
        cells.push_back(buf);
      }
    }
    rows.push_back(std::move(cells));
  }
  return FormatCsv(header, rows);
}

void WriteRobotMeasurements(const RobotMeasurementSet& set, const std::string& path) {
  const std::string text = FormatRobotMeasurements(set);
  // What the reader would refuse is never written: the text is read back before the file exists,
  // so a joint of 5000° or a covariance that is not positive definite stops here, naming the row,
  // not in the command that reads the file next.
  try {
    const RobotMeasurementSet back = ParseRobotMeasurements(text, path);
    if (back.kind == MeasurementKind::kBall && HasCentreCovariance(back, path)) {
      for (const RobotMeasurement& row : back.rows) CentreCovariance(row, path);
    }
  } catch (const InputError& e) {
    throw InputError(e.where(), "not written, the readers would refuse it: " + e.message());
  }
  WriteFileAtomically(path, text);
}

bool HasCentreCovariance(const RobotMeasurementSet& set, const std::string& path) {
  int found = 0;
  std::string missing;
  for (const char* name : kCentreCovarianceColumns) {
    bool has = false;
    for (const std::string& c : set.extra_columns) has |= (c == name);
    if (has) {
      ++found;
    } else if (missing.empty()) {
      missing = name;
    }
  }
  if (found > 0 && found < static_cast<int>(kCentreCovarianceColumns.size())) {
    throw InputError({path, 1, missing},
                     "missing: the centre covariance needs all of cov_xx,cov_yy,cov_zz,cov_xy,cov_xz,cov_yz");
  }
  return found == static_cast<int>(kCentreCovarianceColumns.size());
}

Mat3 CentreCovariance(const RobotMeasurement& row, const std::string& path) {
  double v[6];
  for (std::size_t i = 0; i < kCentreCovarianceColumns.size(); ++i) {
    const auto it = row.extra.find(kCentreCovarianceColumns[i]);
    if (it == row.extra.end() || !std::isfinite(it->second)) {
      throw InputError({path, row.line, kCentreCovarianceColumns[i]}, "missing or not a finite number");
    }
    v[i] = it->second;
  }
  Mat3 c;
  c << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
  for (int i = 0; i < 3; ++i) {
    if (!(v[i] > 0.0)) throw InputError({path, row.line, kCentreCovarianceColumns[i]}, "variance must be > 0");
  }
  Eigen::LLT<Mat3> llt(c);
  if (llt.info() != Eigen::Success) {
    throw InputError({path, row.line, "cov_xy,cov_xz,cov_yz"},
                     "the centre covariance is not positive definite (a correlation of magnitude >= 1)");
  }
  return c;
}

void SetCentreCovariance(const Mat3& c, RobotMeasurement* row) {
  const double v[6] = {c(0, 0), c(1, 1), c(2, 2), c(0, 1), c(0, 2), c(1, 2)};
  for (std::size_t i = 0; i < kCentreCovarianceColumns.size(); ++i) row->extra[kCentreCovarianceColumns[i]] = v[i];
}

void AddCentreCovarianceColumns(RobotMeasurementSet* set) {
  for (const char* name : kCentreCovarianceColumns) {
    bool has = false;
    for (const std::string& c : set->extra_columns) has |= (c == name);
    if (!has) set->extra_columns.push_back(name);
  }
}

}  // namespace ramtk::kinematics
