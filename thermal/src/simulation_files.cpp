// The files of `ramtk simulate thermal` (docs/formats.md "Thermal experiment files").
#include <algorithm>
#include <nlohmann/json.hpp>

#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/simulator.h"

namespace ramtk::thermal {

void WriteThermalSimulation(const ThermalSimResult& r, const ThermalSimOptions& o, const std::string& preset,
                            const std::string& out_dir, bool overwrite, const Provenance& provenance) {
  // Every file into a staged folder, moved into place when complete (core/outputs.h).
  StagedFolder staged(out_dir, overwrite, "--out");
  const std::string dir = staged.path().string() + "/";
  kinematics::WriteRobotMeasurements(r.ball, dir + "ball.csv");
  kinematics::WriteRobotMeasurements(r.monitoring, dir + "monitoring.csv");
  WriteThermalSetup(r.setup, dir + "setup.json");
  WriteFileAtomically(dir + "truth_params.csv", TruthTrajectoriesCsv(r));
  nlohmann::json j;
  j["preset"] = preset;
  j["seed"] = o.seed;
  j["cycles"] = o.cycles;
  j["cycle_period_s"] = o.cycle_period_s;
  j["drifting_params"] = ParamListToString(r.drifting_params);
  j["sensor_noise_mm"] = o.sensor_noise_mm;
  j["tool_sensor_noise_mm"] = o.tool_sensor_noise_mm;
  j["repeatability_mm"] = o.repeatability_mm;
  for (const Vec3& p : r.monitoring_points_in_base) j["monitoring_points_in_base_mm"].push_back({p.x(), p.y(), p.z()});
  WriteFileAtomically(dir + "truth.json", j.dump(2) + "\n");
  const auto [path, text] = FolderProvenance(
      dir, {"ball.csv", "monitoring.csv", "setup.json", "truth_params.csv", "truth.json"}, provenance);
  WriteFileAtomically(path, text);
  staged.Commit();
}

double LargestBallDriftMm(const ThermalSimResult& r) {
  double max_drift = 0.0;
  for (const auto& row : r.ball.rows) {
    const Vec3 d = row.position_mm - r.ball.rows[row.index].position_mm;
    max_drift = std::max(max_drift, d.norm());
  }
  return max_drift;
}

}  // namespace ramtk::thermal
