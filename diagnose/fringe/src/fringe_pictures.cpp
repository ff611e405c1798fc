// Pictures of the ideal model's residual against the variables that could explain it: fringe phase
// (projector response, phase steps), frame index (drift), image position (regions, defocus,
// saturation on bright parts) and intensity level (saturation, response).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <random>

#include "fringe_internal.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/vision/fringe/image_io.h"

namespace ramtk::diagnose::fringe {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Mean of y in `bins` equal bins of x over [lo, hi].
report::Series Binned(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi, int bins,
                      const std::string& label) {
  std::vector<double> sum(bins, 0.0);
  std::vector<long> n(bins, 0);
  for (size_t i = 0; i < x.size(); ++i) {
    const int k = std::clamp(static_cast<int>((x[i] - lo) / (hi - lo) * bins), 0, bins - 1);
    sum[k] += y[i], ++n[k];
  }
  report::Series s;
  s.label = label;
  s.style = report::SeriesStyle::kLines;
  for (int k = 0; k < bins; ++k)
    if (n[k] >= 20) s.x.push_back(lo + (k + 0.5) * (hi - lo) / bins), s.y.push_back(sum[k] / n[k]);
  return s;
}

}  // namespace

std::vector<Picture> WriteFringePictures(const FringeFit& fit, double floor, const std::string& folder,
                                         unsigned long long seed) {
  std::filesystem::create_directories(folder);
  std::vector<Picture> out;
  const int nf = fit.frames;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, fit.pixels.size() - 1);

  // Residual against the fringe phase θ_k = φ + δ_k (phase-shift frames).
  {
    std::vector<double> th, r;
    report::Series dots;
    dots.label = "sampled residuals";
    for (size_t i = 0; i < fit.pixels.size(); ++i)
      for (int k = 0; k < fit.steps; ++k) {
        const double t = std::remainder(fit.pixels[i].phi + StepShift(k, fit.steps), 2 * kPi) * 180.0 / kPi;
        th.push_back(t);
        r.push_back(fit.residual[i * nf + fit.phase_frame[k]]);
      }
    std::uniform_int_distribution<size_t> any(0, th.size() - 1);
    for (int s = 0; s < 4000; ++s) {
      const size_t k = any(rng);
      dots.x.push_back(th[k]), dots.y.push_back(r[k]);
    }
    AddFigure(OnePanel("residual_vs_phase",
                       "Residual of the phase-shift frames against the fringe phase; a periodic mean is projector "
                       "response (harmonics) or phase-step error; the grey band is ± the noise floor.",
                       "Residual of the ideal model vs fringe phase (phase-shift frames)",
                       "fringe phase θ = φ + δk (deg)", "measured − model (DN)",
                       {dots, Binned(th, r, -180, 180, 72, "mean per 5°")}, floor),
              folder, &out);
  }
  // Residual per frame.
  {
    report::Series rms, mean;
    rms.label = "RMS", mean.label = "mean";
    rms.style = mean.style = report::SeriesStyle::kLinesPoints;
    for (int f = 0; f < nf; ++f) {
      double s = 0, s2 = 0;
      long m = 0;
      for (size_t i = 0; i < fit.pixels.size(); ++i) {
        const double v = fit.residual[i * nf + f];
        if (std::isfinite(v)) s += v, s2 += v * v, ++m;
      }
      if (m == 0) continue;
      rms.x.push_back(f), rms.y.push_back(std::sqrt(s2 / m));
      mean.x.push_back(f), mean.y.push_back(s / m);
    }
    AddFigure(OnePanel("residual_vs_frame",
                       "RMS and mean residual per frame: a trend is intensity drift, a step between blocks a level "
                       "mismatch of the Gray-code frames.",
                       "Residual per frame (0.." + std::to_string(fit.steps - 1) + " phase shift, then Gray code)",
                       "frame index", "residual (DN)", {rms, mean}, floor),
              folder, &out);
  }
  // Residual against the ideal intensity level.
  {
    std::vector<double> lp, rp, lg, rg;
    for (int s = 0; s < 200000; ++s) {
      const size_t i = pick(rng);
      const int f = static_cast<int>(rng() % nf);
      const double level = IdealIntensity(fit, fit.pixels[i], f);
      if (!std::isfinite(fit.residual[i * nf + f])) continue;
      const bool phase = std::find(fit.phase_frame.begin(), fit.phase_frame.end(), f) != fit.phase_frame.end();
      (phase ? lp : lg).push_back(level);
      (phase ? rp : rg).push_back(fit.residual[i * nf + f]);
    }
    const double hi = std::max(fit.full_scale * 1.1, 1.0);
    AddFigure(OnePanel("residual_vs_level",
                       "Mean residual against the ideal intensity: a fall at the top is saturation, a curve over the "
                       "range a nonlinear response, an offset between the frame kinds a level mismatch.",
                       "Mean residual vs ideal intensity level", "ideal model intensity (DN)", "mean residual (DN)",
                       {Binned(lp, rp, 0, hi, 60, "phase-shift frames"), Binned(lg, rg, 0, hi, 60, "Gray-code frames")},
                       floor),
              folder, &out);
  }
  // Map of the per-pixel residual RMS.
  {
    cv::Mat map(fit.height, fit.width, CV_32F, cv::Scalar(0));
    std::vector<float> values;
    for (size_t i = 0; i < fit.pixels.size(); ++i) {
      double s2 = 0;
      int m = 0;
      for (int f = 0; f < nf; ++f)
        if (std::isfinite(fit.residual[i * nf + f])) s2 += std::pow(fit.residual[i * nf + f], 2), ++m;
      const float v = static_cast<float>(std::sqrt(s2 / std::max(m, 1)));
      map.at<float>(fit.pixels[i].y, fit.pixels[i].x) = v;
      values.push_back(v);
    }
    std::nth_element(values.begin(), values.begin() + values.size() * 99 / 100, values.end());
    const double top = std::max<double>(values[values.size() * 99 / 100], 3.0 * floor);
    cv::Mat u8;
    map.convertTo(u8, CV_8U, 255.0 / top);
    cv::Mat colour;
    cv::applyColorMap(u8, colour, cv::COLORMAP_TURBO);
    colour.setTo(cv::Scalar(0, 0, 0), fit.index < 0);
    const double scale = fit.width > 1000 ? 0.5 : 1.0;
    if (scale != 1.0) cv::resize(colour, colour, cv::Size(), scale, scale, cv::INTER_AREA);
    const std::string text = "residual RMS per pixel, 0 (blue) .. " +
                             std::to_string(static_cast<int>(std::round(top))) + " DN (red); black = not analysed";
    cv::putText(colour, text, {8, colour.rows - 10}, cv::FONT_HERSHEY_SIMPLEX,
                0.4 * colour.cols / 320.0 > 0.8 ? 0.8 : 0.4, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    vision::WriteImage(folder + "/residual_map.png", colour);
    out.push_back({"residual_map.png",
                   "Per-pixel RMS residual over all frames (black: not analysed); regions, code edges and bright "
                   "parts show where the ideal model fails."});
  }
  return out;
}

}  // namespace ramtk::diagnose::fringe
