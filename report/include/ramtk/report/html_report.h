// One self-contained HTML page per run: summary, tables, interactive figures, pictures and links
// to the data files. Everything is inlined (Plotly.js, PNGs as data URIs), so the page opens
// without a network and can be mailed as one file.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ramtk/core/provenance.h"
#include "ramtk/report/figure.h"
#include "ramtk/report/plotly.h"

namespace ramtk::report {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  // Starts a section (<h2>); the following blocks belong to it.
  void Section(const std::string& heading);
  // A paragraph of plain text (escaped).
  void Paragraph(const std::string& text);
  // A two-column table of names and values.
  void KeyValues(const std::vector<std::pair<std::string, std::string>>& rows);
  // A table with a header row.
  void Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // An interactive figure: one Plotly chart per panel, in a container with id figure.id.
  void AddFigure(const Figure& figure);
  // A 3D point view in a container with the given id.
  void AddCloud(const std::string& id, const Cloud3d& cloud, const std::string& caption);
  // A PNG inlined as a data URI in an <img> with the given id. Throws when the file cannot be read.
  void AddImage(const std::string& id, const std::string& png_path, const std::string& caption);
  // A "Provenance" section: version, commit, command line, inputs with their XXH3-128, the run
  // (start, host, folder) and the effective options as preformatted JSON (docs/formats.md).
  void AddProvenance(const Provenance& provenance);
  // Links to data files (paths relative to the report).
  void Links(const std::vector<std::pair<std::string, std::string>>& label_and_path);

  // The element ids of the figures, clouds and images added so far (what a browser test checks).
  const std::vector<std::string>& element_ids() const { return ids_; }

  // The page. `plotly_js` is the library's source (FindPlotlyJs()).
  std::string Html(const std::string& plotly_js) const;
  // The page with Plotly.js from FindPlotlyJs() (for outputs written together as one unit);
  // throws std::runtime_error when the bundle cannot be found.
  std::string Page() const;
  // Writes the page atomically, with Plotly.js from FindPlotlyJs(); throws std::runtime_error
  // when the bundle cannot be found.
  void Write(const std::string& path) const;

 private:
  std::string title_;
  std::string body_;
  std::string charts_;  // JavaScript: one draw call per chart
  std::vector<std::string> ids_;
  int sections_ = 0;
};

// HTML-escapes text (&, <, >, ", ').
std::string EscapeHtml(const std::string& text);

}  // namespace ramtk::report
