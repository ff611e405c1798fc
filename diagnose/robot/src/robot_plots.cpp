#include "robot_plots.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "ramtk/core/units.h"
#include "ramtk/diagnose/engine/plot.h"

namespace ramtk::diagnose::robot_detail {
namespace {

report::Series Series(const std::string& label, report::SeriesStyle style = report::SeriesStyle::kPoints) {
  report::Series s;
  s.label = label;
  s.style = style;
  return s;
}

// x, y, z components of a residual against one variable.
std::vector<report::Series> Components(const std::vector<double>& x, const std::vector<Eigen::Vector3d>& res) {
  std::vector<report::Series> s = {Series("x"), Series("y"), Series("z")};
  for (size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 3; ++a) s[a].x.push_back(x[i]), s[a].y.push_back(res[i][a]);
  return s;
}

// Modified-DH lengths are a_i and d_i; every other parameter (alpha, beta, theta) is an angle.
bool IsLengthName(const std::string& name) {
  return name.size() >= 2 && (name[0] == 'a' || name[0] == 'd') && std::isdigit(static_cast<unsigned char>(name[1]));
}

}  // namespace

void WriteRobotPictures(const RowSet& rs, const std::vector<Eigen::Vector3d>& before,
                        const std::vector<Eigen::Vector3d>& after, const std::vector<Eigen::Vector3d>& heldout_before,
                        const std::vector<Eigen::Vector3d>& heldout_after, double sigma,
                        const std::vector<std::string>& added, const Eigen::MatrixXd& added_series,
                        const std::string& cause, const std::string& folder, std::vector<Picture>* pictures) {
  const size_t n = rs.rows.size();
  auto write = [&](std::vector<report::Series> s, const std::string& id, const std::string& title,
                   const std::string& x_label, const std::string& y_label, double band, const std::string& caption) {
    AddFigure(OnePanel(id, caption, title, x_label, y_label, std::move(s), band), folder, pictures);
  };
  auto column = [&](auto get) {
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = get(rs.rows[i]);
    return v;
  };
  const std::string res_label = "residual (mm)";
  write(Components(column([](const Row& r) { return r.time_h; }), before), "residual_vs_time",
        "current model: residual vs time", "time (h)", res_label, 2 * sigma,
        "Residual of the current model (x, y, z in the sensor frame) against time; grey band ±2σ of the noise.");
  write(Components(column([](const Row& r) { return static_cast<double>(r.pose); }), before), "residual_vs_pose",
        "current model: residual vs pose", "pose", res_label, 2 * sigma,
        "Residual of the current model against the pose number (all cycles).");
  for (int j = 0; j < 6; ++j) {
    const std::string q = "q" + std::to_string(j + 1);
    write(Components(column([j](const Row& r) { return RadToDeg(r.q[j]); }), before), "residual_vs_" + q,
          "current model: residual vs " + q, q + " (deg)", res_label, 2 * sigma,
          "Residual of the current model against joint " + std::to_string(j + 1) + ".");
  }
  for (const std::string& c : rs.extra_columns) {
    const auto v = column([&c](const Row& r) {
      const auto it = r.extra.find(c);
      return it == r.extra.end() ? 0.0 : it->second;
    });
    std::string id = "residual_vs_";
    for (char ch : c) id += std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ? ch : '_';
    write(Components(v, before), id, "current model: residual vs " + c, c, res_label, 2 * sigma,
          "Residual of the current model against the extra column " + c + ".");
  }
  {
    report::Series b = Series("current model"), a = Series("with " + cause);
    for (size_t i = 0; i < n; ++i) {
      b.x.push_back(rs.rows[i].time_h), b.y.push_back(heldout_before[i].norm());
      a.x.push_back(rs.rows[i].time_h), a.y.push_back(heldout_after[i].norm());
    }
    write({b, a}, "heldout_before_after", "held-out residual |r|: current vs extended model", "time (h)",
          "|residual| (mm)", 0.0,
          "Held-out residual length (cross-validated over poses) of the current model and of the extended one.");
  }
  {
    std::vector<report::Series> s = {Series("x"), Series("y"), Series("z")};
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) s[a].x.push_back(rs.rows[i].time_h), s[a].y.push_back(after[i][a]);
    write(s, "residual_after_vs_time", "extended model (" + cause + "): residual vs time", "time (h)", res_label,
          2 * sigma, "Residual after the extension, against time.");
  }
  if (!added.empty() && added_series.cols() > 0) {
    std::vector<double> t(added_series.cols(), 0.0);
    std::vector<int> count(t.size(), 0);
    for (const Row& r : rs.rows) t[r.cycle_pos] += r.time_h, ++count[r.cycle_pos];
    for (size_t c = 0; c < t.size(); ++c) t[c] /= std::max(1, count[c]);
    // One unit per axis: lengths (mm) and angles (µrad) in separate panels.
    report::Panel lengths, angles;
    lengths.title = "lengths", angles.title = "angles";
    lengths.x_label = angles.x_label = "time (h)";
    lengths.y_label = "drift (mm)", angles.y_label = "drift (µrad)";
    for (size_t k = 0; k < added.size(); ++k) {
      report::Series p = Series(added[k], report::SeriesStyle::kLinesPoints);
      p.x = t;
      for (int c = 0; c < added_series.cols(); ++c) p.y.push_back(added_series(k, c));
      (IsLengthName(added[k]) ? lengths : angles).series.push_back(std::move(p));
    }
    report::Figure f;
    f.id = "drift_parameters";
    f.title = "per-cycle drift of the added parameters";
    f.caption = "Per-cycle estimates of the parameters the extension adds: lengths in mm, angles in µrad.";
    if (!lengths.series.empty()) f.panels.push_back(lengths);
    if (!angles.series.empty()) f.panels.push_back(angles);
    AddFigure(f, folder, pictures);
  }
}

}  // namespace ramtk::diagnose::robot_detail
