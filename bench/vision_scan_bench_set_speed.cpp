// `vision_scan_bench speed --manifest SET/manifest.json`: a stereo set on disk loaded into memory
// once (native sample depth, as `ramtk scan` loads it), then decoded, matched, triangulated and
// fitted `repeat` times with the scan's options (ScanFrames, what `ramtk scan` runs once the
// frames are loaded). Per stage: min / median / max seconds, and the
// cost per unit of work (decode: per pixel-frame, per valid pixel and MB/s of samples; match:
// per valid left pixel; triangulate and fit: per point). With `with_float` each repetition also
// decodes the frames converted to float first (the conversion timed apart) with the decode's
// default options (diagnostic maps kept), which is what the preset mode measured until it
// decoded the simulator's native frames with the scan's options. Beside the wall time, the
// process's CPU time (all threads) of the decode and of the rest: on a machine shared with other
// work the wall time grows with the load, the CPU time much less, and CPU / cores is what the
// stage would take on idle cores with perfect parallelism.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan.h"

namespace ramtk::vision {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// User + system CPU seconds of this process so far (all threads).
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Stat {
  std::vector<double> v;
  double Min() const { return *std::min_element(v.begin(), v.end()); }
  double Max() const { return *std::max_element(v.begin(), v.end()); }
  double Median() const {
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    return s.size() % 2 ? s[s.size() / 2] : 0.5 * (s[s.size() / 2 - 1] + s[s.size() / 2]);
  }
};

struct Work {
  double pixel_frames = 0;  // pixels x frames over both cameras
  double bytes = 0;         // bytes of samples over both cameras
  long valid = 0;           // decoded valid pixels, both cameras
  long left_valid = 0;      // the match's left pixels with a coordinate
  long points = 0;          // triangulated points
};

void PrintRow(const char* name, const Stat& s, double per, const char* unit) {
  std::printf("  %-24s %8.3f %8.3f %8.3f s", name, s.Min(), s.Median(), s.Max());
  if (per > 0) std::printf("   %7.2f %s (median)", 1e9 * s.Median() / per, unit);
  std::printf("\n");
}

}  // namespace

int SetSpeed(const std::string& manifest_path, int repeat, bool with_float) {
  const FringeManifest m = ReadFringeManifest(manifest_path);
  const StereoCalibration calib = ReadStereoCalibration(m.Resolve(m.calibration));
  const ScanOptions options;
  std::vector<ImageStack> stacks;
  Work w;
  for (const std::string camera : {"left", "right"}) {
    std::vector<std::string> paths;
    for (const std::string& f : m.cameras.at(camera)) paths.push_back(m.Resolve(f));
    stacks.push_back(LoadImageStack(paths, options.decode.dark_fraction, true));
    for (const cv::Mat& f : stacks.back().frames) {
      w.pixel_frames += static_cast<double>(f.total());
      w.bytes += static_cast<double>(f.total() * f.elemSize());
    }
  }
  const cv::Mat& f0 = stacks[0].frames[0];
  std::printf("%s: %dx%d, %zu frames per camera, %d-byte samples, %.0f MB in memory\n", manifest_path.c_str(), f0.cols,
              f0.rows, stacks[0].frames.size(), static_cast<int>(f0.elemSize()), w.bytes / 1e6);
  Stat decode, match, triangulate, fit, total, to_float, decode_float, decode_cpu, rest_cpu, decode_float_cpu;
  for (int k = 0; k < repeat; ++k) {
    // ScanFrames: the scan's own path after loading (both decodes, then the rest, releasing each
    // map once no later stage reads it); its progress report after the second decode splits the
    // CPU time.
    ScanOptions o = options;
    double cpu = CpuSeconds(), cpu_decoded = 0;
    o.progress = [&](const ramtk::Progress& p) {
      if (p.stage == "decode right") cpu_decoded = CpuSeconds();
      return true;
    };
    auto t = Clock::now();
    const ScanResult r = ScanFrames(m, calib, stacks[0].frames, stacks[1].frames, stacks[0].full_scale, o);
    const ScanSummary& s = r.summary;
    decode_cpu.v.push_back(cpu_decoded - cpu);
    rest_cpu.v.push_back(CpuSeconds() - cpu_decoded);
    decode.v.push_back(s.decode_s);
    match.v.push_back(s.match_s);
    triangulate.v.push_back(s.triangulate_s);
    fit.v.push_back(s.fit_s);
    total.v.push_back(decode.v.back() + s.match_s + s.triangulate_s + s.fit_s);
    w.valid = s.left.valid_pixels + s.right.valid_pixels;
    w.left_valid = s.match.left_valid;
    w.points = s.triangulation.points;
    std::printf(
        "run %d: total %.3f s (decode %.3f, match %.3f, triangulate %.3f, fit %.3f); CPU decode %.3f s, the rest "
        "%.3f s\n  %s\n",
        k + 1, total.v.back(), decode.v.back(), s.match_s, s.triangulate_s, s.fit_s, decode_cpu.v.back(),
        rest_cpu.v.back(), s.BriefReport().c_str());
    if (!with_float) continue;
    t = Clock::now();
    std::vector<std::vector<cv::Mat>> as_float(2);
    for (int c = 0; c < 2; ++c)
      for (const cv::Mat& f : stacks[c].frames) {
        as_float[c].emplace_back();
        f.convertTo(as_float[c].back(), CV_32F);
      }
    to_float.v.push_back(Since(t));
    t = Clock::now();
    cpu = CpuSeconds();
    for (int c = 0; c < 2; ++c)
      (void)DecodeFrames(m, as_float[c], stacks[c].full_scale, DecodeOptions{}, c ? "right" : "left");
    decode_float.v.push_back(Since(t));
    decode_float_cpu.v.push_back(CpuSeconds() - cpu);
  }
  std::printf("\n%d repetitions, both cameras (min / median / max), cost per unit of work:\n", repeat);
  std::printf("  valid pixels %ld (both cameras), left valid %ld, points %ld\n", w.valid, w.left_valid, w.points);
  PrintRow("decode", decode, w.pixel_frames, "ns/pixel-frame");
  PrintRow("  per valid pixel", decode, static_cast<double>(w.valid), "ns/valid pixel");
  std::printf("  %-24s %8.0f MB/s of samples (median)\n", "  rate", w.bytes / decode.Median() / 1e6);
  PrintRow("match", match, static_cast<double>(w.left_valid), "ns/left valid pixel");
  PrintRow("triangulate", triangulate, static_cast<double>(w.points), "ns/point");
  PrintRow("fit", fit, static_cast<double>(w.points), "ns/point");
  PrintRow("total in memory", total, 0, "");
  PrintRow("CPU: decode", decode_cpu, w.pixel_frames, "ns/pixel-frame");
  PrintRow("CPU: match..fit", rest_cpu, 0, "");
  if (with_float) {
    PrintRow("frames to float", to_float, w.pixel_frames, "ns/pixel-frame");
    PrintRow("decode of float frames", decode_float, w.pixel_frames, "ns/pixel-frame");
    PrintRow("CPU: float decode", decode_float_cpu, w.pixel_frames, "ns/pixel-frame");
  }
  return 0;
}

}  // namespace ramtk::vision
