// Pose planning on real data: the IPA UR10 data set measured with a Leica T-Mac (Series A,
// 11910 poses). N poses are chosen from Series A's own joint sets (D-optimal, calib/pose_planning.h)
// or at random; the robot is calibrated on them (links and set-up, no non-geometric terms) and
// the calibration predicts every other Series A pose. Printed: the RMS per coordinate of that
// prediction, planned against the mean over random draws, per N. Skips (exit 0) when the data
// are absent.
//
//   pose_planning_ur10 [--data CSV] [--format YAML] [--robot YAML] [--sizes 30,50,100]
//                      [--draws 5] [--points]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "ramtk/calib/pose_planning.h"
#include "ramtk/calib/robot_calibration.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/kinematics/tracker_io.h"

namespace {

using namespace ramtk;

struct Args {
  std::string data = std::string(RAMTK_SHARED_DIR) + "/data/ipa-robot-accuracy/Series_A/measurements_grid.csv";
  std::string format = std::string(RAMTK_SOURCE_DIR) + "/docs/examples/ipa_tmac_format.yaml";
  std::string robot = std::string(RAMTK_DATASETS_DIR) + "/robots/ur10.yaml";
  std::vector<int> sizes = {30, 50, 100};
  int draws = 5;
  bool points = false;  // plan and calibrate with the positions only
};

kinematics::TrackerMeasurements Subset(const kinematics::TrackerMeasurements& data, const std::vector<int>& poses) {
  kinematics::TrackerMeasurements out = data;
  out.poses.clear();
  for (int i : poses) out.poses.push_back(data.poses[i]);
  return out;
}

struct Result {
  double rms = 0.0;       // other poses, RMS per coordinate (mm)
  double fit = 0.0;       // the calibration's own residual on its N poses (mm)
};

Result CalibrateAndPredict(const kinematics::RobotChain& nominal, const kinematics::TrackerMeasurements& data,
                           std::vector<int> chosen, bool points) {
  std::sort(chosen.begin(), chosen.end());
  std::vector<int> rest;
  std::size_t k = 0;
  for (int i = 0; i < static_cast<int>(data.poses.size()); ++i) {
    if (k < chosen.size() && chosen[k] == i) {
      ++k;
    } else {
      rest.push_back(i);
    }
  }
  calib::RobotCalibrationOptions o;
  o.try_cyclic = false;
  o.try_compliance = false;
  o.use_rotation = !points;
  calib::RobotCalibrationSummary summary;
  const calib::RobotCalibration cal = calib::CalibrateRobot(nominal, Subset(data, chosen), o, &summary);
  Result r;
  r.rms = calib::EvaluateCalibration(cal, Subset(data, rest)).rms_per_coordinate_mm;
  r.fit = summary.after.rms_per_coordinate_mm;
  return r;
}

int Run(const Args& a) {
  if (!std::filesystem::exists(a.data)) {
    std::printf("skipped: %s not found (the IPA robot-accuracy data set)\n", a.data.c_str());
    return 0;
  }
  const kinematics::RobotChain nominal = kinematics::ReadRobotChain(a.robot);
  const kinematics::TrackerFormat format = kinematics::ReadTrackerFormat(a.format);
  const kinematics::TrackerMeasurements data = kinematics::ReadTrackerMeasurements(a.data, format);
  std::vector<Eigen::VectorXd> candidates;
  for (const kinematics::TrackerPose& p : data.poses) {
    candidates.push_back(Eigen::Map<const Eigen::VectorXd>(p.q_rad.data(), p.q_rad.size()));
  }
  const bool six_d = data.has_rotation && !a.points;
  std::printf("%s: %zu poses; planning %s over all of them, calibrating (links + set-up, no terms) on N, predicting "
              "the other poses\n",
              a.data.c_str(), data.poses.size(), six_d ? "6-D" : "points");
  std::printf("%5s %11s %11s %11s %11s %11s %11s %11s %8s\n", "N", "planned mm", "random mm", "random min",
              "random max", "planned fit", "random fit", "sigma ratio", "plan s");
  for (int n : a.sizes) {
    calib::PosePlanningOptions po;
    po.num_poses = n;
    po.six_d = six_d;
    po.random_draws = a.draws;
    po.seed = 1;
    const auto t0 = std::chrono::steady_clock::now();
    const calib::PosePlanner planner(nominal, candidates, po);
    calib::PosePlanningSummary summary;
    const std::vector<int> chosen = planner.Plan(&summary);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Result planned = CalibrateAndPredict(nominal, data, chosen, a.points);
    double sum = 0.0, fit = 0.0, lo = 1e300, hi = 0.0;
    for (int d = 0; d < a.draws; ++d) {
      const Result r = CalibrateAndPredict(nominal, data, planner.RandomSet(n, 1000 + d), a.points);
      sum += r.rms;
      fit += r.fit;
      lo = std::min(lo, r.rms);
      hi = std::max(hi, r.rms);
    }
    double log_ratio = 0.0;
    for (Eigen::Index k = 0; k < summary.planned.sigma.size(); ++k) {
      log_ratio += std::log(summary.planned.sigma[k] / summary.random.sigma[k]);
    }
    const double sigma_ratio = std::exp(log_ratio / std::max<Eigen::Index>(1, summary.planned.sigma.size()));
    std::printf("%5d %11.4f %11.4f %11.4f %11.4f %11.4f %11.4f %11.3f %8.1f\n", n, planned.rms, sum / a.draws, lo, hi,
                planned.fit, fit / a.draws, sigma_ratio, seconds);
    std::fflush(stdout);
  }
  {
    // The floor: every pose calibrated and predicted (in-sample), and the nominal links.
    calib::RobotCalibrationOptions o;
    o.try_cyclic = false;
    o.try_compliance = false;
    o.use_rotation = !a.points;
    calib::RobotCalibrationSummary all;
    calib::CalibrateRobot(nominal, data, o, &all);
    std::printf("all %zu poses: RMS per coordinate %.4f mm calibrated (in-sample), %.4f mm held-out (5-fold), %.4f mm "
                "with the nominal links (set-up fitted)\n",
                data.poses.size(), all.after.rms_per_coordinate_mm, all.held_out.rms_per_coordinate_mm,
                all.before.rms_per_coordinate_mm);
  }
  std::printf("planned/random mm: RMS per coordinate on the Series A poses not used; random: mean, min, max over %d "
              "draws; fit: the calibration's residual on its own N poses; sigma ratio: geometric mean over the identifiable unknowns of the predicted sigma, planned / "
              "random (RMS over the draws)\n",
              a.draws);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s: expected a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--data") {
      a.data = value();
    } else if (arg == "--format") {
      a.format = value();
    } else if (arg == "--robot") {
      a.robot = value();
    } else if (arg == "--draws") {
      a.draws = std::stoi(value());
    } else if (arg == "--points") {
      a.points = true;
    } else if (arg == "--sizes") {
      a.sizes.clear();
      std::stringstream s(value());
      std::string cell;
      while (std::getline(s, cell, ',')) a.sizes.push_back(std::stoi(cell));
    } else {
      std::fprintf(stderr, "unknown option %s\n", arg.c_str());
      return 2;
    }
  }
  try {
    return Run(a);
  } catch (const ramtk::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
