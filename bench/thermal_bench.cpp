// Thermal drift on the thesis preset (KR150, 90 cycles, 20 ball poses, 34 monitoring points):
// identification of all cycles (eq. 3-10, Eigen BDCSVD) beside the same solve by normal
// equations (Cholesky of AᵀA, the usual shortcut), and the whole screening of Fig. 3-5.
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>

#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/thermal/simulator.h"

namespace {

using namespace ramtk;
using namespace ramtk::thermal;

struct Data {
  kinematics::RobotModel model;
  ThermalSimResult sim;
  ThermalExperiment experiment;
};

const Data& GetData() {
  static const Data data = [] {
    Data d;
    d.model = kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
    d.sim = SimulateThermal(d.model, ThesisPreset(1));
    d.experiment =
        MakeExperiment(d.model, d.sim.setup, GroupCycles(d.sim.ball, "ball"), GroupCycles(d.sim.monitoring, "mon"));
    return d;
  }();
  return data;
}

void BM_IdentifyCycles_Svd(benchmark::State& state) {
  const Data& d = GetData();
  const DriftModel dm(d.model, d.sim.setup, d.experiment.ball.taught);
  const Eigen::MatrixXd y = d.experiment.ball.DifferencesFromReference();
  IdentificationOptions id;
  id.params = d.sim.drifting_params;
  for (auto _ : state) benchmark::DoNotOptimize(dm.Solve(y, id));
}
BENCHMARK(BM_IdentifyCycles_Svd);

void BM_IdentifyCycles_NormalEquations(benchmark::State& state) {
  const Data& d = GetData();
  const DriftModel dm(d.model, d.sim.setup, d.experiment.ball.taught);
  const Eigen::MatrixXd y = d.experiment.ball.DifferencesFromReference();
  Eigen::MatrixXd a(dm.FullSensitivity().rows(), d.sim.drifting_params.size());
  for (std::size_t c = 0; c < d.sim.drifting_params.size(); ++c)
    a.col(c) = dm.FullSensitivity().col(d.sim.drifting_params[c]);
  for (auto _ : state) {
    const Eigen::MatrixXd x = (a.transpose() * a).ldlt().solve(a.transpose() * y);
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_IdentifyCycles_NormalEquations);

void BM_ScreenThesisPreset(benchmark::State& state) {
  const Data& d = GetData();
  for (auto _ : state) benchmark::DoNotOptimize(ScreenParameters(d.experiment, {}));
}
BENCHMARK(BM_ScreenThesisPreset)->Unit(benchmark::kMillisecond);

void BM_SimulateThesisPreset(benchmark::State& state) {
  const Data& d = GetData();
  for (auto _ : state) benchmark::DoNotOptimize(SimulateThermal(d.model, ThesisPreset(2)));
}
BENCHMARK(BM_SimulateThesisPreset)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
