// Monte-Carlo check of the standard deviations a stereo calibration reports.
//
//   calib_sigma_sweep [--seeds N] [--first-seed F] [--views V] [--noise GREY] [--supersample S] [--jitter 0|1]
//                     [--window FRACTION]
//
// N rendered stereo sessions of the truth rig (tests/calib/camera_test_util.h: 640×480 cameras,
// 120 mm baseline, chessboard 9×6×20 mm, V pairs each; seed F + i draws the board poses and the
// image noise). Every session's images are detected twice — corners refined the old way
// (CornerRefinement::kSectorBased) and the default way (kSubPix) — and calibrated with
// CalibrateStereo. For each of the 22 rig parameters (per camera fx fy cx cy k1 k2 p1 p2, then
// R and T) it prints the mean error, the observed RMS error against the truth, the RMS of the
// reported σ, their ratio, the largest |error/σ| and how many sessions were beyond 3σ.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "camera_test_util.h"

using namespace ramtk::calib;
namespace t = ramtk::calib::testing;

namespace {

double Arg(int argc, char** argv, const char* name, double fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], name)) return std::atof(argv[i + 1]);
  return fallback;
}

struct Tally {
  std::vector<std::vector<double>> error, sigma;  // [parameter][session]
  Tally() : error(t::kStereoParameters), sigma(t::kStereoParameters) {}
};

// Display units: px for intrinsics, 1e-3 for distortion, degrees for R, mm for T.
double Scale(int p) {
  const int q = p < 16 ? p % 8 : p;
  if (q >= 16 && q < 19) return 180.0 / CV_PI;
  return q >= 4 && q < 8 ? 1e3 : 1.0;
}
const char* Unit(int p) {
  const int q = p < 16 ? p % 8 : p;
  if (q >= 16) return q < 19 ? "deg" : "mm";
  return q >= 4 ? "1e-3" : "px";
}

void Print(const char* label, const Tally& t) {
  const std::size_t n = t.error[0].size();
  std::printf("\n%s (%zu sessions)\n", label, n);
  std::printf("%-5s %-5s %11s %11s %11s %8s %7s %9s\n", "param", "unit", "mean err", "obs RMS", "rep sigma", "obs/rep",
              "max|z|", ">3 sigma");
  int beyond_total = 0;
  double ratio_lo = 1e30, ratio_hi = 0.0, zmax = 0.0;
  for (int p = 0; p < t::kStereoParameters; ++p) {
    double mean = 0.0, ms = 0.0, sig2 = 0.0, zm = 0.0;
    int beyond = 0;
    for (std::size_t s = 0; s < n; ++s) {
      const double e = t.error[p][s], sg = t.sigma[p][s];
      mean += e / n;
      ms += e * e / n;
      sig2 += sg * sg / n;
      zm = std::max(zm, std::abs(e / sg));
      if (std::abs(e) > 3.0 * sg) ++beyond;
    }
    const double ratio = std::sqrt(ms / sig2);
    ratio_lo = std::min(ratio_lo, ratio), ratio_hi = std::max(ratio_hi, ratio), zmax = std::max(zmax, zm);
    beyond_total += beyond;
    const double k = Scale(p);
    std::printf("%-5s %-5s %11.5f %11.5f %11.5f %8.2f %7.2f %9d\n", t::StereoParameterName(p), Unit(p), mean * k,
                std::sqrt(ms) * k, std::sqrt(sig2) * k, ratio, zm, beyond);
  }
  std::printf("%s: beyond 3 sigma %d/%zu, obs/rep %.2f-%.2f, max |z| %.2f\n", label, beyond_total,
              n * t::kStereoParameters, ratio_lo, ratio_hi, zmax);
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = static_cast<int>(Arg(argc, argv, "--seeds", 30));
  const int first = static_cast<int>(Arg(argc, argv, "--first-seed", 100));
  const int views = static_cast<int>(Arg(argc, argv, "--views", 12));
  BoardRenderOptions ro;
  ro.noise_sigma = Arg(argc, argv, "--noise", 2.0);
  ro.supersample = static_cast<int>(Arg(argc, argv, "--supersample", ro.supersample));
  ro.jitter = Arg(argc, argv, "--jitter", ro.jitter ? 1 : 0) != 0;
  const BoardSpec board = ParseBoardSpec("chessboard:9x6:20", {});
  const BoardRenderer rl(board, t::TruthCamera(false), ro), rr(board, t::TruthCamera(true), ro);
  std::printf(
      "calib_sigma_sweep: %d sessions (seeds %d..%d) of %d stereo pairs, %s, noise %.3g grey levels, "
      "supersample %d%s\n",
      seeds, first, first + seeds - 1, views, board.ToString().c_str(), ro.noise_sigma, ro.supersample,
      ro.jitter ? " jittered" : "");
  const CornerRefinement kinds[2] = {CornerRefinement::kSectorBased, CornerRefinement::kSubPix};
  Tally tally[2];
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < seeds; ++i) {
    const unsigned seed = static_cast<unsigned>(first + i);
    const t::StereoImages img = t::RenderStereoImages(board, rl, rr, views, seed, 1000ULL * seed);
    for (int k = 0; k < 2; ++k) {
      BoardDetectOptions o;
      o.refinement = kinds[k];
      o.subpix_window_fraction = Arg(argc, argv, "--window", o.subpix_window_fraction);
      const StereoCalibrationResult st =
          CalibrateStereo(t::DetectViews(img.left, board, o, "left"), t::DetectViews(img.right, board, o, "right"),
                          cv::Size(640, 480), {});
      std::vector<double> e, s;
      t::StereoErrors(st, &e, &s);
      for (int p = 0; p < t::kStereoParameters; ++p) {
        tally[k].error[p].push_back(e[p]);
        tally[k].sigma[p].push_back(s[p]);
      }
      std::fprintf(stderr, "seed %u %s: %zu pairs, fx %+.3f (z %+.2f), Tz %+.4f mm (z %+.2f)\n", seed,
                   k == 0 ? "sector-based" : "subpix", st.pair_names.size(), e[0], e[0] / s[0], e[21], e[21] / s[21]);
    }
  }
  Print("kSectorBased (findChessboardCornersSB, CALIB_CB_ACCURACY)", tally[0]);
  const std::string label =
      "kSubPix (SB + cornerSubPix, half-window " +
      cv::format("%.2f", Arg(argc, argv, "--window", BoardDetectOptions().subpix_window_fraction)) +
      " x neighbour distance)";
  Print(label.c_str(), tally[1]);
  std::printf("\n%.1f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
