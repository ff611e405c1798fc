// Accuracy sweep of the robot diagnosis on hidden-effect draws (diagnose/robot_hidden.h): the
// confusion matrix hidden vs named, the correct-name rate, the false-alarm rate on clean draws and
// the share of present effects whose held-out excess removed is >= 50 %.
//   diagnose_robot_sweep [--draws N] [--first-seed S] [--cycles C] [--poses P] [--verbose]
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <string>

#include "ramtk/diagnose/engine/report.h"
#include "ramtk/diagnose/robot/robot_hidden.h"
#include "ramtk/kinematics/robot_io.h"

int main(int argc, char** argv) {
  int draws = 200, cycles = 16, poses = 15;
  std::uint64_t first = 1;
  bool verbose = false;
  std::string report;  // folder: write each draw's report into report/seed-N
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::atoll(argv[++i]) : 0LL; };
    if (a == "--draws")
      draws = static_cast<int>(next());
    else if (a == "--first-seed")
      first = static_cast<std::uint64_t>(next());
    else if (a == "--cycles")
      cycles = static_cast<int>(next());
    else if (a == "--poses")
      poses = static_cast<int>(next());
    else if (a == "--verbose")
      verbose = true;
    else if (a == "--report" && i + 1 < argc)
      report = argv[++i];
    else {
      std::cerr << "usage: diagnose_robot_sweep [--draws N] [--first-seed S] [--cycles C] [--poses P] [--verbose] "
                   "[--report DIR]\n";
      return 2;
    }
  }
  const auto model =
      ramtk::kinematics::ReadRobotModel(std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml");
  ramtk::diagnose::HiddenRobotOptions ho;
  ho.cycles = cycles, ho.poses = poses;
  ramtk::diagnose::DiagnoseOptions opt;
  if (const char* f = std::getenv("SWEEP_FOLDS")) opt.folds = std::atoi(f);
  std::map<std::string, std::map<std::string, int>> confusion;
  std::set<std::string> named_set;
  int correct = 0, clean = 0, false_alarms = 0, present = 0, gain_ok = 0;
  for (int k = 0; k < draws; ++k) {
    const std::uint64_t seed = first + k;
    const auto draw = ramtk::diagnose::DrawHiddenRobotEffect(model, seed, ho);
    if (!report.empty()) opt.output_folder = report + "/seed-" + std::to_string(seed);
    const auto d = ramtk::diagnose::DiagnoseRobotData(draw.input, opt);
    if (!report.empty()) ramtk::diagnose::WriteDiagnosis(d, opt.output_folder);
    // `ambiguous` counts as correct when the truth is in the look-alike set of at most 2 (issue 15).
    std::string named = d.cause;
    if (d.cause == ramtk::diagnose::kAmbiguous || d.cause == ramtk::diagnose::kNotObservable) {
      named += "{";
      for (size_t i = 0; i < d.look_alikes.size(); ++i) named += (i ? "," : "") + d.look_alikes[i];
      named += "}";
    }
    ++confusion[draw.effect][named];
    named_set.insert(named);
    const bool in_set = std::find(d.look_alikes.begin(), d.look_alikes.end(), draw.effect) != d.look_alikes.end();
    const bool ok = d.cause == draw.effect || (d.cause == ramtk::diagnose::kAmbiguous && in_set && d.look_alikes.size() <= 2);
    correct += ok;
    if (draw.effect == ramtk::diagnose::kNoEffect) {
      ++clean;
      false_alarms += !ok;
    } else {
      ++present;
      gain_ok += ok && d.excess_removed >= 0.5;
    }
    if (verbose || !ok)
      std::cout << "seed " << seed << ": hidden " << draw.effect << " (" << draw.description << ") -> named " << d.cause
                << (named != d.cause ? " " + named : std::string()) << ", excess removed " << std::setprecision(3) << d.excess_removed << ", held-out " << d.rms_before
                << " -> " << d.rms_after << " mm\n";
    if (verbose)
      for (const std::string& f : d.findings) std::cout << "    # " << f << "\n";
  }
  std::cout << "\nconfusion (rows hidden, columns named):\n" << std::setw(22) << "";
  for (const auto& n : named_set) std::cout << "  " << n;
  std::cout << "\n";
  for (const auto& [hidden, row] : confusion) {
    std::cout << std::setw(22) << hidden;
    for (const auto& n : named_set) std::cout << "  " << std::setw(static_cast<int>(n.size())) << (row.count(n) ? row.at(n) : 0);
    std::cout << "\n";
  }
  std::cout << std::fixed << std::setprecision(1) << "\ncorrect names: " << correct << "/" << draws << " ("
            << 100.0 * correct / draws << "%)\nfalse alarms on clean draws: " << false_alarms << "/" << clean << " ("
            << (clean ? 100.0 * false_alarms / clean : 0.0)
            << "%)\npresent effects named with >= 50% of the excess removed: " << gain_ok << "/" << present << " ("
            << (present ? 100.0 * gain_ok / present : 0.0) << "%)\n";
  return 0;
}
