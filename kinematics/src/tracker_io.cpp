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

namespace ramtk::kinematics {
namespace {

// ---------------------------------------------------------------------------------------------
// The table: header and cells split at the separator, with the file line of every row.

std::string_view Trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

// Cells of one line split at `sep`, with RFC 4180 quotes (a quoted cell may hold the separator,
// "" is a quote), each trimmed. A tab separator is not trimmed away from the cells' edges.
void SplitLine(std::string_view line, char sep, std::vector<std::string>* cells) {
  cells->clear();
  if (line.find('"') == std::string_view::npos) {
    std::size_t start = 0;
    while (true) {
      const std::size_t end = line.find(sep, start);
      const std::string_view cell = line.substr(start, end == std::string_view::npos ? end : end - start);
      cells->emplace_back(Trim(cell));
      if (end == std::string_view::npos) break;
      start = end + 1;
    }
    return;
  }
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == sep) {
      cells->emplace_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells->emplace_back(Trim(cell));
}

struct Table {
  std::string path;
  char separator = ',';
  int header_line = 0;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
};

// `;` if the header holds one, else `,`, else tab (a one-column file: `,`).
char DetectSeparator(std::string_view header) {
  if (header.find(';') != std::string_view::npos) return ';';
  if (header.find(',') != std::string_view::npos) return ',';
  if (header.find('\t') != std::string_view::npos) return '\t';
  return ',';
}

Table SplitTable(const std::string& text, const std::string& path, char separator) {
  Table t;
  t.path = path;
  std::string_view all(text);
  // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first column's name.
  if (all.substr(0, 3) == "\xEF\xBB\xBF") all.remove_prefix(3);
  std::size_t start = 0;
  int line_number = 0;
  std::vector<std::string> cells;
  while (start < all.size()) {
    std::size_t end = all.find('\n', start);
    if (end == std::string_view::npos) end = all.size();
    const std::string_view line = Trim(all.substr(start, end - start));
    start = end + 1;
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    if (t.header.empty()) {
      t.separator = separator != 0 ? separator : DetectSeparator(line);
      SplitLine(line, t.separator, &t.header);
      t.header_line = line_number;
      continue;
    }
    SplitLine(line, t.separator, &cells);
    if (cells.size() != t.header.size()) {
      throw InputError({path, line_number, ""}, "expected " + std::to_string(t.header.size()) +
                                                    " cells as in the header, got " + std::to_string(cells.size()) +
                                                    " (separator '" +
                                                    (t.separator == '\t' ? "tab" : std::string(1, t.separator)) + "')");
    }
    t.rows.push_back(std::move(cells));
    t.lines.push_back(line_number);
  }
  if (t.header.empty()) throw InputError({path, 0, ""}, "empty file: expected a header row");
  if (t.rows.empty()) throw InputError({path, t.header_line, ""}, "no data rows after the header");
  return t;
}

// ---------------------------------------------------------------------------------------------
// Numbers with either decimal mark.

// Parses the whole cell as a double; false when it is not a number. Non-finite values parse (the
// caller says what is wrong with them).
bool ToDouble(std::string_view cell, char decimal, double* value) {
  if (cell.empty()) return false;
  char small[64];
  std::string large;
  char* buf = small;
  if (cell.size() >= sizeof(small)) {
    large.assign(cell);
    buf = large.data();
  } else {
    std::memcpy(small, cell.data(), cell.size());
    small[cell.size()] = '\0';
  }
  if (decimal == ',') {
    for (std::size_t i = 0; i < cell.size(); ++i) {
      if (buf[i] == '.') return false;  // a point in a decimal-comma file: a thousands mark or a mix-up
      if (buf[i] == ',') buf[i] = '.';
    }
  }
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(buf, &end);
  return end == buf + cell.size();
}

struct Cells {
  const Table& t;
  char decimal;

  InputLocation At(std::size_t row, int column) const { return {t.path, t.lines[row], t.header[column]}; }

