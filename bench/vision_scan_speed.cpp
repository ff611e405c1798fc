// Scan speed beside SLMaster's CPU pipeline on the same real set, interleaved in one run.
//
//   vision_scan_speed [--set MANIFEST] [--reps N] [--peer DRIVER] [--peer-data DIR] [--ramtk EXE]
//                     [--reference]
//
// Per repetition, in this order: ramtk in-process (images loaded from disk, then decode both
// cameras, match, triangulate, fit: the library calls `ramtk scan` makes), ramtk whole process
// (`ramtk scan SET --out TMP --force -q`, wall time; its summary.json gives the stage times of
// that one cold run), SLMaster's timing driver once (../shared/peers/slmaster: `driver --once`,
// wall time; its own line gives the load and pipeline times of that one cold run), and the
// driver's repeated in-memory pipeline (`driver --reps 3`, the median of its warm runs).
// Each whole process less its own load and pipeline times is reported too (start-up, writing the
// outputs, exit: ramtk writes cloud.ply, depth.png and two JSON files, the driver nothing), and
// ramtk's start-up and exit alone (`ramtk --version`, its 46 shared libraries).
// Warm is compared with warm and cold with cold: ramtk's in-process runs repeat in this
// process (heap and threads warm), so they face the driver's repeated runs; a fresh process's
// first run (page faults of every new buffer, thread start) faces the other's first run. Until
// 2026-11-26 the warm ramtk figure faced SLMaster's cold one, which overstated the ratio
// (SLMaster's pipeline: ~0.83 s warm against ~1.29 s cold on the same machine).
// With --reference the reference decode (the test hook DecodeTestHooks::reference_path) runs too,
// for the before/after ratio in the same run. The in-process run keeps freed blocks in the heap, as
// `ramtk scan` does (main() below); it does not take the scan's single arena and huge-page
// reserve (tools/huge_pages.h), which matter to a cold process, not to warm repetitions.
//
// The peer driver comes from --peer or the environment variable RAMTK_SLMASTER_DRIVER; if it is
// absent the peer columns are skipped with a message. Also reported: the memory-bandwidth floor
// (one pass reading every byte of the set's images, already in memory) and image loading with
// OpenImageIO (float and native) against cv::imread. And, for a count like the peer's valid
// disparities, the left pixels ramtk's match gives a crossing without its left-right and
// modulation checks (its points are those that pass both).
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "ramtk/vision/decode/detail/test_hooks.h"
#include "ramtk/vision/decode/decode.h"
#include "ramtk/vision/fringe/image_io.h"
#include "ramtk/vision/fringe/manifest.h"
#include "ramtk/vision/scan/scan.h"
#include "ramtk/vision/stereo/stereo_match.h"

using namespace ramtk::vision;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

double Ms(Clock::time_point since) { return std::chrono::duration<double, std::milli>(Clock::now() - since).count(); }

std::string Arg(int argc, char** argv, const char* name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], name)) return argv[i + 1];
  return fallback;
}
bool Flag(int argc, char** argv, const char* name) {
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], name)) return true;
  return false;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double Min(const std::vector<double>& v) { return v.empty() ? 0 : *std::min_element(v.begin(), v.end()); }

// Runs a command, returns its wall time (ms) and its first stdout line.
double RunTimed(const std::string& cmd, std::string* first_line) {
  const auto t0 = Clock::now();
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  std::string first;
  while (std::fgets(buf, sizeof buf, p))
    if (first.empty()) first = buf;
  const int rc = pclose(p);
  const double ms = Ms(t0);
  if (first_line) *first_line = first;
  return rc == -1 ? -1 : ms;
}

// The stage seconds of a `ramtk scan` run from its summary.json, ms: load and the pipeline
// (decode + roi + match + triangulate + fit); false if the file is missing or unreadable.
bool ColdStages(const std::string& summary_path, double* load_ms, double* pipeline_ms) {
  std::ifstream in(summary_path);
  if (!in) return false;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("seconds")) return false;
  const nlohmann::json& s = j["seconds"];
  double pipe = 0;
  for (const char* k : {"decode", "roi", "match", "triangulate", "fit"}) pipe += s.value(k, 0.0);
  *load_ms = 1000 * s.value("load", 0.0);
  *pipeline_ms = 1000 * pipe;
  return true;
}

