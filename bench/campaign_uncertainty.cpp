// Uncertainty end to end through the campaign's image twin (issue 14): the twin (images → scan
// centres with their covariance → set-up calibration with its covariance → weighted drift
// identification with its covariance) is run for several seeds, and at every stage the observed
// error against truth is divided by the stage's own propagated prediction. An honest chain gives
// ratios near 1 (an RMS over seeds of |error| / |σ| for the 3-vectors, of the RMS error / σ for
// the drift parameters); > 1 means the stage is optimistic.
//
//   campaign_uncertainty --robot datasets/robots/kuka_kr150_r3100.yaml --seeds 10 --work /tmp/cu
//       [--scale 0.25] [--supersampling 2]   (camera window scale and rays per pixel side, as the twin)
//       [--frozen-drift]   (each cycle's drift held at its ball poses' mean time: no drift inside a cycle)
//       [--cold-reference]   (the robot stands through the first cycle: the reference is measured cold)
//       [--one-dx-per-cycle]   (identify one ΔX per cycle, DriftModel::Solve, instead of the drift in time)
//
// Each line also shows the chain fed the true centres against the same (image chain's) prediction.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "ramtk/campaign/campaign.h"
#include "ramtk/kinematics/robot_io.h"

namespace {

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

}  // namespace

int main(int argc, char** argv) {
  using namespace ramtk;
  namespace fs = std::filesystem;
  const std::string robot = Arg(argc, argv, "--robot", "datasets/robots/kuka_kr150_r3100.yaml");
  const int seeds = std::atoi(Arg(argc, argv, "--seeds", "10").c_str());
  const int first = std::atoi(Arg(argc, argv, "--first-seed", "1").c_str());
  const fs::path work = Arg(argc, argv, "--work", "/tmp/campaign_uncertainty");
  const kinematics::RobotModel model = kinematics::ReadRobotModel(robot);
  // Per budget line: sum of (observed / predicted)^2 over seeds, for images and true centres.
  std::map<std::string, double> ratio2, ratio2_truth;
  std::vector<std::string> order;
  for (int seed = first; seed < first + seeds; ++seed) {
    campaign::CampaignOptions o;
    o.seed = static_cast<std::uint64_t>(seed);
    o.image_scale = std::atof(Arg(argc, argv, "--scale", std::to_string(o.image_scale)).c_str());
    o.supersampling = std::atoi(Arg(argc, argv, "--supersampling", std::to_string(o.supersampling)).c_str());
    o.drift_changes_within_cycle = !Flag(argc, argv, "--frozen-drift");
    o.drift_in_time = !Flag(argc, argv, "--one-dx-per-cycle");
    o.cold_reference = Flag(argc, argv, "--cold-reference");
    o.screen_keep = -1;  // the screening has no propagated σ to score
    const fs::path out = work / ("seed" + std::to_string(seed));
    fs::remove_all(out);
    const campaign::CampaignSummary s = campaign::SimulateAndRunCampaign(model, o, out.string());
    std::printf("seed %d: %s\n", seed, s.BriefReport().c_str());
    for (const campaign::StageError& e : s.budget) {
      if (!std::isfinite(e.predicted) || !(e.predicted > 0)) continue;
      const std::string key = e.stage + ": " + e.quantity;
      if (!ratio2.count(key)) order.push_back(key);
      ratio2[key] += std::pow(e.images / e.predicted, 2);
      ratio2_truth[key] += std::pow(e.truth / e.predicted, 2);
      std::printf("  %-44s observed %-10.4g predicted %-10.4g ratio %.2f\n", key.c_str(), e.images, e.predicted,
                  e.images / e.predicted);
    }
    std::fflush(stdout);
  }
  std::printf("\nRMS over %d seeds of observed / predicted (1 = the propagated sigma is honest); beside it the chain\n"
              "fed the true centres against the same prediction:\n", seeds);
  for (const std::string& key : order)
    std::printf("  %-44s %.2f   (true centres %.2f)\n", key.c_str(), std::sqrt(ratio2[key] / seeds),
                std::sqrt(ratio2_truth[key] / seeds));
  return 0;
}