  double Number(std::size_t row, int column) const {
    const std::string& text = t.rows[row][column];
    double v = 0.0;
    if (text.empty()) throw InputError(At(row, column), "expected a number, got an empty cell");
    if (!ToDouble(text, decimal, &v)) {
      throw InputError(At(row, column),
                       "expected a number, got '" + text + "'" + (decimal == ',' ? " (decimal mark ',')" : ""));
    }
    if (!std::isfinite(v)) throw InputError(At(row, column), "expected a finite number, got '" + text + "'");
    return v;
  }

  double Bounded(std::size_t row, int column, double scale, double limit, const char* unit,
                 const char* limit_name) const {
    const double v = Number(row, column) * scale;
    if (!(std::abs(v) <= limit)) {
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%g", limit);
      throw InputError(At(row, column), "value " + t.rows[row][column] + " is beyond the plausible range +-" + buf +
                                            " " + unit + " (" + limit_name + ")");
    }
    return v;
  }

  int Integer(std::size_t row, int column) const {
    const double v = Number(row, column);
    if (v != std::floor(v) || std::abs(v) > 2e9) {
      throw InputError(At(row, column), "expected an integer, got '" + t.rows[row][column] + "'");
    }
    return static_cast<int>(v);
  }
};

// ---------------------------------------------------------------------------------------------
// Time stamps.

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
long long DaysFromCivil(long long y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const long long yoe = y - era * 400;
  const long long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const long long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

int DaysInMonth(long long y, int m) {
  static const int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : kDays[m - 1];
}

// A time as whole seconds plus a fraction, so that differences of unix times keep microseconds.
struct Stamp {
  long long whole = 0;
  double fraction = 0.0;
};

bool Digits(std::string_view s, std::size_t pos, std::size_t count, int* value) {
  if (pos + count > s.size()) return false;
  int v = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + (s[i] - '0');
  }
  *value = v;
  return true;
}

// Calendar fields to unix seconds (UTC); false when a field is out of range.
bool CivilToStamp(int y, int mo, int d, int h, int mi, int s, Stamp* out) {
  if (mo < 1 || mo > 12 || d < 1 || d > DaysInMonth(y, mo) || h > 23 || mi > 59 || s > 60) return false;
  out->whole = DaysFromCivil(y, mo, d) * 86400 + h * 3600 + mi * 60 + s;
  out->fraction = 0.0;
  return true;
}

// yyyymmddHHMMSS, exactly 14 digits (the tracker's local time, taken as UTC).
bool ParseCompact(std::string_view s, Stamp* out) {
  int y, mo, d, h, mi, sec;
  if (s.size() != 14) return false;
  if (!Digits(s, 0, 4, &y) || !Digits(s, 4, 2, &mo) || !Digits(s, 6, 2, &d) || !Digits(s, 8, 2, &h) ||
      !Digits(s, 10, 2, &mi) || !Digits(s, 12, 2, &sec)) {
    return false;
  }
  return CivilToStamp(y, mo, d, h, mi, sec, out);
}

// YYYY-MM-DD(T| )hh:mm:ss[(.|,)fff][Z|±hh[:]mm|±hh]; without an offset the time is taken as UTC.
bool ParseIso8601(std::string_view s, Stamp* out) {
  int y, mo, d, h, mi, sec;
  if (s.size() < 19 || !Digits(s, 0, 4, &y) || s[4] != '-' || !Digits(s, 5, 2, &mo) || s[7] != '-' ||
      !Digits(s, 8, 2, &d) || (s[10] != 'T' && s[10] != ' ') || !Digits(s, 11, 2, &h) || s[13] != ':' ||
      !Digits(s, 14, 2, &mi) || s[16] != ':' || !Digits(s, 17, 2, &sec)) {
    return false;
  }
  if (!CivilToStamp(y, mo, d, h, mi, sec, out)) return false;
  std::size_t pos = 19;
  if (pos < s.size() && (s[pos] == '.' || s[pos] == ',')) {
    // As an integer over a power of ten: .125 is exactly 0.125.
    long long digits = 0, scale = 1;
    for (++pos; pos < s.size() && s[pos] >= '0' && s[pos] <= '9'; ++pos) {
      if (scale < 1000000000000000000LL / 10) {  // beyond 1e-17 s the digits carry nothing
        digits = digits * 10 + (s[pos] - '0');
        scale *= 10;
      }
    }
    if (scale == 1) return false;
    out->fraction = static_cast<double>(digits) / static_cast<double>(scale);
  }
  if (pos == s.size()) return true;
  if (s[pos] == 'Z' || s[pos] == 'z') return pos + 1 == s.size();
  if (s[pos] != '+' && s[pos] != '-') return false;
  const int sign = s[pos] == '-' ? -1 : 1;
  int oh = 0, om = 0;
  if (!Digits(s, pos + 1, 2, &oh)) return false;
  pos += 3;
  if (pos < s.size() && s[pos] == ':') ++pos;
  if (pos < s.size() && !Digits(s, pos, 2, &om)) return false;
  if (pos < s.size()) pos += 2;
  if (pos != s.size() || oh > 23 || om > 59) return false;
  out->whole -= sign * (oh * 3600 + om * 60);  // local = UTC + offset
  return true;
}

enum class TimeForm { kNone, kSeconds, kIso8601, kCompact, kUnusable };

// A yyyymmddHHMMSS stamp that a spreadsheet turned into a number with fewer digits: the value is
// of the stamp's size, but not the 14 plain digits.
bool LooksLikeRoundedCompact(const std::string& text, char decimal) {
  double v = 0.0;
  return text.size() != 14 && ToDouble(text, decimal, &v) && v >= 1e13 && v < 1e14;
}

TimeForm DecideTimeForm(const std::string& form, const std::string& first, char decimal) {
  if (form == "seconds") return TimeForm::kSeconds;
  if (form == "iso8601") return TimeForm::kIso8601;
  if (form == "yyyymmddhhmmss") return TimeForm::kCompact;
  Stamp s;
  if (ParseIso8601(first, &s)) return TimeForm::kIso8601;
  if (ParseCompact(first, &s)) return TimeForm::kCompact;
  if (LooksLikeRoundedCompact(first, decimal)) return TimeForm::kUnusable;
  return TimeForm::kSeconds;
}

// ---------------------------------------------------------------------------------------------
// Columns.

class Columns {
 public:
  explicit Columns(const Table& t) : t_(t) {
    for (std::size_t i = 0; i < t.header.size(); ++i) {
      const auto [it, inserted] = index_.emplace(t.header[i], static_cast<int>(i));
      if (!inserted) it->second = -2;  // named twice: an error if used
    }
  }
  bool Has(const std::string& name) const { return index_.count(name) > 0; }
  int Find(const std::string& name) const {
    const auto it = index_.find(name);
    if (it == index_.end()) return -1;
    if (it->second == -2) throw InputError({t_.path, t_.header_line, name}, "column name appears twice in the header");
    return it->second;
  }
  // The column `name` that the format (member `role`) asks for.
  int Require(const std::string& name, const std::string& role) const {
    const int c = Find(name);
    if (c < 0) {
      throw InputError({t_.path, t_.header_line, name}, "missing column (" + role + "; the header has " +
                                                            std::to_string(t_.header.size()) + " columns)");
    }
    return c;
  }
  std::vector<int> RequireAll(const std::vector<std::string>& names, const std::string& role) const {
    std::vector<int> out;
    out.reserve(names.size());
    for (const std::string& n : names) out.push_back(Require(n, role));
    return out;
  }

