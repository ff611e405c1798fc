// Private to the tracker reader (tracker_io.h): the table split from the text, its cells as
// numbers, time stamps, and the columns the format names resolved against the header.
#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::kinematics::tracker_detail {

// ---- the table and its numbers (tracker_table.cpp) ----

// The table: header and cells split at the separator, with the file line of every row.
struct Table {
  std::string path;
  char separator = ',';
  int header_line = 0;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
};

Table SplitTable(const std::string& text, const std::string& path, char separator);

// Parses the whole cell as a double; false when it is not a number. Non-finite values parse (the
// caller says what is wrong with them).
bool ToDouble(std::string_view cell, char decimal, double* value);

// The cells of a table read as numbers with its decimal mark; errors name the file, line and column.
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

// ---- time stamps (tracker_time.cpp) ----

// A time as whole seconds plus a fraction, so that differences of unix times keep microseconds.
struct Stamp {
  long long whole = 0;
  double fraction = 0.0;
};

enum class TimeForm { kNone, kSeconds, kIso8601, kCompact, kUnusable };

// yyyymmddHHMMSS, exactly 14 digits (the tracker's local time, taken as UTC).
bool ParseCompact(std::string_view s, Stamp* out);

// YYYY-MM-DD(T| )hh:mm:ss[(.|,)fff][Z|±hh[:]mm|±hh]; without an offset the time is taken as UTC.
bool ParseIso8601(std::string_view s, Stamp* out);

// A yyyymmddHHMMSS stamp that a spreadsheet turned into a number with fewer digits: the value is
// of the stamp's size, but not the 14 plain digits.
bool LooksLikeRoundedCompact(const std::string& text, char decimal);

TimeForm DecideTimeForm(const std::string& form, const std::string& first, char decimal);

// ---- columns (tracker_columns.cpp) ----

// The header's column names (a name given twice is an error only when used).
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

int RotationColumnCount(RotationForm form);

Layout ResolveColumns(const Table& t, const Columns& cols, const TrackerFormat& f);

// `,` when the separator is `;` and a cell of a number column (or a time without ':') holds a
// comma, else `.`.
char DetectDecimal(const Table& t, const Layout& l);

// Reads one row's rotation in the form's convention.
Mat3 ReadRotation(const Cells& cells, std::size_t r, const Layout& l, const TrackerFormat& f);

// Reads target `k` of row `r` (its columns l.positions[3k..3k+2] and its σ or covariance).
TargetMeasurement ReadTarget(const Cells& cells, std::size_t r, const Layout& l, int k, double length);

}  // namespace ramtk::kinematics::tracker_detail
