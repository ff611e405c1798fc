#pragma once
// Shared simulated experiments for the thermal tests (fixed seeds, cached per seed).
#include <map>
#include <memory>
#include <string>

#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/monitoring.h"
#include "ramtk/thermal/simulator.h"

namespace ramtk::thermal::testing {

inline const kinematics::RobotModel& Kr150() {
  static const kinematics::RobotModel model =
      kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
  return model;
}

struct SimulatedExperiment {
  ThermalSimOptions options;
  ThermalSimResult sim;
  ThermalExperiment experiment;
};

inline const SimulatedExperiment& Thesis(std::uint64_t seed) {
  static std::map<std::uint64_t, std::unique_ptr<SimulatedExperiment>> cache;
  auto& slot = cache[seed];
  if (!slot) {
    auto e = std::make_unique<SimulatedExperiment>();
    e->options = ThesisPreset(seed);
    e->sim = SimulateThermal(Kr150(), e->options);
    e->experiment = MakeExperiment(Kr150(), e->sim.setup, GroupCycles(e->sim.ball, "ball.csv"),
                                   GroupCycles(e->sim.monitoring, "monitoring.csv"));
    slot = std::move(e);
  }
  return *slot;
}

}  // namespace ramtk::thermal::testing