 private:
  const Table& t_;
  std::unordered_map<std::string, int> index_;
};

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

// Every column the reader uses, resolved against the header.
struct Layout {
  std::vector<int> joints;
  std::vector<int> positions;  // 3 per target
  std::vector<std::string> target_names;
  int target = -1, pose = -1;
  std::vector<int> rotation;
  std::string rotation_field;  // the rotation columns, for errors about them together
  std::vector<int> sigma, covariance, references;
  int time = -1, cycle = -1;
};

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

// `,` when the separator is `;` and a cell of a number column (or a time without ':') holds a
// comma, else `.`.
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

// Reads one row's rotation in the form's convention.
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

// Reads target `k` of row `r` (its columns l.positions[3k..3k+2] and its σ or covariance).
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

}  // namespace

// ---------------------------------------------------------------------------------------------

std::string TrackerFormat::Validate() const {
  if (separator != 0 && separator != ',' && separator != ';' && separator != '\t' && separator != '|') {
    return "separator: expected ',', ';', tab, '|' or 0 (detect)";
  }
  if (decimal != 0 && decimal != '.' && decimal != ',') return "decimal: expected '.', ',' or 0 (detect)";
  if (decimal == ',' && separator == ',') return "decimal: the decimal mark ',' cannot also be the separator";
  auto named = [](const std::vector<std::string>& names) {
    for (const std::string& n : names) {
      if (n.empty()) return false;
    }
    return true;
  };
  if (joint_columns.size() > 12) return "joint_columns: at most 12 joints";
  if (!named(joint_columns)) return "joint_columns: empty column name";
  if (position_columns.size() % 3 != 0) {
    return "position_columns: expected three columns (x,y,z) per target, got " +
           std::to_string(position_columns.size());
  }
  if (!named(position_columns)) return "position_columns: empty column name";
  if (!target_column.empty() && position_columns.size() > 3) {
    return "position_columns: one target per row (target_column) takes exactly three columns";
  }
  if (!pose_column.empty() && target_column.empty()) {
    return "pose_column: only used with target_column (one target per row)";
  }
  if (rotation == RotationForm::kNone && !rotation_columns.empty()) {
    return "rotation_columns: given without a rotation form (rotation: none)";
  }
  if (!rotation_columns.empty() && static_cast<int>(rotation_columns.size()) != RotationColumnCount(rotation)) {
    return "rotation_columns: expected " + std::to_string(RotationColumnCount(rotation)) +
           " columns for this rotation form, got " + std::to_string(rotation_columns.size());
  }
  if (!named(rotation_columns)) return "rotation_columns: empty column name";
  if (!sigma_columns.empty() && !covariance_columns.empty()) {
    return "sigma_columns: give sigma_columns or covariance_columns, not both";
  }
  if (sigma_columns.size() % 3 != 0) return "sigma_columns: expected three columns (sx,sy,sz) per target";
  if (covariance_columns.size() % 6 != 0) {
    return "covariance_columns: expected six columns (cov_xx,cov_yy,cov_zz,cov_xy,cov_xz,cov_yz) per target";
  }
  if (!position_columns.empty() && !sigma_columns.empty() && sigma_columns.size() != position_columns.size()) {
    return "sigma_columns: expected as many columns as position_columns";
  }
  if (!position_columns.empty() && !covariance_columns.empty() &&
      covariance_columns.size() != 2 * position_columns.size()) {
    return "covariance_columns: expected six columns per target of position_columns";
  }
  if (!named(sigma_columns) || !named(covariance_columns)) return "sigma_columns: empty column name";
  if (reference_columns.size() % 3 != 0) return "reference_columns: expected three columns (x,y,z) per reference";
  if (!named(reference_columns)) return "reference_columns: empty column name";
  if (time_form != "auto" && time_form != "seconds" && time_form != "iso8601" && time_form != "yyyymmddhhmmss") {
    return "time_form: expected auto, seconds, iso8601 or yyyymmddhhmmss, got '" + time_form + "'";
  }
  return "";
}

// ---------------------------------------------------------------------------------------------
// The format file.

namespace {

InputLocation YamlAt(const std::string& path, const YAML::Node& node, const std::string& field) {
  InputLocation where{path, 0, field};
  if (node.IsDefined() && node.Mark().line >= 0) where.line = node.Mark().line + 1;
  return where;
}

std::string YamlText(const std::string& path, const YAML::Node& node, const std::string& key) {
  if (node.IsNull()) return {};
  if (!node.IsScalar()) throw InputError(YamlAt(path, node, key), "expected text");
  return node.Scalar();
}

std::vector<std::string> YamlNames(const std::string& path, const YAML::Node& node, const std::string& key) {
  if (node.IsNull()) return {};
  if (!node.IsSequence()) throw InputError(YamlAt(path, node, key), "expected a list of column names");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = key + "[" + std::to_string(i) + "]";
    if (!node[i].IsScalar() || node[i].Scalar().empty()) {
      throw InputError(YamlAt(path, node[i], field), "expected a column name");
    }
    out.push_back(node[i].Scalar());
  }
  return out;
}

char YamlChar(const std::string& path, const YAML::Node& node, const std::string& key, bool separator) {
  const std::string v = YamlText(path, node, key);
  if (v.empty() || v == "auto") return 0;
  if (separator && (v == "tab" || v == "\t")) return '\t';
  if (v.size() == 1) return v[0];
  throw InputError(
      YamlAt(path, node, key),
      std::string("expected ") + (separator ? "',', ';', tab, '|'" : "'.' or ','") + " or auto, got '" + v + "'");
}

}  // namespace

