// Fringe-image simulator: the camera model beside OpenCV (projection vs cv::projectPoints,
// back-projection vs cv::undistortPoints), sensor noise beside cv::randn, and rendering
// throughput (rays per second) of the small preset. Read the ratios; the machine is shared.
#include <benchmark/benchmark.h>

#include <opencv2/calib3d.hpp>
#include <random>
#include <vector>

#include "ramtk/vision/sim/fringe_simulator.h"

namespace {

using namespace ramtk;
using namespace ramtk::vision;

const CameraIntrinsics& Camera() {
  static const CameraIntrinsics c = MakeFringePreset("thesis").cameras.left;
  return c;
}

const std::vector<cv::Point3d>& Points() {
  static const std::vector<cv::Point3d> pts = [] {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> xy(-200.0, 200.0), z(600.0, 800.0);
    std::vector<cv::Point3d> p;
    for (int i = 0; i < 100000; ++i) p.emplace_back(xy(rng), xy(rng) * 0.75, z(rng));
    return p;
  }();
  return pts;
}

std::vector<cv::Point2d> Pixels() {
  std::vector<cv::Point2d> px;
  cv::Mat k = (cv::Mat_<double>(3, 3) << Camera().fx, 0, Camera().cx, 0, Camera().fy, Camera().cy, 0, 0, 1);
  const Distortion& d = Camera().distortion;
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
  cv::projectPoints(Points(), cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist, px);
  return px;
}

void BM_ProjectRamtk(benchmark::State& state) {
  for (auto _ : state) {
    double sum = 0.0;
    for (const cv::Point3d& p : Points()) sum += ProjectPoint(Camera(), Vec3(p.x, p.y, p.z)).x();
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * Points().size());
}

void BM_ProjectOpenCv(benchmark::State& state) {
  cv::Mat k = (cv::Mat_<double>(3, 3) << Camera().fx, 0, Camera().cx, 0, Camera().fy, Camera().cy, 0, 0, 1);
  const Distortion& d = Camera().distortion;
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
  std::vector<cv::Point2d> px;
  for (auto _ : state) {
    cv::projectPoints(Points(), cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist, px);
    benchmark::DoNotOptimize(px.data());
  }
  state.SetItemsProcessed(state.iterations() * Points().size());
}

void BM_BackProjectRamtk(benchmark::State& state) {
  const std::vector<cv::Point2d> px = Pixels();
  for (auto _ : state) {
    double sum = 0.0;
    for (const cv::Point2d& p : px) sum += PixelRay(Camera(), Vec2(p.x, p.y)).x();
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * px.size());
}

// OpenCV run to the same convergence (1e-15) as ramtk's Gauss–Newton.
void BM_BackProjectOpenCvConverged(benchmark::State& state) {
  const std::vector<cv::Point2d> px = Pixels();
  cv::Mat k = (cv::Mat_<double>(3, 3) << Camera().fx, 0, Camera().cx, 0, Camera().fy, Camera().cy, 0, 0, 1);
  const Distortion& d = Camera().distortion;
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << d.k1, d.k2, d.p1, d.p2, d.k3);
  std::vector<cv::Point2d> out;
  for (auto _ : state) {
    cv::undistortPoints(px, out, k, dist, cv::noArray(), cv::noArray(),
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-15));
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * px.size());
}

void BM_SensorNoiseRamtk(benchmark::State& state) {
  const cv::Mat radiance(1024, 1280, CV_32F, cv::Scalar(0.5));
  SensorOptions o;
  for (auto _ : state) benchmark::DoNotOptimize(ApplySensor(radiance, 1.0, o, 1, 0).data);
  state.SetItemsProcessed(state.iterations() * radiance.total());
}

// Peer: constant-σ Gaussian noise with cv::randn, then 8-bit conversion (no signal dependence).
void BM_SensorNoiseOpenCvRandn(benchmark::State& state) {
  const cv::Mat radiance(1024, 1280, CV_32F, cv::Scalar(0.5 * 0.9 * 255));
  cv::Mat noise(radiance.size(), CV_32F), out;
  for (auto _ : state) {
    cv::randn(noise, 0.0, 1.8);
    cv::Mat(radiance + noise).convertTo(out, CV_8U);
    benchmark::DoNotOptimize(out.data);
  }
  state.SetItemsProcessed(state.iterations() * radiance.total());
}

void BM_RenderSmallLeft(benchmark::State& state) {
  FringeSimulationConfig c = MakeFringePreset("small");
  const std::vector<PatternFrame> frames = ExpandSequence(c.sequence);
  RenderOptions o;
  o.supersampling = static_cast<int>(state.range(0));
  const PinholeView camera = RenderedCameraView(c, 0);
  for (auto _ : state) benchmark::DoNotOptimize(RenderView(c.scene, camera, c.projector, frames, o).depth.data);
  const double rays = 640.0 * 512.0 * (o.supersampling * o.supersampling + 1);
  state.counters["rays_per_s"] = benchmark::Counter(rays * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["frames"] = static_cast<double>(frames.size());
}

BENCHMARK(BM_ProjectRamtk)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ProjectOpenCv)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BackProjectRamtk)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BackProjectOpenCvConverged)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SensorNoiseRamtk)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SensorNoiseOpenCvRandn)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RenderSmallLeft)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
