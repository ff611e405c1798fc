// Fringe decoding: ramtk (3-step LS phase + complementary Gray code temporal unwrapping) beside
// OpenCV structured_light SinusoidalPattern (3-step PSP + its histogram-based spatial
// unwrapping) on the same simulated 3-step set (400x300 camera, 1024 px projector, 32 periods,
// 1 DN noise, 8 bit). Time is the whole process from 8-bit images to an unwrapped map; the
// accuracy against the analytic truth is reported as counters (projector px; OpenCV's map is
// relative, so its best constant offset and sign are fitted to the truth first - a favour).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <opencv2/structured_light.hpp>
#include <vector>

#include "decode_synth.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/phase_shift.h"

namespace {

using namespace ramtk::vision;

struct BenchData {
  FringeManifest manifest;
  cv::Mat truth;
  std::vector<cv::Mat> frames;     // CV_32F, ramtk input (3 phase + 6 code images)
  std::vector<cv::Mat> frames_u8;  // the same images as CV_8U
  double period = 0;
};

const BenchData& Data() {
  static const BenchData d = [] {
    BenchData b;
    testing::SynthOptions o;
    o.noise_dn = 1.0;
    o.blur_px = 1.0;
    b.manifest = testing::GrayManifest(3, 32, true);
    b.truth = testing::TruthCoordinate(o, b.manifest.Extent());
    b.frames = testing::SynthesizeFrames(b.manifest, b.truth, o);
    for (const cv::Mat& f : b.frames) {
      cv::Mat u8;
      f.convertTo(u8, CV_8U);
      b.frames_u8.push_back(u8);
    }
    b.period = b.manifest.Extent() / 32.0;
    return b;
  }();
  return d;
}

struct Accuracy {
  double rms_px = 0;       // RMS error of pixels within half a period of the truth
  double wrong_order = 0;  // fraction of compared pixels off by more than half a period
  double compared = 0;     // fraction of all pixels compared
};

// `coordinate` in projector px (NaN = invalid); `fit_offset` fits sign and constant first.
Accuracy Compare(const cv::Mat& coordinate, const cv::Mat& truth, double period, bool fit_offset) {
  std::vector<std::pair<double, double>> pairs;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const float c = coordinate.at<float>(y, x);
      if (std::isfinite(c)) pairs.emplace_back(c, truth.at<double>(y, x));
    }
  Accuracy a;
  if (pairs.empty()) return a;
  double sign = 1, offset = 0;
  if (fit_offset) {
    // Sign from the correlation, offset as the median difference.
    double mc = 0, mt = 0, cov = 0;
    for (auto& p : pairs) mc += p.first, mt += p.second;
    mc /= pairs.size();
    mt /= pairs.size();
    for (auto& p : pairs) cov += (p.first - mc) * (p.second - mt);
    sign = cov >= 0 ? 1 : -1;
    std::vector<double> d;
    for (auto& p : pairs) d.push_back(p.second - sign * p.first);
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    offset = d[d.size() / 2];
  }
  double ss = 0;
  long good = 0, bad = 0;
  for (auto& p : pairs) {
    const double e = sign * p.first + offset - p.second;
    if (std::abs(e) > period / 2) {
      ++bad;
    } else {
      ss += e * e;
      ++good;
    }
  }
  a.rms_px = good ? std::sqrt(ss / good) : 0;
  a.wrong_order = static_cast<double>(bad) / pairs.size();
  a.compared = static_cast<double>(pairs.size()) / truth.total();
  return a;
}

void SetCounters(benchmark::State& state, const Accuracy& a) {
  state.counters["rms_px"] = a.rms_px;
  state.counters["wrong_order"] = a.wrong_order;
  state.counters["valid"] = a.compared;
}

void BM_RamtkDecode3StepComplementaryGray(benchmark::State& state) {
  const BenchData& d = Data();
  DecodeOptions opt;
  opt.intensity_sigma_dn = 1.0;
  DecodedCamera out;
  for (auto _ : state) {
    std::vector<cv::Mat> frames;
    for (const cv::Mat& f : d.frames_u8) {
      cv::Mat g;
      f.convertTo(g, CV_32F);
      frames.push_back(g);
    }
    out = DecodeFrames(d.manifest, frames, 255.0, opt, "cam");
    benchmark::DoNotOptimize(out.coordinate.data);
  }
  SetCounters(state, Compare(out.coordinate, d.truth, d.period, false));
}
BENCHMARK(BM_RamtkDecode3StepComplementaryGray)->Unit(benchmark::kMillisecond);