TrackerFormat ParseTrackerFormat(const std::string& yaml_text, const std::string& path) {
  const YAML::Node root = LoadYamlText(yaml_text, path);
  TrackerFormat f;
  if (root.IsNull()) return f;
  if (!root.IsMap()) throw InputError({path, 1, ""}, "expected a YAML mapping at the top level");
  std::map<std::string, int> key_lines;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string key = it->first.Scalar();
    const YAML::Node value = it->second;
    key_lines[key] = it->first.Mark().line + 1;
    auto unit = [&](const char* a, const char* b) {
      const std::string v = YamlText(path, value, key);
      if (v == a) return 0;
      if (v == b) return 1;
      throw InputError(YamlAt(path, value, key), std::string("expected '") + a + "' or '" + b + "', got '" + v + "'");
    };
    if (key == "separator") {
      f.separator = YamlChar(path, value, key, true);
    } else if (key == "decimal") {
      f.decimal = YamlChar(path, value, key, false);
    } else if (key == "joint_columns") {
      f.joint_columns = YamlNames(path, value, key);
    } else if (key == "joint_unit") {
      f.joint_unit = unit("deg", "rad") == 0 ? AngleUnit::kDegree : AngleUnit::kRadian;
    } else if (key == "position_columns") {
      f.position_columns = YamlNames(path, value, key);
    } else if (key == "length_unit") {
      f.length_unit = unit("mm", "m") == 0 ? LengthUnit::kMillimetre : LengthUnit::kMetre;
    } else if (key == "target_column") {
      f.target_column = YamlText(path, value, key);
    } else if (key == "pose_column") {
      f.pose_column = YamlText(path, value, key);
    } else if (key == "rotation") {
      const std::string v = YamlText(path, value, key);
      if (v == "none") {
        f.rotation = RotationForm::kNone;
      } else if (v == "quaternion") {
        f.rotation = RotationForm::kQuaternion;
      } else if (v == "kuka_abc") {
        f.rotation = RotationForm::kKukaAbc;
      } else if (v == "euler_xyz") {
        f.rotation = RotationForm::kEulerXyz;
      } else if (v == "matrix") {
        f.rotation = RotationForm::kMatrix;
      } else {
        throw InputError(YamlAt(path, value, key),
                         "expected none, quaternion, kuka_abc, euler_xyz or matrix, got '" + v + "'");
      }
    } else if (key == "rotation_columns") {
      f.rotation_columns = YamlNames(path, value, key);
    } else if (key == "rotation_unit") {
      f.rotation_unit = unit("deg", "rad") == 0 ? AngleUnit::kDegree : AngleUnit::kRadian;
    } else if (key == "sigma_columns") {
      f.sigma_columns = YamlNames(path, value, key);
    } else if (key == "covariance_columns") {
      f.covariance_columns = YamlNames(path, value, key);
    } else if (key == "reference_columns") {
      f.reference_columns = YamlNames(path, value, key);
    } else if (key == "time_column") {
      f.time_column = YamlText(path, value, key);
    } else if (key == "time_form") {
      f.time_form = YamlText(path, value, key);
    } else if (key == "cycle_column") {
      f.cycle_column = YamlText(path, value, key);
    } else {
      throw InputError({path, it->first.Mark().line + 1, key},
                       "unknown key (expected separator, decimal, joint_columns, joint_unit, position_columns, "
                       "length_unit, target_column, pose_column, rotation, rotation_columns, rotation_unit, "
                       "sigma_columns, covariance_columns, reference_columns, time_column, time_form, cycle_column)");
    }
  }
  const std::string problem = f.Validate();
  if (!problem.empty()) {
    const OptionsProblem p = SplitOptionsProblem(problem);
    const auto line = key_lines.find(p.field);
    throw InputError({path, line == key_lines.end() ? 0 : line->second, p.field}, p.message);
  }
  return f;
}