// The median of the driver's repeated in-memory pipeline runs (its "TOTAL (in memory)" line), ms;
// 0 if the output is not understood.
double PeerWarmPipeline(const std::string& peer, const std::string& data) {
  FILE* p = popen(("'" + peer + "' --reps 3 --data '" + data + "'").c_str(), "r");
  if (!p) return 0;
  char buf[4096];
  double median = 0;
  while (std::fgets(buf, sizeof buf, p)) {
    double lo = 0, mid = 0;
    if (std::sscanf(buf, " TOTAL (in memory) min %lf ms median %lf ms", &lo, &mid) == 2) median = mid;
  }
  pclose(p);
  return median;
}

struct InProcess {
  double load_ms = 0, decode_ms = 0, match_ms = 0, triangulate_ms = 0, fit_ms = 0, total_ms = 0;
  long points = 0;
};

// The set's two cameras loaded and decoded as `ramtk scan` does, with the time of each part
// added to *load_ms and *decode_ms.
std::vector<DecodedCamera> DecodeBoth(const FringeManifest& m, const DecodeOptions& decode, double* load_ms,
                                      double* decode_ms) {
  std::vector<DecodedCamera> decoded;
  for (const std::string cam : {"left", "right"}) {
    std::vector<std::string> paths;
    for (const std::string& f : m.cameras.at(cam)) paths.push_back(m.Resolve(f));
    const auto tl = Clock::now();
    const ImageStack stack =
        LoadImageStack(paths, decode.dark_fraction, !detail::CurrentDecodeTestHooks().reference_path);
    *load_ms += Ms(tl);
    const auto td = Clock::now();
    decoded.push_back(DecodeFrames(m, stack.frames, stack.full_scale, decode, cam));
    *decode_ms += Ms(td);
  }
  return decoded;
}

InProcess RunRamtk(const std::string& set, bool reference) {
  InProcess r;
  const auto t0 = Clock::now();
  const FringeManifest m = ReadFringeManifest(set);
  const StereoCalibration calib = ReadStereoCalibration(m.Resolve(m.calibration));
  detail::DecodeTestHooks hooks;
  hooks.reference_path = reference;
  const detail::ScopedDecodeTestHooks scope(hooks);
  ScanOptions opt;
  const std::vector<DecodedCamera> decoded = DecodeBoth(m, opt.decode, &r.load_ms, &r.decode_ms);
  const ScanResult res = ScanDecoded(calib, decoded[0], decoded[1], decoded[0].summary.period_px, opt);
  r.match_ms = 1000 * res.summary.match_s;
  r.triangulate_ms = 1000 * res.summary.triangulate_s;
  r.fit_ms = 1000 * res.summary.fit_s;
  r.points = res.summary.triangulation.points;
  r.total_ms = Ms(t0);
  return r;
}

// Left pixels the match gives a crossing without its consistency checks, for a count like
// SLMaster's (a valid disparity is a phase match along a rectified row, with no left-right check):
// `lr_off` without the left-right check, `none` without the modulation check either. ramtk's
// points are the ones that pass both.
void UncheckedMatches(const std::string& set, long* lr_off, long* none) {
  const FringeManifest m = ReadFringeManifest(set);
  const StereoCalibration calib = ReadStereoCalibration(m.Resolve(m.calibration));
  const ScanOptions opt;
  double load_ms = 0, decode_ms = 0;
  const std::vector<DecodedCamera> decoded = DecodeBoth(m, opt.decode, &load_ms, &decode_ms);
  StereoMatchOptions mo = opt.match;
  mo.lr_tolerance_px = 0;  // no left-right check
  *lr_off = MatchStereo(calib, decoded[0], decoded[1], decoded[0].summary.period_px, mo).summary.matched;
  mo.max_modulation_ratio = 1e30;  // nor the modulation check
  *none = MatchStereo(calib, decoded[0], decoded[1], decoded[0].summary.period_px, mo).summary.matched;
}

