// Board-pose CSV files, hand-eye result JSON and the board-pose simulator.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>

#include "pose_noise.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/json.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::calib {

std::vector<BoardPoseObservation> ReadBoardPoseObservations(const std::string& path) {
  const CsvTable t = ReadCsv(path);
  int q[kinematics::kNumJoints];
  for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = t.Column("q" + std::to_string(i + 1));
  const int x = t.Column("x"), y = t.Column("y"), z = t.Column("z");
  const int a = t.Column("a"), b = t.Column("b"), c = t.Column("c");
  std::vector<BoardPoseObservation> obs;
  for (std::size_t r = 0; r < t.size(); ++r) {
    BoardPoseObservation o;
    for (int i = 0; i < kinematics::kNumJoints; ++i) o.q_controller[i] = DegToRad(t.Number(r, q[i]));
    o.camera_from_board.translation() = Vec3(t.Number(r, x), t.Number(r, y), t.Number(r, z));
    o.camera_from_board.linear() =
        RotationFromKukaAbc({DegToRad(t.Number(r, a)), DegToRad(t.Number(r, b)), DegToRad(t.Number(r, c))});
    obs.push_back(o);
  }
  return obs;
}

std::string FormatBoardPoseObservations(const std::vector<BoardPoseObservation>& obs) {
  std::vector<std::string> header = {"pose", "q1", "q2", "q3", "q4", "q5", "q6", "x", "y", "z", "a", "b", "c"};
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    std::vector<std::string> row = {std::to_string(i + 1)};
    for (int k = 0; k < kinematics::kNumJoints; ++k) row.push_back(FormatFixed(RadToDeg(obs[i].q_controller[k]), 9));
    for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(obs[i].camera_from_board.translation()[k], 6));
    const KukaAbc abc = KukaAbcFromRotation(obs[i].camera_from_board.linear());
    for (double v : {abc.a, abc.b, abc.c}) row.push_back(FormatFixed(RadToDeg(v), 9));
    rows.push_back(row);
  }
  return FormatCsv(header, rows);
}

std::string HandEyeResultJson(const HandEyeResult& result, const HandEyeSummary& summary) {
  nlohmann::json j;
  j["method"] = summary.method;
  j["refined"] = summary.refined;
  j["camera_from_base"] = PoseToJson(result.camera_from_base);
  j["flange_from_board"] = PoseToJson(result.flange_from_board);
  nlohmann::json res = nlohmann::json::array();
  for (std::size_t i = 0; i < result.translation_residual_mm.size(); ++i) {
    res.push_back({{"index", i},
                   {"rotation_deg", RadToDeg(result.rotation_residual_rad[i])},
                   {"translation_mm", result.translation_residual_mm[i]}});
  }
  j["residuals"] = res;
  j["rms_rotation_deg"] = summary.rms_rotation_deg;
  j["rms_translation_mm"] = summary.rms_translation_mm;
  j["summary"] = {{"iterations", summary.iterations},
                  {"initial_cost", summary.initial_cost},
                  {"final_cost", summary.final_cost},
                  {"brief", summary.BriefReport()}};
  return j.dump(2) + "\n";
}

std::vector<BoardPoseObservation> SimulateBoardPoses(const kinematics::RobotModel& model,
                                                     const std::vector<kinematics::JointVector>& joints,
                                                     const Isometry3& camera_from_base,
                                                     const Isometry3& flange_from_board, double sigma_deg,
                                                     double sigma_mm, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<BoardPoseObservation> obs;
  for (const kinematics::JointVector& q : joints) {
    BoardPoseObservation o;
    o.q_controller = q;
    o.camera_from_board = internal::PerturbPose(
        camera_from_base * kinematics::BaseFromFlange(model, q) * flange_from_board, sigma_deg, sigma_mm, rng, g);
    obs.push_back(o);
  }
  return obs;
}

}  // namespace ramtk::calib
