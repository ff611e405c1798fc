// Pose planning (calib/pose_planning.h): the identifiable set is the calibration's, the planned
// set beats random sets of the same size in predicted σ, and — truth the planner did not produce —
// calibrating on planned poses predicts an independent validation set better than calibrating on
// random poses, with the same noise and link errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "ramtk/calib/pose_planning.h"
#include "ramtk/calib/robot_calibration.h"
#include "ramtk/calib/robot_calibration_sim.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/robot_io.h"
#include "robot_test_util.h"

namespace ramtk::calib {
namespace {

using kinematics::RobotChain;
using test::Quick;
using test::Robot;

std::vector<Eigen::VectorXd> JointsOf(const kinematics::TrackerMeasurements& data) {
  std::vector<Eigen::VectorXd> q;
  for (const kinematics::TrackerPose& p : data.poses) q.push_back(Eigen::Map<const Eigen::VectorXd>(p.q_rad.data(), p.q_rad.size()));
  return q;
}

kinematics::TrackerMeasurements Subset(const kinematics::TrackerMeasurements& data, const std::vector<int>& poses) {
  kinematics::TrackerMeasurements out = data;
  out.poses.clear();
  for (int i : poses) out.poses.push_back(data.poses[i]);
  return out;
}

// The planner's identifiable unknowns are exactly those CalibrateRobot identifies on the same
// joint configurations (points and 6-D).
TEST(PosePlanning, IdentifiableSetIsTheCalibrations) {
  for (bool six_d : {false, true}) {
    for (const std::string robot : {"ur10.yaml", "kuka_kr150_r3100.yaml"}) {
      const RobotChain nominal = Robot(robot);
      RobotCalibrationSimOptions so;
      so.num_poses = 80;
      so.six_d = six_d;
      const RobotCalibrationSimulation sim = SimulateRobotCalibration(nominal, so);
      const RobotCalibration cal = CalibrateRobot(nominal, sim.data, Quick(), nullptr);
      std::set<std::string> identified;
      for (const CalibrationUnknown& u : cal.unknowns) {
        if (u.status == "identified") identified.insert(u.name);
      }
      PosePlanningOptions po;
      po.six_d = six_d;
      const PosePlanner planner(nominal, JointsOf(sim.data), po);
      PosePlanningSummary summary;
      po.num_poses = 20;
      const PosePlanner planner20(nominal, JointsOf(sim.data), po);
      planner20.Plan(&summary);
      const std::set<std::string> planned(summary.names.begin(), summary.names.end());
      EXPECT_EQ(planned, identified) << robot << (six_d ? " 6-D" : " points");
      EXPECT_EQ(planner.num_unknowns(), 4 * nominal.NumJoints() + (six_d ? 6 : 3)) << robot;
    }
  }
}

// Predicted σ: the planned set determines every identifiable unknown better than random sets of
// the same size, on average over candidate pools (seeds); log det is larger than every draw's.
TEST(PosePlanning, PlannedSetHasSmallerPredictedSigmaThanRandom) {
  for (const std::string robot : {"ur10.yaml", "kuka_kr150_r3100.yaml"}) {
    const RobotChain nominal = Robot(robot);
    double mean_log_ratio = 0.0;
    int count = 0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      PosePlanningOptions po;
      po.num_poses = 30;
      po.seed = seed;
      po.random_draws = 20;
      const PosePlanner planner(nominal, SampleJointConfigurations(400, {150.0}, nominal.NumJoints(), seed), po);
      PosePlanningSummary s;
      const std::vector<int> chosen = planner.Plan(&s);
      ASSERT_EQ(static_cast<int>(chosen.size()), 30);
      EXPECT_EQ(static_cast<int>(std::set<int>(chosen.begin(), chosen.end()).size()), 30) << "distinct poses";
      ASSERT_TRUE(s.planned.full_rank);
      for (int d = 0; d < 20; ++d) {
        const PoseSetQuality q = planner.Evaluate(planner.RandomSet(30, 100 * seed + d));
        EXPECT_GT(s.planned.log_det, q.log_det) << robot << " seed " << seed << " draw " << d;
      }
      for (Eigen::Index k = 0; k < s.planned.sigma.size(); ++k) {
        mean_log_ratio += std::log(s.planned.sigma[k] / s.random.sigma[k]);
        ++count;
      }
      EXPECT_LT(s.planned.condition_number, s.random.condition_number) << robot << " seed " << seed;
      EXPECT_GT(s.planned.observability_index, s.random.observability_index) << robot << " seed " << seed;
    }
    mean_log_ratio /= count;
    std::printf("%s: geometric mean of planned/random predicted sigma %.3f\n", robot.c_str(), std::exp(mean_log_ratio));
    EXPECT_LT(std::exp(mean_log_ratio), 0.9) << robot;
  }
}

// The exchange passes never lower log det below the greedy choice.
TEST(PosePlanning, ExchangeDoesNotLowerLogDet) {
  const RobotChain nominal = Robot("kuka_kr150_r3100.yaml");
  const std::vector<Eigen::VectorXd> candidates = SampleJointConfigurations(300, {150.0}, 6, 9);
  PosePlanningOptions po;
  po.num_poses = 15;
  po.six_d = true;
  po.exchange_passes = 0;
  PosePlanningSummary greedy, exchanged;
  PosePlanner(nominal, candidates, po).Plan(&greedy);
  po.exchange_passes = 5;
  PosePlanner(nominal, candidates, po).Plan(&exchanged);
  EXPECT_GE(exchanged.planned.log_det, greedy.planned.log_det - 1e-9);
  EXPECT_EQ(greedy.exchanges, 0);
}

TEST(PosePlanning, RejectsTooFewPosesAndBadOptions) {
  const RobotChain nominal = Robot("ur10.yaml");
  PosePlanningOptions po;
  po.num_poses = 5;  // 15 values for 27 unknowns
  const PosePlanner planner(nominal, SampleJointConfigurations(50, {150.0}, 6, 1), po);
  EXPECT_THROW(planner.Plan(), InputError);
  po.num_targets = 0;
  EXPECT_NE(po.Validate(), "");
  EXPECT_THROW(SampleJointConfigurations(10, {150.0, 10.0}, 6, 1), InputError);
}

// Plain joint CSVs (the planner's own output) read back; a tracker file through its format.
TEST(PosePlanning, CandidateFilesRoundTrip) {
  const std::vector<Eigen::VectorXd> joints = SampleJointConfigurations(7, {170.0}, 6, 4);
  const std::string dir = ::testing::TempDir();
  const std::string path = dir + "/planned_joints.csv";
  WriteFileAtomically(path, FormatJointCsv(joints, "test"));
  const std::vector<Eigen::VectorXd> back = ReadCandidateJoints(path, nullptr, 6);
  ASSERT_EQ(back.size(), joints.size());
  for (std::size_t i = 0; i < joints.size(); ++i) EXPECT_LT((back[i] - joints[i]).norm(), 1e-7);
  EXPECT_THROW(ReadCandidateJoints(path, nullptr, 7), InputError);
  const std::string tracker = dir + "/tracker.csv";
  WriteFileAtomically(tracker, "a;b;c;d;e;f;px;py;pz\n1;2;3;4;5;6;1,5;2;3\n10;20;30;40;50;60;1;2;3\n");
  kinematics::TrackerFormat f;
  f.joint_columns = {"a", "b", "c", "d", "e", "f"};
  f.position_columns = {"px", "py", "pz"};
  const std::vector<Eigen::VectorXd> t = ReadCandidateJoints(tracker, &f, 6);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[1][5], 60.0 * M_PI / 180.0, 1e-12);
}

