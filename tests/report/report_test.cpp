// ramtk::report: figures as gnuplot PNGs and Plotly charts, the self-contained HTML page. Truths:
// RFC 4648 base64 vectors, the figure's own data (round trip through the Plotly JSON), pixel
// content of the PNG (size, ink, the palette's colours), HTML escaping rules.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ramtk/core/file_io.h"
#include "ramtk/report/figure.h"
#include "ramtk/report/gnuplot.h"
#include "ramtk/report/html_report.h"
#include "ramtk/report/plotly.h"

namespace ramtk::report {
namespace {

namespace fs = std::filesystem;

std::string OutDir(const std::string& name) {
  const fs::path d = fs::path(RAMTK_TEST_OUTPUT_DIR) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

Figure TwoPanels() {
  Figure f;
  f.id = "drift";
  f.title = "drift of two kinds";
  Panel lengths, angles;
  lengths.title = "lengths", lengths.x_label = "time (h)", lengths.y_label = "drift (mm)";
  angles.title = "angles", angles.x_label = "time (h)", angles.y_label = "drift (µrad)";
  Series d1, d2, beta;
  d1.label = "d1", d2.label = "it's a_b {x}^2";  // quote and gnuplot enhanced-text characters
  beta.label = "beta2";
  d1.style = SeriesStyle::kLinesPoints, d2.style = SeriesStyle::kLines, beta.style = SeriesStyle::kPoints;
  for (int i = 0; i < 40; ++i) {
    const double t = 0.1 * i;
    d1.x.push_back(t), d1.y.push_back(0.05 * (1 - std::exp(-t)));
    d2.x.push_back(t), d2.y.push_back(-0.03 * (1 - std::exp(-t / 2)));
    beta.x.push_back(t), beta.y.push_back(120 * (1 - std::exp(-t)));
    beta.y_low.push_back(beta.y.back() - 10), beta.y_high.push_back(beta.y.back() + 10);
  }
  d1.y[5] = NAN;  // a gap
  lengths.series = {d1, d2};
  lengths.zero_band = 0.01;
  angles.series = {beta};
  f.panels = {lengths, angles};
  return f;
}

cv::Vec3b Bgr(const char* hex) {
  const unsigned v = static_cast<unsigned>(std::strtoul(hex + 1, nullptr, 16));
  return cv::Vec3b(v & 255, (v >> 8) & 255, (v >> 16) & 255);
}

int CountNear(const cv::Mat& img, cv::Vec3b c, int tol) {
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
      if (std::abs(p[0] - c[0]) <= tol && std::abs(p[1] - c[1]) <= tol && std::abs(p[2] - c[2]) <= tol) ++n;
    }
  return n;
}

TEST(ReportFigure, RefusesFiguresThatCannotBeDrawn) {
  Figure f = TwoPanels();
  f.panels[0].series[0].y.pop_back();
  EXPECT_THROW(CheckFigure(f), std::invalid_argument);
  f = TwoPanels();
  f.id = "bad id";
  EXPECT_THROW(CheckFigure(f), std::invalid_argument);
  f = TwoPanels();
  f.panels[1].series[0].y_low.pop_back();
  EXPECT_THROW(CheckFigure(f), std::invalid_argument);
  f = TwoPanels();
  f.panels.clear();
  EXPECT_THROW(CheckFigure(f), std::invalid_argument);
  EXPECT_NO_THROW(CheckFigure(TwoPanels()));
}

TEST(ReportFigure, PaletteColoursAreDistinct) {
  for (int a = 0; a < 7; ++a)
    for (int b = a + 1; b < 7; ++b) EXPECT_STRNE(SeriesColour(a), SeriesColour(b));
}

TEST(ReportGnuplot, PngHasTheExpectedSizeInkAndSeriesColours) {
  if (FindGnuplot().empty()) GTEST_SKIP() << "gnuplot not installed (Debian gnuplot-nox)";
  const std::string dir = OutDir("png");
  const std::string png = dir + "/drift.png";
  PngOptions o;
  WritePng(TwoPanels(), png, o);
  const cv::Mat img = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, o.width);
  EXPECT_EQ(img.rows, 2 * o.panel_height + 40);  // two panels and the title line
  // Ink: not blank, not flooded.
  const int white = CountNear(img, cv::Vec3b(255, 255, 255), 8);
  const double ink = 1.0 - static_cast<double>(white) / img.total();
  EXPECT_GT(ink, 0.02);
  EXPECT_LT(ink, 0.5);
  // Each series is drawn in its palette colour (the lengths panel's two series, the angle series
  // in colour 0 of its own panel).
  EXPECT_GT(CountNear(img, Bgr(SeriesColour(0)), 20), 200);
  EXPECT_GT(CountNear(img, Bgr(SeriesColour(1)), 20), 100);
  // No temporaries left beside the output.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "drift.png");
  }
  EXPECT_EQ(files, 1);
}

