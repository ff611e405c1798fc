// Sphere extraction beside PCL's RANSAC sphere fit (SACSegmentation, SACMODEL_SPHERE, optimized
// coefficients) on the same synthetic clouds: the visible cap of a 38.1 mm ball at 700 mm with
// a backdrop plane and outliers. Arg 0: the cap at 0.5 mm ray pitch (~3.8k ball points, ~10k in
// all); arg 1: 0.15 mm pitch, about a 3312x2488 camera's footprint (~42k ball points, ~90k in
// all). Read the ratio ramtk/PCL; the machine is shared.
#include <benchmark/benchmark.h>

#include "ramtk/vision/sphere/sphere_fit.h"
#include "sphere_pcl_peer.h"
#include "sphere_synth.h"

namespace {

using namespace ramtk::vision;

const test::SynthCloud& Cloud(int which) {
  static const test::SynthCloud clouds[2] = {[] {
                                               test::CapScene s;
                                               return test::MakeCapCloud(s, 1);
                                             }(),
                                             [] {
                                               test::CapScene s;
                                               s.pitch_mm = 0.15;
                                               s.backdrop_pitch_mm = 0.3;
                                               return test::MakeCapCloud(s, 1);
                                             }()};
  return clouds[which];
}

void BM_SphereRamtk(benchmark::State& state) {
  const test::SynthCloud& cloud = Cloud(static_cast<int>(state.range(0)));
  SphereFitOptions o;
  o.radius_mm = 19.05;
  o.noise_model = PointNoiseModel::kAlongLineOfSight;
  o.viewpoint_mm = cloud.viewpoint;
  double error = 0;
  for (auto _ : state) {
    const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
    if (s.spheres.empty())
      state.SkipWithError("no sphere");
    else
      error = (s.spheres[0].centre_mm - test::CapScene().centre).norm();
  }
  state.counters["points"] = static_cast<double>(cloud.points.size());
  state.counters["centre_err_um"] = error * 1e3;
}

void BM_SpherePcl(benchmark::State& state) {
  const test::SynthCloud& cloud = Cloud(static_cast<int>(state.range(0)));
  const auto pcl_cloud = test::ToPcl(cloud.points);
  double error = 0;
  for (auto _ : state) {
    const test::PclSphere p = test::PclFitSphere(pcl_cloud, 0.1, 17.05, 21.05);
    if (!p.found)
      state.SkipWithError("no sphere");
    else
      error = (p.centre - test::CapScene().centre).norm();
  }
  state.counters["points"] = static_cast<double>(cloud.points.size());
  state.counters["centre_err_um"] = error * 1e3;
}

BENCHMARK(BM_SphereRamtk)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpherePcl)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
