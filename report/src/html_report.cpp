#include "ramtk/report/html_report.h"

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <stdexcept>

#include "ramtk/core/file_io.h"

namespace ramtk::report {
namespace {

std::string Base64(const std::string& bytes) {
  static const char* kTable = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kTable[(v >> 18) & 63], out += kTable[(v >> 12) & 63], out += kTable[(v >> 6) & 63], out += kTable[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kTable[(v >> 18) & 63], out += kTable[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kTable[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// JSON inside <script>: "</" would end the script element.
std::string ScriptSafe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') out += "<\\";
    else out += json[i];
  }
  return out;
}

const char* kStyle = R"(
body { font-family: "DejaVu Sans", "Segoe UI", Helvetica, Arial, sans-serif; margin: 0 auto; max-width: 1150px;
       padding: 0 24px 48px; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #0072B2; padding-bottom: 6px; }
h2 { font-size: 1.25em; margin-top: 1.8em; color: #0b4f7c; }
.meta { color: #666; font-size: 0.9em; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 3px 9px; text-align: left; vertical-align: top; }
th { background: #f0f4f8; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 1em 0 1.6em; }
figcaption { color: #444; font-size: 0.92em; margin-top: 4px; }
.figtitle { font-weight: bold; margin-bottom: 4px; }
img.picture { max-width: 100%; border: 1px solid #ddd; }
#ramtk-errors { color: #b00; white-space: pre-wrap; }
)";

// Runs before the library: console errors and exceptions are collected in #ramtk-errors and
// window.ramtkErrors, so a reader (and the browser test) sees a figure that failed.
const char* kErrorHook = R"(
window.ramtkErrors = [];
window.addEventListener('error', function (e) { window.ramtkErrors.push(String(e.message || e)); });
window.addEventListener('unhandledrejection', function (e) { window.ramtkErrors.push(String(e.reason)); });
(function () {
  var original = console.error;
  console.error = function () {
    window.ramtkErrors.push('console.error: ' + Array.prototype.join.call(arguments, ' '));
    return original.apply(console, arguments);
  };
})();
)";

bool LooksNumeric(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && end != s.c_str() && *end == '\0';
}

}  // namespace

std::string EscapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::Section(const std::string& heading) {
  body_ += "<h2 id=\"section-" + std::to_string(++sections_) + "\">" + EscapeHtml(heading) + "</h2>\n";
}

void HtmlReport::Paragraph(const std::string& text) { body_ += "<p>" + EscapeHtml(text) + "</p>\n"; }

void HtmlReport::KeyValues(const std::vector<std::pair<std::string, std::string>>& rows) {
  body_ += "<table class=\"kv\">\n";
  for (const auto& [k, v] : rows)
    body_ += "<tr><th>" + EscapeHtml(k) + "</th><td" + (LooksNumeric(v) ? " class=\"num\"" : "") + ">" +
             EscapeHtml(v) + "</td></tr>\n";
  body_ += "</table>\n";
}

void HtmlReport::AddProvenance(const Provenance& p) {
  Section("Provenance");
  std::vector<std::pair<std::string, std::string>> rows = {{"ramtk", p.version + " (commit " + p.git_commit + ")"},
                                                           {"command", ShellCommandLine(p.command)}};
  for (const ProvenanceInput& i : p.inputs)
    rows.push_back({"input " + i.path, std::to_string(i.bytes) + " bytes, XXH3-128 " + i.xxh3_128});
  rows.push_back({"run", "started " + p.started_utc + " on " + p.host + " in " + p.working_directory});
  KeyValues(rows);
  body_ += "<pre class=\"provenance-options\">" + EscapeHtml(p.options.dump(2)) + "</pre>\n";
}

void HtmlReport::Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const std::string& h : header) body_ += "<th>" + EscapeHtml(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const std::string& c : row)
      body_ += std::string("<td") + (LooksNumeric(c) ? " class=\"num\"" : "") + ">" + EscapeHtml(c) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::AddFigure(const Figure& figure) {
  CheckFigure(figure);
  body_ += "<figure id=\"" + figure.id + "\" class=\"ramtk-figure\">\n";
  if (!figure.title.empty()) body_ += "<div class=\"figtitle\">" + EscapeHtml(figure.title) + "</div>\n";
  for (size_t p = 0; p < figure.panels.size(); ++p) {
    const std::string id = figure.id + "-panel" + std::to_string(p);
    body_ += "<div id=\"" + id + "\" class=\"ramtk-chart\"></div>\n";
    charts_ += "  ['" + id + "', " + ScriptSafe(PlotlyPanelJson(figure.panels[p])) + "],\n";
  }
  if (!figure.caption.empty()) body_ += "<figcaption>" + EscapeHtml(figure.caption) + "</figcaption>\n";
  body_ += "</figure>\n";
  ids_.push_back(figure.id);
}

void HtmlReport::AddCloud(const std::string& id, const Cloud3d& cloud, const std::string& caption) {
  body_ += "<figure id=\"" + id + "\" class=\"ramtk-figure\">\n<div id=\"" + id +
           "-panel0\" class=\"ramtk-chart\"></div>\n";
  if (!caption.empty()) body_ += "<figcaption>" + EscapeHtml(caption) + "</figcaption>\n";
  body_ += "</figure>\n";
  charts_ += "  ['" + id + "-panel0', " + ScriptSafe(PlotlyCloudJson(cloud)) + "],\n";
  ids_.push_back(id);
}

void HtmlReport::AddImage(const std::string& id, const std::string& png_path, const std::string& caption) {
  const std::string bytes = ReadTextFile(png_path);
  body_ += "<figure id=\"" + id + "\" class=\"ramtk-picture\">\n<img class=\"picture\" alt=\"" + EscapeHtml(caption) +
           "\" src=\"data:image/png;base64," + Base64(bytes) + "\">\n";
  if (!caption.empty()) body_ += "<figcaption>" + EscapeHtml(caption) + "</figcaption>\n";
  body_ += "</figure>\n";
  ids_.push_back(id);
}

void HtmlReport::Links(const std::vector<std::pair<std::string, std::string>>& label_and_path) {
  body_ += "<ul class=\"links\">\n";
  for (const auto& [label, path] : label_and_path)
    body_ += "<li><a href=\"" + EscapeHtml(path) + "\">" + EscapeHtml(label) + "</a> <span class=\"meta\">" +
             EscapeHtml(path) + "</span></li>\n";
  body_ += "</ul>\n";
}

std::string HtmlReport::Html(const std::string& plotly_js) const {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char when[64];
  std::strftime(when, sizeof(when), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::string html;
  html.reserve(plotly_js.size() + body_.size() + charts_.size() + 4096);
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"generator\" content=\"ramtk\">\n<title>" + EscapeHtml(title_) + "</title>\n";
  html += "<style>" + std::string(kStyle) + "</style>\n";
  html += "<script>" + std::string(kErrorHook) + "</script>\n";
  html += "<script>\n" + plotly_js + "\n</script>\n</head>\n<body>\n";
  html += "<h1>" + EscapeHtml(title_) + "</h1>\n<p class=\"meta\">Written by ramtk on " + std::string(when) +
          ". Self-contained: the charts are drawn by the Plotly.js copy inlined in this file; drag to zoom, "
          "double-click to reset.</p>\n";
  html += body_;
  html += "<div id=\"ramtk-errors\"></div>\n<script>\n(function () {\n var charts = [\n" + charts_ + " ];\n";
  html += R"( var config = {responsive: true, displaylogo: false};
 var done = charts.map(function (c) {
   try { return Plotly.newPlot(c[0], c[1].data, c[1].layout, config); }
   catch (e) { window.ramtkErrors.push(c[0] + ': ' + e); return Promise.resolve(); }
 });
 Promise.all(done).then(function () {
   document.body.setAttribute('data-charts-drawn', String(charts.length));
 }).catch(function (e) { window.ramtkErrors.push(String(e)); }).then(function () {
   if (window.ramtkErrors.length) document.getElementById('ramtk-errors').textContent =
       'Errors while drawing:\n' + window.ramtkErrors.join('\n');
   document.body.setAttribute('data-ramtk-errors', String(window.ramtkErrors.length));
 });
})();
</script>
</body>
</html>
)";
  return html;
}

std::string HtmlReport::Page() const {
  const std::string js = FindPlotlyJs();
  if (js.empty())
    throw std::runtime_error("Plotly.js not found (install the Debian package python3-plotly, or set RAMTK_PLOTLY_JS)");
  return Html(ReadTextFile(js));
}

void HtmlReport::Write(const std::string& path) const {
  const std::string js = FindPlotlyJs();
  if (js.empty())
    throw std::runtime_error("cannot write " + path +
                             ": Plotly.js not found (install the Debian package python3-plotly, or set RAMTK_PLOTLY_JS)");
  WriteFileAtomically(path, Html(ReadTextFile(js)));
}

}  // namespace ramtk::report