void Floor(const std::string& set, int reps) {
  const FringeManifest m = ReadFringeManifest(set);
  std::vector<std::string> paths;
  for (const auto& [cam, files] : m.cameras)
    for (const std::string& f : files) paths.push_back(m.Resolve(f));
  std::vector<cv::Mat> imgs;
  std::size_t bytes = 0;
  for (const std::string& p : paths) {
    int bits = 0;
    imgs.push_back(LoadImageNative(p, &bits));
    bytes += imgs.back().total() * imgs.back().elemSize();
  }
  std::vector<double> t;
  std::uint64_t checksum = 0;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = Clock::now();
    for (const cv::Mat& im : imgs) {
      const auto* p = reinterpret_cast<const std::uint64_t*>(im.data);
      const std::size_t n = im.total() * im.elemSize() / 8;
      std::uint64_t s = 0;
      for (std::size_t i = 0; i < n; ++i) s += p[i];
      checksum += s;
    }
    t.push_back(Ms(t0));
  }
  std::printf("memory-bandwidth floor: %zu images, %.1f MB read once in %.2f ms (min of 5, one core; checksum %llu)\n",
              imgs.size(), bytes / 1e6, Min(t), static_cast<unsigned long long>(checksum % 1000));
  // Loading: OpenImageIO to float (reference path), native 8/16-bit (fast path), cv::imread.
  std::vector<double> oiio_f, native, imread;
  for (int rep = 0; rep < std::min(3, reps); ++rep) {
    auto t0 = Clock::now();
    for (const std::string& p : paths) (void)LoadImageDn(p, nullptr);
    oiio_f.push_back(Ms(t0));
    t0 = Clock::now();
    for (const std::string& p : paths) (void)LoadImageNative(p, nullptr);
    native.push_back(Ms(t0));
    t0 = Clock::now();
    for (const std::string& p : paths) (void)cv::imread(p, cv::IMREAD_UNCHANGED);
    imread.push_back(Ms(t0));
  }
  std::printf(
      "loading %zu images (min of %d): OpenImageIO -> float %.1f ms, LoadImageNative %.1f ms, cv::imread %.1f ms\n",
      paths.size(), std::min(3, reps), Min(oiio_f), Min(native), Min(imread));
}

}  // namespace

