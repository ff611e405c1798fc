#include "ramtk/report/plotly.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace ramtk::report {
namespace {

using nlohmann::json;

// Non-finite values become null (a gap in Plotly), which nlohmann does by itself for NaN only.
json Values(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(std::isfinite(x) ? json(x) : json(nullptr));
  return a;
}

std::string Rgba(const char* hex, double alpha) {
  const unsigned v = static_cast<unsigned>(std::strtoul(hex + 1, nullptr, 16));
  return "rgba(" + std::to_string((v >> 16) & 255) + "," + std::to_string((v >> 8) & 255) + "," +
         std::to_string(v & 255) + "," + std::to_string(alpha).substr(0, 4) + ")";
}

const char* kMarkers[] = {"circle", "square", "triangle-up", "diamond", "triangle-down", "circle-open",
                          "square-open", "x", "cross", "star"};

json BaseLayout(const std::string& title) {
  return {{"title", {{"text", title}, {"font", {{"size", 15}}}}},
          {"margin", {{"l", 70}, {"r", 20}, {"t", 50}, {"b", 55}}},
          {"legend", {{"x", 1.02}, {"y", 1.0}, {"xanchor", "left"}, {"yanchor", "top"}}},
          {"plot_bgcolor", "white"},
          {"paper_bgcolor", "white"},
          {"hovermode", "closest"}};
}

json Axis(const std::string& label) {
  return {{"title", {{"text", label}}}, {"showgrid", true}, {"gridcolor", "#e5e5e5"},
          {"zeroline", false},           {"linecolor", "#555"}, {"mirror", true}, {"ticks", "outside"}};
}

}  // namespace

std::string PlotlyPanelJson(const Panel& panel) {
  json data = json::array();
  double x_min = INFINITY, x_max = -INFINITY;
  for (const Series& s : panel.series)
    for (double x : s.x)
      if (std::isfinite(x)) x_min = std::min(x_min, x), x_max = std::max(x_max, x);
  if (panel.zero_band > 0 && std::isfinite(x_min)) {
    data.push_back({{"type", "scatter"}, {"x", {x_min, x_max, x_max, x_min}},
                    {"y", {-panel.zero_band, -panel.zero_band, panel.zero_band, panel.zero_band}},
                    {"fill", "toself"}, {"fillcolor", "rgba(150,150,150,0.25)"}, {"line", {{"width", 0}}},
                    {"mode", "lines"}, {"name", panel.zero_band_label}, {"hoverinfo", "skip"}});
  }
  for (size_t k = 0; k < panel.series.size(); ++k) {
    const Series& s = panel.series[k];
    const char* colour = SeriesColour(static_cast<int>(k));
    if (!s.y_low.empty()) {
      data.push_back({{"type", "scatter"}, {"x", Values(s.x)}, {"y", Values(s.y_high)}, {"mode", "lines"},
                      {"line", {{"width", 0}, {"color", colour}}}, {"showlegend", false}, {"hoverinfo", "skip"},
                      {"legendgroup", "s" + std::to_string(k)}});
      data.push_back({{"type", "scatter"}, {"x", Values(s.x)}, {"y", Values(s.y_low)}, {"mode", "lines"},
                      {"fill", "tonexty"}, {"fillcolor", Rgba(colour, 0.22)},
                      {"line", {{"width", 0}, {"color", colour}}}, {"showlegend", false}, {"hoverinfo", "skip"},
                      {"legendgroup", "s" + std::to_string(k)}});
    }
    json t = {{"type", "scatter"}, {"x", Values(s.x)}, {"y", Values(s.y)}, {"name", s.label},
              {"showlegend", !s.label.empty()}, {"legendgroup", "s" + std::to_string(k)}};
    switch (s.style) {
      case SeriesStyle::kPoints:
        t["mode"] = "markers";
        t["marker"] = {{"color", colour}, {"size", 5}, {"symbol", kMarkers[k % 10]}};
        break;
      case SeriesStyle::kLines:
        t["mode"] = "lines";
        t["line"] = {{"color", colour}, {"width", 2}};
        break;
      case SeriesStyle::kLinesPoints:
        t["mode"] = "lines+markers";
        t["line"] = {{"color", colour}, {"width", 2}};
        t["marker"] = {{"color", colour}, {"size", 6}, {"symbol", kMarkers[k % 10]}};
        break;
    }
    data.push_back(t);
  }
  json layout = BaseLayout(panel.title);
  layout["xaxis"] = Axis(panel.x_label);
  layout["yaxis"] = Axis(panel.y_label);
  if (panel.log_y) layout["yaxis"]["type"] = "log";
  layout["height"] = 380;
  return json{{"data", data}, {"layout", layout}}.dump();
}

