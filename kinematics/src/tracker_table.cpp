// The tracker table: header and cells split at the separator, with the file line of every row;
// numbers with either decimal mark.
#include "tracker_internal.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace ramtk::kinematics::tracker_detail {
namespace {

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

// `;` if the header holds one, else `,`, else tab (a one-column file: `,`).
char DetectSeparator(std::string_view header) {
  if (header.find(';') != std::string_view::npos) return ';';
  if (header.find(',') != std::string_view::npos) return ',';
  if (header.find('\t') != std::string_view::npos) return '\t';
  return ',';
}

}  // namespace

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

}  // namespace ramtk::kinematics::tracker_detail
