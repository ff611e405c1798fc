// Sensor frame drift: the fixed sensor's rotation and translation, quadratic in time (sensor frame).
#include <Eigen/Geometry>

#include "../robot_fit_kit.h"

namespace ramtk::diagnose::robot_detail {
namespace {

void FitSensorFrameDrift(const Context& ctx, CauseOutput out) {
  std::vector<Mat3X> cols;
  for (const Row& r : ctx.rows->rows) {
    Mat3X m(3, 12);
    m.leftCols(6) = r.time_h * r.j_setup.leftCols(6);
    m.rightCols(6) = r.time_h * r.time_h * r.j_setup.leftCols(6);
    cols.push_back(m);
  }
  const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
  if (keep.empty()) return;
  static const char* names[6] = {"rx_urad", "ry_urad", "rz_urad", "tx_mm", "ty_mm", "tz_mm"};
  std::vector<std::string> col_names;
  std::vector<std::pair<std::string, double>> keys;
  for (int k : keep) {
    const std::string name = std::string(names[k % 6]) + (k < 6 ? "_per_h" : "_per_h2");
    col_names.push_back(name), keys.emplace_back(name, k % 6 < 3 ? 1e6 : 1.0);
  }
  FitColumns(ctx, out, "sensor_frame_drift", cols, keep, col_names, keys);
}

// The sensor turns and moves linearly in time (per hour).
void PlantSensorFrameDrift(PlantContext* p) {
  const Eigen::Vector3d w = p->random.Unit() * p->random.Uniform(30, 150) * 1e-6,
                        v = p->random.Unit() * p->random.Uniform(0.05, 0.3);
  p->draw->truth["rotation_urad_per_h"] = w.norm() * 1e6;
  p->draw->truth["translation_mm_per_h"] = v.norm();
  p->draw->description = "sensor drifts " + Fmt(w.norm() * 1e6) + " µrad/h and " + Fmt(v.norm()) + " mm/h";
  auto& rows = p->result->ball.rows;
  const double t0 = rows.empty() ? 0.0 : rows[0].time_s;
  for (auto& m : rows) {
    const double t = (m.time_s - t0) / 3600.0;
    m.position_mm = Eigen::AngleAxisd(w.norm() * t, w.normalized()) * m.position_mm + v * t;
  }
}

}  // namespace

const RobotCauseCode kSensorFrameDrift{3, "", true, FitSensorFrameDrift, nullptr, PlantSensorFrameDrift};

}  // namespace ramtk::diagnose::robot_detail