// Truth the planner did not produce: the simulator's robot with link errors (1 mm, 0.1°, on the
// identifiable links, so that the identified values have a truth) is measured (0.05 mm noise) at
// N planned and at N random poses of one candidate pool; each set is calibrated; the errors that
// count are the prediction of 400 independent validation poses against the simulator's
// noise-free truth, and the identified links' error against the truth (angles as mm at 1 m).
// Over 12 seeds (link errors, pool, validation) the planned sets are better on average.
TEST(PosePlanning, PlannedPosesCalibrateBetterThanRandomAgainstTruth) {
  const RobotChain nominal = Robot("kuka_kr150_r3100.yaml");
  const int n = 20, pool = 300, draws = 3;
  double planned_sum = 0.0, random_sum = 0.0, planned_param = 0.0, random_param = 0.0;
  int planned_wins = 0;
  const int seeds = 12;
  std::vector<bool> perturb(nominal.NumParams(), false);
  {
    PosePlanningOptions po;
    po.num_poses = 30;
    PosePlanningSummary s;
    PosePlanner(nominal, SampleJointConfigurations(200, {150.0}, 6, 1), po).Plan(&s);
    for (const std::string& name : s.names) {
      const int i = kinematics::ChainParamIndexFromName(name, 6);
      if (i >= 0) perturb[i] = true;
    }
  }
  for (int seed = 1; seed <= seeds; ++seed) {
    RobotCalibrationSimOptions so;
    so.num_poses = pool;
    so.seed = static_cast<std::uint64_t>(seed);
    so.noise_seed = static_cast<std::uint64_t>(seed + 500);
    so.position_noise_mm = 0.05;
    so.perturb = perturb;
    const RobotCalibrationSimulation sim = SimulateRobotCalibration(nominal, so);
    const std::vector<Eigen::VectorXd> validation = SampleJointConfigurations(400, {150.0}, 6, seed + 1000);
    std::vector<Vec3> truth;
    for (const Eigen::VectorXd& q : validation) {
      truth.push_back(so.tracker_from_base * (kinematics::ChainBaseFromFlange(sim.truth, q) * so.targets_in_flange[0]));
    }
    // RMS per coordinate of the prediction error, and RMS error of the identified links.
    auto score = [&](const std::vector<int>& poses, double* param_error) {
      const RobotCalibration cal = CalibrateRobot(nominal, Subset(sim.data, poses), Quick(), nullptr);
      double sum = 0.0;
      for (std::size_t i = 0; i < validation.size(); ++i) sum += (PredictTarget(cal, validation[i], 0) - truth[i]).squaredNorm();
      const Eigen::VectorXd t = sim.truth.Params();
      double ps = 0.0;
      int count = 0;
      for (const CalibrationUnknown& u : cal.unknowns) {
        const int i = kinematics::ChainParamIndexFromName(u.name, 6);
        if (i < 0 || u.status != "identified") continue;
        const double e = kinematics::IsChainAngleParam(i) ? 1000.0 * (DegToRad(u.value) - t[i]) : u.value - t[i];
        ps += e * e;
        ++count;
      }
      *param_error = std::sqrt(ps / std::max(count, 1));
      return std::sqrt(sum / (3.0 * validation.size()));
    };
    PosePlanningOptions po;
    po.num_poses = n;
    po.position_sigma_mm = 0.05;
    const PosePlanner planner(nominal, JointsOf(sim.data), po);
    double pp = 0.0;
    const double planned = score(planner.Plan(), &pp);
    double random = 0.0, rp = 0.0;
    for (int d = 0; d < draws; ++d) {
      double p = 0.0;
      random += score(planner.RandomSet(n, 77 * seed + d), &p) / draws;
      rp += p / draws;
    }
    std::printf("seed %2d: validation RMS per coordinate planned %.4f mm, random %.4f mm; link error %.4f / %.4f mm\n",
                seed, planned, random, pp, rp);
    planned_sum += planned;
    random_sum += random;
    planned_param += pp;
    random_param += rp;
    planned_wins += planned < random ? 1 : 0;
  }
  std::printf("mean over %d seeds: planned %.4f mm, random %.4f mm; links %.4f / %.4f mm; planned better in %d\n",
              seeds, planned_sum / seeds, random_sum / seeds, planned_param / seeds, random_param / seeds, planned_wins);
  EXPECT_LT(planned_sum, 0.9 * random_sum);
  EXPECT_LT(planned_param, random_param);
  EXPECT_GE(planned_wins, 8);
}

}  // namespace
}  // namespace ramtk::calib
