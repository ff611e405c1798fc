// Temperature-driven drift: link lengths and the sensor translation linear in a measured
// temperature column (any extra column whose name contains "temp"); the best column kept.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "../robot_fit_kit.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::diagnose::robot_detail {
namespace {

void FitTemperatureDrivenDrift(const Context& ctx, CauseOutput out) {
  const std::vector<Row>& rows = ctx.rows->rows;
  const std::vector<int> lengths = thermal::TraditionalParams(ctx.input->model);
  Evaluated best;
  double best_score = INFINITY;
  for (const std::string& column : ctx.rows->extra_columns) {
    std::string lower = column;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (lower.find("temp") == std::string::npos) continue;
    double mean = 0;
    for (const Row& r : rows) {
      const auto it = r.extra.find(column);
      mean += it == r.extra.end() ? 0.0 : it->second;
    }
    mean /= std::max<size_t>(1, rows.size());
    std::vector<Mat3X> cols;
    for (const Row& r : rows) {
      const auto it = r.extra.find(column);
      const double dt = (it == r.extra.end() ? mean : it->second) - mean;
      Mat3X m(3, lengths.size() + 3);
      for (size_t k = 0; k < lengths.size(); ++k) m.col(k) = r.j_param.col(lengths[k]) * dt;
      m.rightCols(3) = r.j_setup.middleCols(3, 3) * dt;
      cols.push_back(m);
    }
    const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
    if (keep.empty()) continue;
    std::vector<std::string> names;
    std::vector<std::pair<std::string, double>> keys;
    for (int k : keep) {
      const std::string name = k < static_cast<int>(lengths.size())
                                   ? kinematics::ParamName(lengths[k]) + "_mm_per_K"
                                   : std::string(k - lengths.size() == 0 ? "tx" : k - lengths.size() == 1 ? "ty" : "tz") +
                                         "_mm_per_K";
      names.push_back(name), keys.emplace_back(name, 1.0);
    }
    Evaluated e;
    e.design = ctx.base;
    AddStaticColumns(SelectColumns(cols, keep), names, &e.design);
    e.cv = Cv(ctx, e.design);
    e.fit = MakeFit("temperature_driven_drift", static_cast<int>(keep.size()), e.cv);
    ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
    e.note = "temperature_driven_drift: lengths and sensor translation linear in column '" + column + "'";
    const double sc = Score(e.cv.heldout_ss, e.cv.heldout_n, e.fit.num_parameters);
    if (sc < best_score) best_score = sc, best = std::move(e);
  }
  if (std::isfinite(best_score))
    out.evaluated->push_back(std::move(best));
  else
    out.notes->push_back("temperature_driven_drift: no temperature column in the data");
}

}  // namespace

const RobotCauseCode kTemperatureDrivenDrift{1, "", true, FitTemperatureDrivenDrift, nullptr, nullptr};

}  // namespace ramtk::diagnose::robot_detail