TEST(ReportGnuplot, MissingProgramIsAClearErrorAndWritesNothing) {
  const std::string dir = OutDir("nognuplot");
  PngOptions o;
  o.gnuplot = "/nonexistent/gnuplot";
  EXPECT_EQ(FindGnuplot(o), "");
  try {
    WritePng(TwoPanels(), dir + "/x.png", o);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot not found"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ReportGnuplot, ScriptQuotesLabelsAndKeepsOneUnitPerAxis) {
  const std::string script = GnuplotScript(TwoPanels(), "/tmp/x.png");
  EXPECT_NE(script.find("title 'it''s a_b {x}^2'"), std::string::npos);
  EXPECT_NE(script.find("set ylabel 'drift (mm)'"), std::string::npos);
  EXPECT_NE(script.find("set ylabel 'drift (µrad)'"), std::string::npos);
  EXPECT_NE(script.find("noenhanced"), std::string::npos);
  EXPECT_NE(script.find("set key outside"), std::string::npos);
}

TEST(ReportPlotly, PanelJsonCarriesTheDataColoursAndAxes) {
  const Figure f = TwoPanels();
  const nlohmann::json p0 = nlohmann::json::parse(PlotlyPanelJson(f.panels[0]));
  // The noise band trace, then the two series.
  ASSERT_EQ(p0["data"].size(), 3u);
  EXPECT_EQ(p0["data"][0]["fill"], "toself");
  EXPECT_EQ(p0["data"][1]["name"], "d1");
  EXPECT_EQ(p0["data"][1]["line"]["color"], SeriesColour(0));
  EXPECT_EQ(p0["data"][2]["line"]["color"], SeriesColour(1));
  EXPECT_TRUE(p0["data"][1]["y"][5].is_null());  // NaN becomes a gap
  EXPECT_DOUBLE_EQ(p0["data"][1]["y"][6].get<double>(), f.panels[0].series[0].y[6]);
  EXPECT_EQ(p0["layout"]["yaxis"]["title"]["text"], "drift (mm)");
  EXPECT_GT(p0["layout"]["legend"]["x"].get<double>(), 1.0);  // legend outside the data
  const nlohmann::json p1 = nlohmann::json::parse(PlotlyPanelJson(f.panels[1]));
  // Band upper edge, band lower edge (filled to the upper), then the series.
  ASSERT_EQ(p1["data"].size(), 3u);
  EXPECT_EQ(p1["data"][1]["fill"], "tonexty");
  EXPECT_DOUBLE_EQ(p1["data"][0]["y"][3].get<double>(), f.panels[1].series[0].y_high[3]);
  EXPECT_DOUBLE_EQ(p1["data"][1]["y"][3].get<double>(), f.panels[1].series[0].y_low[3]);
  EXPECT_EQ(p1["layout"]["yaxis"]["title"]["text"], "drift (µrad)");
}

TEST(ReportPlotly, CloudIsSubsampledAndCarriesTheSphere) {
  Cloud3d c;
  c.max_points = 1000;
  for (int i = 0; i < 10000; ++i) c.xyz.insert(c.xyz.end(), {float(i), 0.f, 1.f});
  c.sphere_radius = 19.05;
  c.sphere_centre[2] = 700;
  const nlohmann::json j = nlohmann::json::parse(PlotlyCloudJson(c));
  ASSERT_EQ(j["data"].size(), 2u);
  EXPECT_LE(j["data"][0]["x"].size(), 1000u);
  EXPECT_GE(j["data"][0]["x"].size(), 900u);
  EXPECT_EQ(j["data"][1]["type"], "surface");
  // Every surface vertex lies on the sphere.
  const auto& sx = j["data"][1]["x"];
  for (size_t i = 0; i < sx.size(); i += 5)
    for (size_t k = 0; k < sx[i].size(); k += 7) {
      const double x = sx[i][k], y = j["data"][1]["y"][i][k], z = j["data"][1]["z"][i][k];
      EXPECT_NEAR(std::sqrt(x * x + y * y + (z - 700) * (z - 700)), 19.05, 1e-9);
    }
}

TEST(ReportHtml, EscapesTextKeepsScriptsClosedAndInlinesImages) {
  const std::string dir = OutDir("html");
  // RFC 4648 test vectors through the data URI.
  WriteFileAtomically(dir + "/a.png", "Man");
  WriteFileAtomically(dir + "/b.png", "Ma");
  WriteFileAtomically(dir + "/c.png", "M");
  HtmlReport r("A <title> & more");
  r.Section("figures");
  Figure f = TwoPanels();
  f.panels[0].series[0].label = "</script><b>";
  r.AddFigure(f);
  r.AddImage("img-a", dir + "/a.png", "a");
  r.AddImage("img-b", dir + "/b.png", "b");
  r.AddImage("img-c", dir + "/c.png", "c");
  r.Table({"x"}, {{"1 < 2"}});
  const std::string html = r.Html("/* library */");
  EXPECT_NE(html.find("<title>A &lt;title&gt; &amp; more</title>"), std::string::npos);
  EXPECT_NE(html.find("<td>1 &lt; 2</td>"), std::string::npos);
  EXPECT_NE(html.find("base64,TWFu\""), std::string::npos);
  EXPECT_NE(html.find("base64,TWE=\""), std::string::npos);
  EXPECT_NE(html.find("base64,TQ==\""), std::string::npos);
  // The label's "</script>" must not close a script element: every "</script>" ends one of the
  // page's four scripts (error hook, library, charts).
  size_t closes = 0;
  for (size_t p = html.find("</script>"); p != std::string::npos; p = html.find("</script>", p + 1)) ++closes;
  EXPECT_EQ(closes, 3u);
  const std::vector<std::string> ids = {"drift", "img-a", "img-b", "img-c"};
  EXPECT_EQ(r.element_ids(), ids);
  EXPECT_NE(html.find("id=\"drift-panel0\""), std::string::npos);
  EXPECT_NE(html.find("id=\"drift-panel1\""), std::string::npos);
}

TEST(ReportHtml, WriteInlinesTheLibrary) {
  if (FindPlotlyJs().empty()) GTEST_SKIP() << "Plotly.js not found (Debian python3-plotly)";
  const std::string dir = OutDir("write");
  HtmlReport r("page");
  r.AddFigure(TwoPanels());
  r.Write(dir + "/report.html");
  const std::string html = ReadTextFile(dir + "/report.html");
  EXPECT_NE(html.find("plotly.js v2"), std::string::npos);
  EXPECT_EQ(html.find("<script src="), std::string::npos);  // nothing fetched
  EXPECT_EQ(html.find("<link "), std::string::npos);
}

}  // namespace
}  // namespace ramtk::report