TrackerFormat ReadTrackerFormat(const std::string& path) { return ParseTrackerFormat(ReadTextFile(path), path); }

// ---------------------------------------------------------------------------------------------
// The measurements.

TrackerMeasurements ReadTrackerMeasurements(const std::string& path, const TrackerFormat& format) {
  ThrowIfInvalid(format.Validate(), "format");  // before reading a large file
  return ParseTrackerMeasurements(ReadTextFile(path), path, format);
}

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
  const double joint_scale = format.joint_unit == AngleUnit::kDegree ? kRadPerDeg : 1.0;
  const double length = format.length_unit == LengthUnit::kMetre ? 1000.0 : 1.0;

  TrackerMeasurements out;
  out.num_joints = static_cast<int>(l.joints.size());
  out.target_names = l.target_names;
  out.has_rotation = format.rotation != RotationForm::kNone;

  // Time form, from the first row's cell when "auto".
  TimeForm time_form = TimeForm::kNone;
  if (l.time >= 0) {
    time_form = DecideTimeForm(format.time_form, t.rows[0][l.time], decimal);
    if (time_form == TimeForm::kUnusable) {
      RAMTK_LOG(kWarning) << path << ":" << t.lines[0] << ": column '" << t.header[l.time] << "': '"
                          << t.rows[0][l.time]
                          << "' looks like a yyyymmddHHMMSS time stamp that a spreadsheet rounded to a number; "
                             "the seconds are lost, so the times are left at 0";
    }
  }
  auto read_time = [&](std::size_t r) {
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
                               (LooksLikeRoundedCompact(cell, decimal)
                                    ? ": a spreadsheet rounded the stamp to a number and the seconds are lost"
                                    : ""));
        }
        break;
      case TimeForm::kNone:
      case TimeForm::kUnusable:
        break;
    }
    return s;
  };

  auto read_joints = [&](std::size_t r) {
    std::vector<double> q(l.joints.size());
    for (std::size_t j = 0; j < l.joints.size(); ++j) {
      q[j] = cells.Bounded(r, l.joints[j], joint_scale, kTrackerMaxAbsJointRad, "rad", "kTrackerMaxAbsJointRad");
    }
    return q;
  };

  // The part of a pose read from its (first) row: joints, rotation, references, cycle, time.
  std::vector<Stamp> stamps;
  auto start_pose = [&](std::size_t r) {
    TrackerPose p;
    p.line = t.lines[r];
    p.q_rad = read_joints(r);
    if (out.has_rotation) p.tracker_from_tool_rotation = ReadRotation(cells, r, l, format);
    for (std::size_t k = 0; k < l.references.size(); k += 3) {
      Vec3 v;
      for (int i = 0; i < 3; ++i) {
        v[i] =
            cells.Bounded(r, l.references[k + i], length, kTrackerMaxAbsPositionMm, "mm", "kTrackerMaxAbsPositionMm");
      }
      p.references_mm.push_back(v);
    }
    if (l.cycle >= 0) p.cycle = cells.Integer(r, l.cycle);
    if (l.time >= 0) stamps.push_back(read_time(r));
    return p;
  };

  if (l.target < 0) {
    out.poses.reserve(t.rows.size());
    const int num_targets = static_cast<int>(l.positions.size() / 3);
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      TrackerPose p = start_pose(r);
      for (int k = 0; k < num_targets; ++k) {
        p.targets.push_back(ReadTarget(cells, r, l, k, length));
        p.targets.back().target = k;
      }
      out.poses.push_back(std::move(p));
    }
  } else {
    // One target per row: consecutive rows with the same pose (and cycle) cell form one pose.
    std::unordered_map<std::string, int> target_index;
    std::size_t first_row = 0;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const bool same_pose = r > 0 && t.rows[r][l.pose] == t.rows[first_row][l.pose] &&
                             (l.cycle < 0 || t.rows[r][l.cycle] == t.rows[first_row][l.cycle]);
      if (!same_pose) {
        first_row = r;
        out.poses.push_back(start_pose(r));
      } else {
        const std::vector<double> q = read_joints(r);
        const std::vector<double>& q0 = out.poses.back().q_rad;
        for (std::size_t j = 0; j < q.size(); ++j) {
          if (std::abs(q[j] - q0[j]) > 1e-9) {
            throw InputError(cells.At(r, l.joints[j]), "joint differs from the same pose's first row (line " +
                                                           std::to_string(t.lines[first_row]) +
                                                           "): the rows of one pose must have the same joints");
          }
        }
      }
      TrackerPose& p = out.poses.back();
      const std::string& name = t.rows[r][l.target];
      if (name.empty()) throw InputError(cells.At(r, l.target), "empty target name");
      const auto [it, inserted] = target_index.emplace(name, static_cast<int>(out.target_names.size()));
      if (inserted) out.target_names.push_back(name);
      for (const TargetMeasurement& m : p.targets) {
        if (m.target == it->second) {
          throw InputError(cells.At(r, l.target), "target '" + name + "' appears twice in the pose starting at line " +
                                                      std::to_string(p.line));
        }
      }
      TargetMeasurement m = ReadTarget(cells, r, l, 0, length);
      m.target = it->second;
      p.targets.push_back(m);
    }
  }

  // Times relative to the first row; a clock going backwards is worth a warning, not an error
  // (a tracker clock reset, rows merged from two files).
  if (!stamps.empty() && time_form != TimeForm::kUnusable) {
    const Stamp s0 = stamps[0];
    if (time_form != TimeForm::kSeconds) {
      out.first_time_unix_s = static_cast<double>(s0.whole) + s0.fraction;
    } else if (s0.fraction >= 1e8) {  // from 1973 on: unix seconds, not seconds since a start
      out.first_time_unix_s = s0.fraction;
    }
    int backwards = 0, first_backwards_line = 0;
    for (std::size_t i = 0; i < out.poses.size(); ++i) {
      out.poses[i].time_s = static_cast<double>(stamps[i].whole - s0.whole) + (stamps[i].fraction - s0.fraction);
      if (i > 0 && out.poses[i].time_s < out.poses[i - 1].time_s) {
        if (backwards++ == 0) first_backwards_line = out.poses[i].line;
      }
    }
    if (backwards > 0) {
      RAMTK_LOG(kWarning) << path << ":" << first_backwards_line << ": column '" << t.header[l.time]
                          << "': the time goes backwards (" << backwards << " time" << (backwards > 1 ? "s" : "")
                          << " in the file)";
    }
  }
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
