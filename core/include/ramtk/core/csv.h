#pragma once
// Comma-separated tables with a header row, as in the file formats of docs/formats.md.
// Blank lines and lines starting with '#' are skipped; cells are trimmed. Every access that can
// fail on user data throws InputError naming the file, line and column.

#include <string>
#include <vector>

namespace ramtk {

class CsvTable {
 public:
  std::string path;                            // for error messages
  std::vector<std::string> header;             // column names
  std::vector<std::vector<std::string>> rows;  // cells, each row header.size() long
  std::vector<int> line_numbers;               // 1-based file line of each row

  // Index of column `name`; -1 if absent and not required, else InputError.
  int Column(const std::string& name, bool required = true) const;
  // Cell as a finite double / an integer / text; InputError names file:line and the column.
  double Number(std::size_t row, int column) const;
  long long Integer(std::size_t row, int column) const;
  // Number() within +-limit, else InputError naming the cell, the limit and its constant's name
  // (a value beyond it is a corrupt file, not a measurement).
  double Bounded(std::size_t row, int column, double limit, const char* limit_name) const;
  const std::string& Text(std::size_t row, int column) const;
  std::size_t size() const { return rows.size(); }
};

CsvTable ParseCsv(const std::string& text, const std::string& path);
CsvTable ReadCsv(const std::string& path);
// One CSV line split with RFC 4180 quotes ("a,""b""" is one cell a,"b); a trailing CR is dropped.
std::vector<std::string> SplitCsvLine(const std::string& line);
// A cell quoted when it holds a comma, a quote or a newline (quotes doubled, newlines as spaces).
std::string CsvQuote(const std::string& cell);

// A number with a fixed count of decimals ("%.*f"), for CSV cells.
std::string FormatFixed(double value, int decimals);
// A number with at most `significant` significant digits ("%.*g"), for CSV cells.
std::string FormatSignificant(double value, int significant);
// The one CSV writer: an optional comment block (each line prefixed "# "), the header, then the
// rows; every cell passes through CsvQuote, so text with commas or quotes reads back as written.
std::string FormatCsv(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                      const std::string& comment = "");

}  // namespace ramtk