std::string PlotlyCloudJson(const Cloud3d& cloud) {
  const size_t n = cloud.xyz.size() / 3;
  const size_t step = cloud.max_points > 0 && n > cloud.max_points ? (n + cloud.max_points - 1) / cloud.max_points : 1;
  json x = json::array(), y = json::array(), z = json::array(), c = json::array();
  const bool coloured = cloud.colour_value.size() == n && n > 0;
  for (size_t i = 0; i < n; i += step) {
    x.push_back(std::round(cloud.xyz[3 * i] * 1e4) / 1e4);
    y.push_back(std::round(cloud.xyz[3 * i + 1] * 1e4) / 1e4);
    z.push_back(std::round(cloud.xyz[3 * i + 2] * 1e4) / 1e4);
    if (coloured) c.push_back(std::isfinite(cloud.colour_value[i]) ? json(std::round(cloud.colour_value[i] * 100) / 100)
                                                                    : json(nullptr));
  }
  json points = {{"type", "scatter3d"}, {"mode", "markers"}, {"x", x}, {"y", y}, {"z", z},
                 {"name", "points" + std::string(step > 1 ? " (every " + std::to_string(step) + ")" : "")}};
  if (coloured)
    points["marker"] = cloud.diverging
                           ? json{{"size", 1.6}, {"color", c}, {"colorscale", "RdBu"}, {"reversescale", true},
                                  {"cmid", 0}, {"colorbar", {{"title", {{"text", cloud.colour_label}}}}}}
                           : json{{"size", 1.6}, {"color", c}, {"colorscale", "Viridis"},
                                  {"colorbar", {{"title", {{"text", cloud.colour_label}}}}}};
  else
    points["marker"] = {{"size", 1.6}, {"color", SeriesColour(0)}};
  json data = json::array({points});
  if (cloud.sphere_radius > 0) {
    const int nu = 25, nv = 49;
    json sx = json::array(), sy = json::array(), sz = json::array();
    for (int i = 0; i < nu; ++i) {
      json rx = json::array(), ry = json::array(), rz = json::array();
      const double th = M_PI * i / (nu - 1);
      for (int j = 0; j < nv; ++j) {
        const double ph = 2 * M_PI * j / (nv - 1);
        rx.push_back(cloud.sphere_centre[0] + cloud.sphere_radius * std::sin(th) * std::cos(ph));
        ry.push_back(cloud.sphere_centre[1] + cloud.sphere_radius * std::sin(th) * std::sin(ph));
        rz.push_back(cloud.sphere_centre[2] + cloud.sphere_radius * std::cos(th));
      }
      sx.push_back(rx), sy.push_back(ry), sz.push_back(rz);
    }
    data.push_back({{"type", "surface"}, {"x", sx}, {"y", sy}, {"z", sz}, {"opacity", 0.25},
                    {"showscale", false}, {"colorscale", {{0, "#999999"}, {1, "#999999"}}},
                    {"name", "fitted sphere"}, {"showlegend", true}, {"hoverinfo", "skip"}});
  }
  json layout = BaseLayout(cloud.title);
  layout["height"] = 560;
  // Below the scene: the colour bar takes the right side.
  layout["legend"] = {{"orientation", "h"}, {"x", 0.0}, {"y", -0.02}, {"xanchor", "left"}, {"yanchor", "top"}};
  layout["scene"] = {{"aspectmode", "data"},
                     {"xaxis", {{"title", {{"text", "x (mm)"}}}}},
                     {"yaxis", {{"title", {{"text", "y (mm)"}}}}},
                     {"zaxis", {{"title", {{"text", "z (mm)"}}}}},
                     // Seen from the camera's side (cloud in a camera frame: z along the line of
                     // sight, y down), a little oblique so the depth reads.
                     {"camera", {{"eye", {{"x", 1.1}, {"y", -0.9}, {"z", -1.5}}}, {"up", {{"x", 0}, {"y", -1}, {"z", 0}}}}}};
  return json{{"data", data}, {"layout", layout}}.dump();
}

std::string FindPlotlyJs() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("RAMTK_PLOTLY_JS"); env && *env) return fs::exists(env) ? env : "";
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const fs::path& p : {exe.parent_path().parent_path() / "share/ramtk/plotly.min.js",
                              exe.parent_path() / "share/ramtk/plotly.min.js"})
      if (fs::exists(p, ec)) return p.string();
  }
#ifdef RAMTK_PLOTLY_JS_BUILD
  if (fs::exists(RAMTK_PLOTLY_JS_BUILD, ec)) return RAMTK_PLOTLY_JS_BUILD;
#endif
  if (fs::exists("/usr/share/python3-plotly/plotly.js", ec)) return "/usr/share/python3-plotly/plotly.js";
  return "";
}

}  // namespace ramtk::report
