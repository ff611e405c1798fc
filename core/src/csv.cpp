#include "ramtk/core/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/parse.h"

namespace ramtk {

std::vector<std::string> SplitCsvLine(const std::string& line);

namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Cells with RFC 4180 quotes (a quoted cell may hold commas), each trimmed.
std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells = SplitCsvLine(line);
  for (std::string& c : cells) c = Trim(c);
  return cells;
}

}  // namespace

int CsvTable::Column(const std::string& name, bool required) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  if (required)
    throw InputError({path, 1, name}, "missing column (header has " + std::to_string(header.size()) + " columns)");
  return -1;
}

const std::string& CsvTable::Text(std::size_t row, int column) const { return rows.at(row).at(column); }

double CsvTable::Number(std::size_t row, int column) const {
  return ParseDouble(Text(row, column), {path, line_numbers.at(row), header.at(column)});
}

double CsvTable::Bounded(std::size_t row, int column, double limit, const char* limit_name) const {
  const double v = Number(row, column);
  if (!(std::abs(v) <= limit)) {
    throw InputError({path, line_numbers.at(row), header.at(column)},
                     "value " + Text(row, column) + " is beyond the plausible range +-" + FormatFixed(limit, 0) + " (" +
                         limit_name + ")");
  }
  return v;
}

long long CsvTable::Integer(std::size_t row, int column) const {
  const std::string& text = Text(row, column);
  const InputLocation where{path, line_numbers.at(row), header.at(column)};
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    throw InputError(where, "expected an integer, got '" + text + "'");
  }
  return value;
}

CsvTable ParseCsv(const std::string& text, const std::string& path) {
  CsvTable table;
  table.path = path;
  // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first column's name.
  const bool bom = text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  std::stringstream ss(bom ? text.substr(3) : text);
  std::string line;
  int line_number = 0;
  while (std::getline(ss, line)) {
    ++line_number;
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    std::vector<std::string> cells = SplitCells(trimmed);
    if (table.header.empty()) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i].empty()) throw InputError({path, line_number, ""}, "empty column name in the header");
        for (std::size_t j = 0; j < i; ++j) {
          if (cells[j] == cells[i]) throw InputError({path, line_number, cells[i]}, "duplicate column name");
        }
      }
      table.header = std::move(cells);
      continue;
    }
    if (cells.size() != table.header.size()) {
      throw InputError({path, line_number, ""}, "expected " + std::to_string(table.header.size()) +
                                                    " cells as in the header, got " + std::to_string(cells.size()));
    }
    table.rows.push_back(std::move(cells));
    table.line_numbers.push_back(line_number);
  }
  if (table.header.empty()) throw InputError({path, 0, ""}, "empty file: expected a header row");
  return table;
}

CsvTable ReadCsv(const std::string& path) { return ParseCsv(ReadTextFile(path), path); }

std::string FormatCsv(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                      const std::string& comment) {
  std::string out;
  std::size_t start = 0;
  while (!comment.empty() && start <= comment.size()) {
    const std::size_t end = std::min(comment.find('\n', start), comment.size());
    out += "# " + comment.substr(start, end - start) + "\n";
    start = end + 1;
  }
  auto append_row = [&out](const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i) out += ',';
      out += CsvQuote(cells[i]);
    }
    out += '\n';
  };
  append_row(header);
  for (const auto& r : rows) append_row(r);
  return out;
}

std::string FormatFixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, value);
  return buf;
}

std::string FormatSignificant(double value, int significant) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", significant, value);
  return buf;
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cells.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}

std::string CsvQuote(const std::string& cell) {
  if (cell.find_first_of(",\"\n") == std::string::npos) return cell;
  std::string q = "\"";
  for (char c : cell) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

}  // namespace ramtk
