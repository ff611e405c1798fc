// The campaign digital twin: simulation of the image sets and the controller log (campaign.h).
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <utility>

#include "campaign_internal.h"
#include "ramtk/campaign/controller_log.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/thermal/simulator.h"
#include "ramtk/vision/sim/fringe_simulator.h"

namespace ramtk::campaign {
namespace fs = std::filesystem;

std::string CampaignOptions::Validate() const {
  if (cycles < 2) return "cycles must be >= 2 (a cold reference and a warm cycle)";
  if (ball_poses < 5) return "ball_poses must be >= 5 (the sensor-to-robot calibration needs 5)";
  if (monitoring_points < 1) return "monitoring_points must be >= 1";
  if (!(cycle_period_s > 0.0)) return "cycle_period_s must be > 0";
  if (!(image_scale > 0.05 && image_scale <= 1.0)) return "image_scale must be in (0.05, 1]";
  if (supersampling < 1 || supersampling > 8) return "supersampling must be in 1..8";
  for (const auto& [field, value] : {std::pair<const char*, double>{"repeatability_mm", repeatability_mm},
                                     {"tool_sensor_noise_mm", tool_sensor_noise_mm}}) {
    if (std::string bad = CheckNoise(field, value, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  }
  if (jobs < 1) return "jobs must be >= 1";
  if (!(scan_min_depth_mm > 0.0 && scan_max_depth_mm > scan_min_depth_mm))
    return "scan depth range: expected 0 < scan_min_depth_mm < scan_max_depth_mm";
  if (screen_keep < -1 || screen_keep > 30) return "screen_keep must be -1 (skip), 0 (held-out) or a count up to 30";
  return "";
}

namespace internal {

std::string SetName(int cycle, int pose) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "c%03d_p%02d", cycle, pose);
  return buf;
}

vision::FringeSimulationConfig CampaignFringeConfig(const Vec3& ball_in_left, double scale, int supersampling,
                                                    std::uint64_t seed) {
  vision::FringeSimulationConfig c = vision::ScaleCameraWindows(vision::MakeFringePreset("small", ball_in_left), scale);
  c.supersampling = supersampling;
  c.seed = seed;
  return c;
}

CampaignFiles SimulateCampaignFiles(const kinematics::RobotModel& model, const CampaignOptions& o,
                                    const std::string& out_dir, double* render_s) {
  thermal::ThermalSimOptions to = thermal::ThesisPreset(o.seed);
  to.cycles = o.cycles;
  to.ball_poses = o.ball_poses;
  to.monitoring_points = o.monitoring_points;
  to.cycle_period_s = o.cycle_period_s;
  to.sensor_noise_mm = 0.0;  // the vision stage makes the centre noise
  to.tool_sensor_noise_mm = o.tool_sensor_noise_mm;
  to.repeatability_mm = o.repeatability_mm;
  to.drift_changes_within_cycle = o.drift_changes_within_cycle;
  if (o.cold_reference) to.duty.insert(to.duty.begin(), thermal::DutyPhase{o.cycle_period_s, 0.0});
  // Ball poses inside what both cameras and the projector see at 700 mm.
  to.sensor_field_mm = Vec3(240.0, 180.0, 100.0);
  CampaignFiles f;
  f.sim = thermal::SimulateThermal(model, to);
  f.out_dir = out_dir;
  std::error_code ec;
  fs::create_directories(fs::path(out_dir) / "sets", ec);
  fs::create_directories(fs::path(out_dir) / "truth", ec);
  if (ec) throw InputError({out_dir, 0, "--out"}, "cannot create the folder: " + ec.message());

  // Controller log and batch list (one capture per ball row).
  ControllerLog log;
  log.has_set = true;
  log.extra_columns = f.sim.ball.extra_columns;
  std::string batch = "# fringe sets of the simulated campaign, one per cycle and pose\n";
  for (const auto& row : f.sim.ball.rows) {
    ControllerLogRow r;
    r.set = SetName(row.cycle, row.index);
    r.time_s = row.time_s;
    r.cycle = row.cycle;
    r.pose = row.index;
    r.q_controller = row.q_controller;
    r.extra = row.extra;
    log.rows.push_back(r);
    batch += "sets/" + r.set + "/manifest.json\n";
  }
  // Render every set (ball centre = the true ball_in_sensor of that measurement).
  const auto t0 = std::chrono::steady_clock::now();
  const auto& rows = f.sim.ball.rows;
  std::mutex mutex;
  std::size_t done = 0;
  bool cancelled = false;
  tbb::task_arena arena(o.jobs);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, rows.size(), std::size_t{1}, [&](std::size_t i) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (cancelled) return;
      }
      const auto& row = rows[i];
      const std::string dir = (fs::path(out_dir) / "sets" / SetName(row.cycle, row.index)).string();
      const vision::FringeSimulationConfig config =
          CampaignFringeConfig(row.position_mm, o.image_scale, o.supersampling, o.seed * 100003u + i);
      vision::SimulateFringeSet(config, dir, false);
      // The capture time on the controller's clock, for matching by time.
      const std::string manifest = dir + "/manifest.json";
      nlohmann::json j = ParseJsonText(ReadTextFile(manifest), manifest);
      j["capture_time_s"] = row.time_s;
      WriteFileAtomically(manifest, j.dump(2) + "\n");
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (o.progress && !cancelled) cancelled = !o.progress({"render", done, rows.size()});
    });
  });
  *render_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  f.cancelled = cancelled;
  if (cancelled) return f;
  WriteFileAtomically((fs::path(out_dir) / "controller_log.csv").string(), FormatControllerLog(log));
  WriteFileAtomically((fs::path(out_dir) / "batch.txt").string(), batch);
  kinematics::WriteRobotMeasurements(f.sim.monitoring, (fs::path(out_dir) / "monitoring.csv").string());
  kinematics::WriteRobotMeasurements(f.sim.ball, (fs::path(out_dir) / "truth" / "ball_truth.csv").string());
  thermal::WriteThermalSetup(f.sim.setup, (fs::path(out_dir) / "truth" / "setup.json").string());
  WriteFileAtomically((fs::path(out_dir) / "truth" / "truth_params.csv").string(),
                      thermal::TruthTrajectoriesCsv(f.sim));
  f.options = to;
  return f;
}

}  // namespace internal
}  // namespace ramtk::campaign
