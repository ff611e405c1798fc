#include "ramtk/diagnose/plot.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "ramtk/core/file_io.h"

namespace ramtk::diagnose {
namespace {

std::string Tick(double v) {
  std::ostringstream out;
  out.precision(3);
  out << v;
  return out.str();
}

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// Width in pixels of a one-line text at the given font scale.
int TextWidth(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline).width;
}

cv::Scalar Bgr(const unsigned char rgb[3]) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

}  // namespace

void WritePlot(const std::vector<PlotSeries>& series, const PlotOptions& o, const std::string& png_path) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const PlotSeries& s : series) {
    if (s.x.size() != s.y.size()) throw std::invalid_argument("plot series x and y differ in length");
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
    }
  }
  if (!(x0 <= x1)) throw std::invalid_argument("nothing to plot");
  if (o.band > 0) y0 = std::min(y0, -o.band), y1 = std::max(y1, o.band);
  if (x1 - x0 < 1e-12) x0 -= 0.5, x1 += 0.5;
  if (y1 - y0 < 1e-12) y0 -= 0.5, y1 += 0.5;
  const double pad_y = 0.05 * (y1 - y0);
  y0 -= pad_y, y1 += pad_y;

  cv::Mat img(o.height, o.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 90, right = 20, top = 58, bottom = 60;
  const int w = o.width - left - right, h = o.height - top - bottom;
  auto px = [&](double x) { return left + static_cast<int>(std::lround((x - x0) / (x1 - x0) * w)); };
  auto py = [&](double y) { return top + h - static_cast<int>(std::lround((y - y0) / (y1 - y0) * h)); };
  const auto font = kFont;
  const cv::Scalar grey(200, 200, 200), black(0, 0, 0);

  if (o.band > 0) {
    cv::rectangle(img, cv::Point(left, py(o.band)), cv::Point(left + w, py(-o.band)), cv::Scalar(235, 235, 235),
                  cv::FILLED);
  }
  for (int k = 0; k <= 5; ++k) {
    const double xv = x0 + (x1 - x0) * k / 5, yv = y0 + (y1 - y0) * k / 5;
    cv::line(img, cv::Point(px(xv), top), cv::Point(px(xv), top + h), grey, 1);
    cv::line(img, cv::Point(left, py(yv)), cv::Point(left + w, py(yv)), grey, 1);
    cv::putText(img, Tick(xv), cv::Point(px(xv) - 20, top + h + 20), font, 0.45, black, 1, cv::LINE_AA);
    cv::putText(img, Tick(yv), cv::Point(5, py(yv) + 5), font, 0.45, black, 1, cv::LINE_AA);
  }
  if (y0 < 0 && y1 > 0) cv::line(img, cv::Point(left, py(0)), cv::Point(left + w, py(0)), cv::Scalar(120, 120, 120), 1);
  cv::rectangle(img, cv::Point(left, top), cv::Point(left + w, top + h), black, 1);

  // Legend box width from the widest label so it stays inside the frame.
  int legend_width = 0;
  for (const PlotSeries& s : series)
    if (!s.label.empty()) legend_width = std::max(legend_width, TextWidth(s.label, 0.45));
  const int legend_x = left + w - legend_width - 35;
  int legend_y = top + 18;
  for (const PlotSeries& s : series) {
    const cv::Scalar c = Bgr(s.rgb);
    if (s.line) {
      std::vector<size_t> order(s.x.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return s.x[a] < s.x[b]; });
      for (size_t k = 1; k < order.size(); ++k)
        cv::line(img, cv::Point(px(s.x[order[k - 1]]), py(s.y[order[k - 1]])),
                 cv::Point(px(s.x[order[k]]), py(s.y[order[k]])), c, 2, cv::LINE_AA);
    } else {
      for (size_t i = 0; i < s.x.size(); ++i)
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
          cv::circle(img, cv::Point(px(s.x[i]), py(s.y[i])), 2, c, cv::FILLED, cv::LINE_AA);
    }
    if (!s.label.empty()) {
      cv::line(img, cv::Point(legend_x, legend_y - 4), cv::Point(legend_x + 20, legend_y - 4), c, 3);
      cv::putText(img, s.label, cv::Point(legend_x + 25, legend_y), font, 0.45, black, 1, cv::LINE_AA);
      legend_y += 18;
    }
  }
  // Title on the first line, the y-axis label on the second (never over each other); the x-axis
  // label centred under the frame and kept inside the image.
  cv::putText(img, o.title, cv::Point(left, 22), font, 0.6, black, 1, cv::LINE_AA);
  cv::putText(img, o.y_label, cv::Point(5, top - 10), font, 0.45, black, 1, cv::LINE_AA);
  const int x_label_width = TextWidth(o.x_label, 0.5);
  const int x_label_x = std::clamp(left + (w - x_label_width) / 2, 5, std::max(5, o.width - x_label_width - 5));
  cv::putText(img, o.x_label, cv::Point(x_label_x, o.height - 15), font, 0.5, black, 1, cv::LINE_AA);

  std::vector<unsigned char> png;
  if (!cv::imencode(".png", img, png)) throw std::runtime_error("could not encode " + png_path);
  WriteFileAtomically(png_path, std::string(png.begin(), png.end()));
}

}  // namespace ramtk::diagnose
