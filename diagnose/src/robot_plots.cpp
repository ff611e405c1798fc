#include "robot_plots.h"

#include <algorithm>
#include <filesystem>

#include "ramtk/core/units.h"
#include "ramtk/diagnose/plot.h"

namespace ramtk::diagnose::robot_detail {
namespace {

PlotSeries Series(const std::string& label, unsigned char r, unsigned char g, unsigned char b) {
  PlotSeries s;
  s.label = label;
  s.rgb[0] = r, s.rgb[1] = g, s.rgb[2] = b;
  return s;
}

// x, y, z components of a residual against one variable.
std::vector<PlotSeries> Components(const std::vector<double>& x, const std::vector<Eigen::Vector3d>& res) {
  std::vector<PlotSeries> s = {Series("x", 31, 119, 180), Series("y", 255, 127, 14), Series("z", 44, 160, 44)};
  for (size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 3; ++a) s[a].x.push_back(x[i]), s[a].y.push_back(res[i][a]);
  return s;
}

}  // namespace

void WriteRobotPictures(const RowSet& rs, const std::vector<Eigen::Vector3d>& before,
                        const std::vector<Eigen::Vector3d>& after, const std::vector<Eigen::Vector3d>& heldout_before,
                        const std::vector<Eigen::Vector3d>& heldout_after, double sigma,
                        const std::vector<std::string>& added, const Eigen::MatrixXd& added_series,
                        const std::string& cause, const std::string& folder, std::vector<Picture>* pictures) {
  const std::filesystem::path dir(folder);
  const size_t n = rs.rows.size();
  auto write = [&](const std::vector<PlotSeries>& s, const std::string& file, const std::string& title,
                   const std::string& x_label, const std::string& y_label, double band, const std::string& caption) {
    PlotOptions o;
    o.title = title, o.x_label = x_label, o.y_label = y_label, o.band = band;
    WritePlot(s, o, (dir / file).string());
    pictures->push_back({file, caption});
  };
  auto column = [&](auto get) {
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = get(rs.rows[i]);
    return v;
  };
  const std::string res_label = "residual (mm)";
  write(Components(column([](const Row& r) { return r.time_h; }), before), "residual_vs_time.png",
        "current model: residual vs time", "time (h)", res_label, 2 * sigma,
        "Residual of the current model (x, y, z in the sensor frame) against time; grey band ±2σ of the noise.");
  write(Components(column([](const Row& r) { return static_cast<double>(r.pose); }), before), "residual_vs_pose.png",
        "current model: residual vs pose", "pose", res_label, 2 * sigma,
        "Residual of the current model against the pose number (all cycles).");
  for (int j = 0; j < 6; ++j) {
    const std::string q = "q" + std::to_string(j + 1);
    write(Components(column([j](const Row& r) { return RadToDeg(r.q[j]); }), before), "residual_vs_" + q + ".png",
          "current model: residual vs " + q, q + " (deg)", res_label, 2 * sigma,
          "Residual of the current model against joint " + std::to_string(j + 1) + ".");
  }
  for (const std::string& c : rs.extra_columns) {
    const auto v = column([&c](const Row& r) {
      const auto it = r.extra.find(c);
      return it == r.extra.end() ? 0.0 : it->second;
    });
    write(Components(v, before), "residual_vs_" + c + ".png", "current model: residual vs " + c, c, res_label,
          2 * sigma, "Residual of the current model against the extra column " + c + ".");
  }
  {
    PlotSeries b = Series("current model", 214, 39, 40), a = Series("with " + cause, 31, 119, 180);
    for (size_t i = 0; i < n; ++i) {
      b.x.push_back(rs.rows[i].time_h), b.y.push_back(heldout_before[i].norm());
      a.x.push_back(rs.rows[i].time_h), a.y.push_back(heldout_after[i].norm());
    }
    write({b, a}, "heldout_before_after.png", "held-out residual |r|: current vs extended model", "time (h)",
          "|residual| (mm)", 0.0,
          "Held-out residual length (cross-validated over poses) of the current model and of the extended one.");
  }
  {
    std::vector<PlotSeries> s = {Series("x", 31, 119, 180), Series("y", 255, 127, 14), Series("z", 44, 160, 44)};
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) s[a].x.push_back(rs.rows[i].time_h), s[a].y.push_back(after[i][a]);
    write(s, "residual_after_vs_time.png", "extended model (" + cause + "): residual vs time", "time (h)", res_label,
          2 * sigma, "Residual after the extension, against time.");
  }
  if (!added.empty() && added_series.cols() > 0) {
    std::vector<double> t(added_series.cols(), 0.0);
    std::vector<int> count(t.size(), 0);
    for (const Row& r : rs.rows) t[r.cycle_pos] += r.time_h, ++count[r.cycle_pos];
    for (size_t c = 0; c < t.size(); ++c) t[c] /= std::max(1, count[c]);
    static const unsigned char palette[8][3] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                                                {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127}};
    std::vector<PlotSeries> s;
    for (size_t k = 0; k < added.size(); ++k) {
      PlotSeries p = Series(added[k], palette[k % 8][0], palette[k % 8][1], palette[k % 8][2]);
      p.line = true;
      p.x = t;
      for (int c = 0; c < added_series.cols(); ++c) p.y.push_back(added_series(k, c));
      s.push_back(p);
    }
    write(s, "drift_parameters.png", "per-cycle drift of the added parameters", "time (h)", "urad / mm", 0.0,
          "Per-cycle estimates of the parameters the extension adds (angles in µrad, lengths in mm).");
  }
}

}  // namespace ramtk::diagnose::robot_detail