int main(int argc, char** argv) {
  // Freed image-sized blocks stay in the heap, as in `ramtk scan` (tools/huge_pages.h). Without it the in-process stage
  // times depended on which blocks glibc's adaptive mmap threshold happened to return to the kernel (decode 110 against
  // 185 ms on the same binary's SLMaster set, depending on the allocations before it).
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  const std::string set = Arg(argc, argv, "--set", "datasets/vision/slmaster_binocular.json");
  const int reps = std::max(1, std::atoi(Arg(argc, argv, "--reps", "5").c_str()));
  const char* env = std::getenv("RAMTK_SLMASTER_DRIVER");
  const std::string peer = Arg(argc, argv, "--peer", env ? env : "");
  const std::string peer_data = Arg(argc, argv, "--peer-data", "../shared/data/slmaster-binocular");
  const fs::path self = fs::absolute(fs::path(argv[0])).parent_path();
  const std::string ramtk_exe = Arg(argc, argv, "--ramtk", (self.parent_path() / "tools" / "ramtk").string());
  const bool reference = Flag(argc, argv, "--reference");
  if (!fs::exists(set)) {
    std::fprintf(stderr, "no set %s (run from the project root or pass --set)\n", set.c_str());
    return 2;
  }
  const bool have_peer = !peer.empty() && fs::exists(peer);
  if (!have_peer)
    std::printf(
        "peer: SLMaster driver %s; skipping the peer (build it with ../shared/peers/slmaster/build.sh and "
        "pass --peer or RAMTK_SLMASTER_DRIVER)\n",
        peer.empty() ? "not given" : ("not found at " + peer).c_str());
  const bool have_exe = fs::exists(ramtk_exe);
  if (!have_exe) std::printf("whole process: %s not found; skipped\n", ramtk_exe.c_str());
  const std::string tmp = (fs::temp_directory_path() / ("ramtk_scan_speed_" + std::to_string(getpid()))).string();

  Floor(set, reps);
  std::vector<double> r_load, r_decode, r_match, r_tri, r_fit, r_total, r_wall, ref_total, ref_decode;
  std::vector<double> p_load, p_pipe, p_wall, p_warm;
  std::vector<double> r_cold_load, r_cold_pipe, r_warm_pipe;
  // Each whole process less its load and pipeline (start-up, reading the set's description,
  // writing the outputs, exit), and ramtk's start-up and exit alone (`ramtk --version`).
  std::vector<double> r_outside, p_outside, r_start;
  long r_points = 0, ref_points = 0;
  std::string p_valid = "-";
  if (reps > 1) (void)RunRamtk(set, false);  // warm-up (file cache, TBB threads)
  for (int rep = 0; rep < reps; ++rep) {
    const InProcess r = RunRamtk(set, false);
    r_load.push_back(r.load_ms);
    r_decode.push_back(r.decode_ms);
    r_match.push_back(r.match_ms);
    r_tri.push_back(r.triangulate_ms);
    r_fit.push_back(r.fit_ms);
    r_total.push_back(r.total_ms);
    r_warm_pipe.push_back(r.decode_ms + r.match_ms + r.triangulate_ms + r.fit_ms);
    r_points = r.points;
    if (reference) {
      const InProcess ref = RunRamtk(set, true);
      ref_total.push_back(ref.total_ms);
      ref_decode.push_back(ref.decode_ms);
      ref_points = ref.points;
    }
    if (have_exe) {
      r_wall.push_back(
          RunTimed("'" + ramtk_exe + "' scan '" + set + "' --out '" + tmp + "' --force -q 2>/dev/null", nullptr));
      double load = 0, pipe = 0;
      if (ColdStages(tmp + "/summary.json", &load, &pipe)) {
        r_cold_load.push_back(load);
        r_cold_pipe.push_back(pipe);
        r_outside.push_back(r_wall.back() - load - pipe);
      }
      r_start.push_back(RunTimed("'" + ramtk_exe + "' --version", nullptr));
    }
    if (have_peer) {
      std::string line;
      p_wall.push_back(RunTimed("'" + peer + "' --once --data '" + peer_data + "'", &line));
      double load = 0, pipe = 0, total = 0;
      long valid = 0, cloud = 0;
      if (std::sscanf(line.c_str(), "load %lf ms, pipeline %lf ms, total %lf ms, valid disparity %ld, cloud %ld", &load,
                      &pipe, &total, &valid, &cloud) >= 4) {
        p_load.push_back(load);
        p_pipe.push_back(pipe);
        p_outside.push_back(p_wall.back() - load - pipe);
        p_valid = std::to_string(valid);
      } else {
        std::printf("peer output not understood: %s", line.c_str());
      }
      const double warm = PeerWarmPipeline(peer, peer_data);
      if (warm > 0) p_warm.push_back(warm);
    }
  }
  fs::remove_all(tmp);
  std::printf("\n%d interleaved repetitions (min / median ms):\n", reps);
  auto row = [](const char* name, const std::vector<double>& v) {
    if (!v.empty()) std::printf("  %-34s %9.1f %9.1f\n", name, Min(v), Median(v));
  };
  row("ramtk load images (2 cameras)", r_load);
  row("ramtk decode (2 cameras)", r_decode);
  row("ramtk match", r_match);
  row("ramtk triangulate", r_tri);
  row("ramtk sphere fit", r_fit);
  row("ramtk in-process total", r_total);
  row("ramtk pipeline, warm (in-process)", r_warm_pipe);
  row("ramtk load, cold (ramtk scan)", r_cold_load);
  row("ramtk pipeline, cold (ramtk scan)", r_cold_pipe);
  row("ramtk whole process (wall)", r_wall);
  row("  of it outside load + pipeline", r_outside);
  row("  of that start-up + exit (--version)", r_start);
  row("ramtk reference decode (2 cameras)", ref_decode);
  row("ramtk reference in-process total", ref_total);
  row("SLMaster load (its line)", p_load);
  row("SLMaster pipeline, cold (--once)", p_pipe);
  row("SLMaster pipeline, warm (--reps 3)", p_warm);
  row("SLMaster whole process (wall)", p_wall);
  row("  of it outside load + pipeline", p_outside);
  std::printf("valid points: ramtk %ld (reference path %s), SLMaster %s valid disparity pixels\n", r_points,
              reference ? std::to_string(ref_points).c_str() : "not run", p_valid.c_str());
  long lr_off = 0, unchecked = 0;
  UncheckedMatches(set, &lr_off, &unchecked);
  std::printf(
      "ramtk left pixels given a crossing without its checks: %ld without the left-right check, %ld "
      "without the modulation check too\n",
      lr_off, unchecked);
  if (have_peer && !p_pipe.empty()) {
    std::printf("ratio SLMaster / ramtk (median; > 1 = ramtk faster):\n");
    if (!p_warm.empty())
      std::printf("  pipeline in memory, warm: %.2f (each repeated in its own process)\n",
                  Median(p_warm) / Median(r_warm_pipe));
    if (!r_cold_pipe.empty()) {
      std::printf("  pipeline in memory, cold: %.2f (one run in a fresh process)\n",
                  Median(p_pipe) / Median(r_cold_pipe));
      std::printf("  cold with loading:        %.2f\n",
                  (Median(p_load) + Median(p_pipe)) / (Median(r_cold_load) + Median(r_cold_pipe)));
    }
    if (!r_wall.empty()) std::printf("  whole process (wall):     %.2f\n", Median(p_wall) / Median(r_wall));
  }
  if (reference && !ref_total.empty())
    std::printf("ratio reference / fast ramtk in-process total: %.2f (decode %.2f)\n",
                Median(ref_total) / Median(r_total), Median(ref_decode) / Median(r_decode));
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  std::printf("peak resident memory of this process: %.0f MB\n", ru.ru_maxrss / 1024.0);
  return 0;
}