// Wrapped phase only (the 3 phase images, no unwrapping): RMS error against the true wrapped
// phase after removing the best constant (for OpenCV also the sign), radians.
double WrappedRms(const cv::Mat& wrapped, const cv::Mat& mask, const BenchData& d, bool fit_sign) {
  double best = 1e9;
  for (int sign : {1, -1}) {
    if (!fit_sign && sign < 0) continue;
    double cs = 0, sn = 0;
    std::vector<double> e;
    for (int y = 0; y < d.truth.rows; ++y)
      for (int x = 0; x < d.truth.cols; ++x) {
        if (!mask.empty() && !mask.at<uchar>(y, x)) continue;
        const double truth = PatternPhase(d.truth.at<double>(y, x), 32, d.manifest.Extent(), -CV_PI);
        const double v = sign * wrapped.at<float>(y, x) - truth;
        e.push_back(v);
        cs += std::cos(v);
        sn += std::sin(v);
      }
    const double offset = std::atan2(sn, cs);
    double ss = 0;
    for (double v : e) ss += std::pow(std::remainder(v - offset, 2 * CV_PI), 2);
    best = std::min(best, std::sqrt(ss / e.size()));
  }
  return best;
}

void BM_RamtkWrappedPhase3Step(benchmark::State& state) {
  const BenchData& d = Data();
  PhaseShiftResult r;
  for (auto _ : state) {
    std::vector<cv::Mat> frames;
    for (int k = 0; k < 3; ++k) {
      cv::Mat g;
      d.frames_u8[k].convertTo(g, CV_32F);
      frames.push_back(g);
    }
    r = ComputePhaseShift(frames);
    benchmark::DoNotOptimize(r.wrapped.data);
  }
  state.counters["wrapped_rms_rad"] = WrappedRms(r.wrapped, cv::Mat(), d, false);
}
BENCHMARK(BM_RamtkWrappedPhase3Step)->Unit(benchmark::kMillisecond);

void BM_OpenCvPspWrappedPhase3Step(benchmark::State& state) {
  const BenchData& d = Data();
  auto params = cv::makePtr<cv::structured_light::SinusoidalPattern::Params>();
  params->width = d.manifest.projector_width;
  params->height = d.manifest.projector_height;
  params->nbrOfPeriods = 32;
  params->shiftValue = static_cast<float>(2 * CV_PI / 3);
  params->methodId = cv::structured_light::PSP;
  params->setMarkers = false;
  cv::Ptr<cv::structured_light::SinusoidalPattern> sp = cv::structured_light::SinusoidalPattern::create(params);
  const std::vector<cv::Mat> psp(d.frames_u8.begin(), d.frames_u8.begin() + 3);
  cv::Mat wrapped, shadow;
  for (auto _ : state) {
    sp->computePhaseMap(psp, wrapped, shadow);
    benchmark::DoNotOptimize(wrapped.data);
  }
  state.counters["wrapped_rms_rad"] = WrappedRms(wrapped, shadow, d, true);
}
BENCHMARK(BM_OpenCvPspWrappedPhase3Step)->Unit(benchmark::kMillisecond);

void BM_OpenCvSinusoidalPsp3Step(benchmark::State& state) {
  const BenchData& d = Data();
  auto params = cv::makePtr<cv::structured_light::SinusoidalPattern::Params>();
  params->width = d.manifest.projector_width;
  params->height = d.manifest.projector_height;
  params->nbrOfPeriods = 32;
  params->shiftValue = static_cast<float>(2 * CV_PI / 3);
  params->methodId = cv::structured_light::PSP;
  params->horizontal = false;
  params->setMarkers = false;
  cv::Ptr<cv::structured_light::SinusoidalPattern> sp = cv::structured_light::SinusoidalPattern::create(params);
  const std::vector<cv::Mat> psp(d.frames_u8.begin(), d.frames_u8.begin() + 3);
  cv::Mat wrapped, shadow, unwrapped;
  for (auto _ : state) {
    sp->computePhaseMap(psp, wrapped, shadow);
    sp->unwrapPhaseMap(wrapped, unwrapped, d.truth.size(), shadow);
    benchmark::DoNotOptimize(unwrapped.data);
  }
  cv::Mat coord(d.truth.size(), CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  for (int y = 0; y < coord.rows; ++y)
    for (int x = 0; x < coord.cols; ++x)
      if (shadow.empty() || shadow.at<uchar>(y, x))
        coord.at<float>(y, x) = static_cast<float>(unwrapped.at<float>(y, x) * d.period / (2 * CV_PI));
  SetCounters(state, Compare(coord, d.truth, d.period, true));
}
BENCHMARK(BM_OpenCvSinusoidalPsp3Step)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
