// Hidden-effect sweep of the laser diagnosis: for each seed the generator hides one observable
// laser effect (or none) in a simulated device log; the diagnosis must name it. Prints the
// confusion matrix (hidden vs named), the correct-name rate, the false-alarm rate on clean logs
// and the share of effects with at least half of the excess removed on held-out data.
//   diagnose_laser_sweep [--draws N] [--first-seed S] [--list]
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "ramtk/diagnose/laser/laser.h"
#include "ramtk/diagnose/laser/laser_hidden.h"

int main(int argc, char** argv) {
  using namespace ramtk::diagnose;
  int draws = 300;
  std::uint64_t first = 1;
  bool list = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--draws" && i + 1 < argc)
      draws = std::atoi(argv[++i]);
    else if (a == "--first-seed" && i + 1 < argc)
      first = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--list")
      list = true;
    else {
      std::fprintf(stderr, "usage: diagnose_laser_sweep [--draws N] [--first-seed S] [--list]\n");
      return 2;
    }
  }
  std::vector<std::string> names = DrawnLaserEffects();
  names.insert(names.begin(), kNoEffect);
  std::map<std::string, std::map<std::string, int>> confusion;
  int effects = 0, correct_effects = 0, clean = 0, false_alarms = 0, gained = 0, further = 0;
  for (int k = 0; k < draws; ++k) {
    const std::uint64_t seed = first + k;
    const HiddenLaserEffect h = DrawHiddenLaserEffect(seed);
    DiagnoseOptions o;
    o.data = "seed " + std::to_string(seed);
    const Diagnosis d = DiagnoseLaserLog(h.simulation.events, h.simulation.motion, h.simulation.calibrated_sensor, o);
    ++confusion[h.effect][d.cause];
    // Only one effect is hidden: any further effect named on top of it is spurious.
    for (const std::string& f : d.findings) further += f.rfind("further effect", 0) == 0;
    if (h.effect == kNoEffect) {
      ++clean;
      false_alarms += d.cause != kNoEffect;
    } else {
      ++effects;
      correct_effects += d.cause == h.effect;
      gained += d.cause == h.effect && d.excess_removed >= 0.5;
    }
    if (list)
      std::printf("seed %llu hidden %s %s=%.4g named %s excess_removed %.3f\n", static_cast<unsigned long long>(seed),
                  h.effect.c_str(), h.parameter.c_str(), h.magnitude, d.cause.c_str(), d.excess_removed);
  }
  std::printf("hidden \\ named");
  std::vector<std::string> cols = names;
  cols.push_back(kUnexplained);
  for (const std::string& c : cols) std::printf(" | %s", c.c_str());
  std::printf("\n");
  for (const std::string& r : names) {
    std::printf("%s", r.c_str());
    for (const std::string& c : cols) std::printf(" | %d", confusion[r][c]);
    std::printf("\n");
  }
  std::printf("spurious further effects named on top of the cause: %d in %d draws\n", further, draws);
  const int correct = correct_effects + (clean - false_alarms);
  std::printf("correct names: %d/%d (%.1f%%)\n", correct, draws, 100.0 * correct / std::max(1, draws));
  std::printf("false alarms on clean logs: %d/%d\n", false_alarms, clean);
  std::printf("effects named with >= 50%% of the excess removed: %d/%d\n", gained, effects);
  const bool ok = correct >= 0.9 * draws && false_alarms <= 0.05 * clean + 0.5;
  return ok ? 0 : 1;
}
