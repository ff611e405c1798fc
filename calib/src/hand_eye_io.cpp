// Hand-eye pose files (joints or flange poses), result JSON and the board-pose simulator.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <Eigen/Cholesky>

#include "hand_eye_json.h"
#include "pose_noise.h"
#include "ramtk/calib/hand_eye.h"
#include "ramtk/calib/hand_eye_flange_refine.h"
#include "ramtk/core/csv.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/json.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/rotation.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/measurements_io.h"

namespace ramtk::calib {

namespace {

// The camera's camera_from_board columns of a pose file: x, y, z (mm) and a, b, c (KUKA deg).
struct BoardColumns {
  int x, y, z, a, b, c;
  explicit BoardColumns(const CsvTable& t)
      : x(t.Column("x")), y(t.Column("y")), z(t.Column("z")), a(t.Column("a")), b(t.Column("b")), c(t.Column("c")) {}
  Isometry3 Pose(const CsvTable& t, std::size_t r) const {
    Isometry3 pose = Isometry3::Identity();
    const auto mm = [&](int col) { return t.Bounded(r, col, kinematics::kMaxAbsPositionMm, "kMaxAbsPositionMm"); };
    const auto deg = [&](int col) { return DegToRad(t.Bounded(r, col, kMaxAbsPoseAngleDeg, "kMaxAbsPoseAngleDeg")); };
    // One statement per cell: the first bad cell in column order is the one named.
    const double px = mm(x), py = mm(y), pz = mm(z);
    const double pa = deg(a), pb = deg(b), pc = deg(c);
    pose.translation() = Vec3(px, py, pz);
    pose.linear() = RotationFromKukaAbc({pa, pb, pc});
    return pose;
  }
};

// The optional covariance columns cov_ij (0 <= i <= j <= 5) in [ω (deg); t (mm)]: all or none.
struct CovarianceColumns {
  int col[6][6];
  bool present = false;
  explicit CovarianceColumns(const CsvTable& t) {
    present = t.Column("cov_00", false) >= 0;
    for (int i = 0; i < 6; ++i)
      for (int k = i; k < 6; ++k) col[i][k] = present ? t.Column("cov_" + std::to_string(i) + std::to_string(k)) : -1;
  }
  // In [ω (rad); t (mm)]; InputError for a matrix that is not positive definite.
  Eigen::Matrix<double, 6, 6> Covariance(const CsvTable& t, std::size_t r) const {
    Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
    if (!present) return c;
    for (int i = 0; i < 6; ++i)
      for (int k = i; k < 6; ++k) c(i, k) = c(k, i) = t.Number(r, col[i][k]);
    if (Eigen::LLT<Eigen::Matrix<double, 6, 6>>(c).info() != Eigen::Success)
      throw InputError({t.path, t.line_numbers[r], "cov_00..cov_55"}, "the covariance is not positive definite");
    Eigen::Matrix<double, 6, 6> to_rad = Eigen::Matrix<double, 6, 6>::Identity();
    to_rad.topLeftCorner<3, 3>() *= DegToRad(1.0);
    return to_rad * c * to_rad;
  }
};

// Joints q1..q6 (deg) and camera_from_board per row.
std::vector<BoardPoseObservation> BoardPosesFromTable(const CsvTable& t) {
  int q[kinematics::kNumJoints];
  for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = t.Column("q" + std::to_string(i + 1));
  const BoardColumns board(t);
  std::vector<BoardPoseObservation> obs;
  for (std::size_t r = 0; r < t.size(); ++r) {
    BoardPoseObservation o;
    for (int i = 0; i < kinematics::kNumJoints; ++i)
      o.q_controller[i] = DegToRad(t.Bounded(r, q[i], kinematics::kMaxAbsJointDeg, "kMaxAbsJointDeg"));
    o.camera_from_board = board.Pose(t, r);
    obs.push_back(o);
  }
  return obs;
}

}  // namespace

std::vector<BoardPoseObservation> ReadBoardPoseObservations(const std::string& path) {
  return BoardPosesFromTable(ReadCsv(path));
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

namespace {

double FlangeUnitScale(const std::string& path, const std::string& units) {
  if (units == "mm") return 1.0;
  if (units == "m") return 1000.0;
  throw InputError({path, 0, "flange_units"}, "expected 'mm' or 'm', got '" + units + "'");
}

// A flange translation cell in mm, within kMaxAbsPositionMm of the base (a value beyond it in a
// file of metres is millimetres given the wrong unit).
double FlangeMm(const CsvTable& t, std::size_t r, int col, double scale) {
  const double mm = scale * t.Number(r, col);
  if (!(std::abs(mm) <= kinematics::kMaxAbsPositionMm)) {
    throw InputError({t.path, t.line_numbers[r], t.header[col]},
                     "value " + t.Text(r, col) + (scale == 1.0 ? " mm" : " m") +
                         " is beyond the plausible range +-100 m (kMaxAbsPositionMm)" +
                         (scale != 1.0 && std::abs(mm) / scale <= kinematics::kMaxAbsPositionMm
                              ? ": are the flange translations in millimetres? (--flange-units mm)"
                              : ""));
  }
  return mm;
}

// The nearest rotation to a printed 3x3 matrix, checked against its printed precision: a
// rotation rounded to d decimals is off by up to 0.5e-d per entry, so |R^T R - I| may reach
// about 2*sqrt(3) times that. The tolerance is 4 times the coarsest entry's rounding, at least
// 1e-6 and at most 2e-3 (a rotation printed with fewer than 3 decimals is refused).
Mat3 PrintedRotation(const CsvTable& t, std::size_t r, const int (&cols)[9], const char* field) {
  Mat3 rot;
  double rounding = 0;
  for (int i = 0; i < 9; ++i) {
    rot(i / 3, i % 3) = t.Number(r, cols[i]);
    rounding = std::max(rounding, PrintedRoundingBound(t.Text(r, cols[i])));
  }
  const double tolerance = std::max(1e-6, 4 * rounding);
  const double orth = (rot.transpose() * rot - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(orth <= std::min(tolerance, 2e-3)) || rot.determinant() < 0) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the rotation part is not a rotation (max |R^T R - I| = %.3g; tolerance %.3g from the printed "
                  "decimals, at most 2e-3)",
                  orth, std::min(tolerance, 2e-3));
    throw InputError({t.path, t.line_numbers[r], field}, text);
  }
  return NearestRotation(rot);
}

// Columns of the flange pose: every form the header holds (matrix, quaternion, KUKA A,B,C). A row
// giving two forms must give one pose.
struct FlangeColumns {
  bool matrix = false, quaternion = false, abc = false;
  int m[12] = {0};
  int x = -1, y = -1, z = -1, a = -1, b = -1, c = -1, qw = -1, qx = -1, qy = -1, qz = -1;

  explicit FlangeColumns(const CsvTable& t) {
    matrix = t.Column("flange_m00", false) >= 0;
    quaternion = t.Column("flange_qw", false) >= 0;
    abc = t.Column("flange_a", false) >= 0 || (!matrix && !quaternion);
    if (matrix) {
      for (int i = 0; i < 12; ++i) m[i] = t.Column("flange_m" + std::to_string(i / 4) + std::to_string(i % 4));
    }
    if (quaternion || abc) x = t.Column("flange_x"), y = t.Column("flange_y"), z = t.Column("flange_z");
    if (quaternion) {
      qw = t.Column("flange_qw"), qx = t.Column("flange_qx"), qy = t.Column("flange_qy"), qz = t.Column("flange_qz");
    }
    if (abc) a = t.Column("flange_a"), b = t.Column("flange_b"), c = t.Column("flange_c");
  }

  Isometry3 Pose(const CsvTable& t, std::size_t r, double scale) const {
    std::vector<std::pair<const char*, Isometry3>> forms;
    if (matrix) {
      Isometry3 pose = Isometry3::Identity();
      const int rot[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
      pose.linear() = PrintedRotation(t, r, rot, "flange_m00..flange_m22");
      const double px = FlangeMm(t, r, m[3], scale), py = FlangeMm(t, r, m[7], scale),
                   pz = FlangeMm(t, r, m[11], scale);
      pose.translation() = Vec3(px, py, pz);
      forms.emplace_back("flange_m00..flange_m23", pose);
    }
    Isometry3 pose = Isometry3::Identity();
    if (quaternion || abc) {
      const double px = FlangeMm(t, r, x, scale), py = FlangeMm(t, r, y, scale), pz = FlangeMm(t, r, z, scale);
      pose.translation() = Vec3(px, py, pz);
    }
    if (quaternion) {
      const Eigen::Quaterniond q(t.Number(r, qw), t.Number(r, qx), t.Number(r, qy), t.Number(r, qz));
      if (!(std::abs(q.norm() - 1.0) <= 1e-3))
        throw InputError({t.path, t.line_numbers[r], "flange_qw..flange_qz"},
                         "the quaternion's norm is " + std::to_string(q.norm()) + ", expected 1 (within 1e-3)");
      pose.linear() = q.normalized().toRotationMatrix();
      forms.emplace_back("flange_x..flange_z, flange_qw..flange_qz", pose);
    }
    if (abc) {
      const auto deg = [&](int col) { return DegToRad(t.Bounded(r, col, kMaxAbsPoseAngleDeg, "kMaxAbsPoseAngleDeg")); };
      const double pa = deg(a), pb = deg(b), pc = deg(c);
      pose.linear() = RotationFromKukaAbc({pa, pb, pc});
      forms.emplace_back("flange_x..flange_z, flange_a..flange_c", pose);
    }
    for (std::size_t k = 1; k < forms.size(); ++k) {
      const double angle_deg =
          RadToDeg(Eigen::AngleAxisd(forms[0].second.linear().transpose() * forms[k].second.linear()).angle());
      const double shift_mm = (forms[0].second.translation() - forms[k].second.translation()).norm();
      if (angle_deg > kFlangeFormsAgreeDeg || shift_mm > kFlangeFormsAgreeMm) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "disagrees with %s in the same row by %.4g deg and %.4g mm (more than %g deg or %g mm): "
                      "which flange pose is meant?",
                      forms[0].first, angle_deg, shift_mm, kFlangeFormsAgreeDeg, kFlangeFormsAgreeMm);
        throw InputError({t.path, t.line_numbers[r], forms[k].first}, text);
      }
    }
    return forms[0].second;
  }
};

// A robot's flange is never within a few centimetres of its base origin at every pose: metres
// read as millimetres (the residuals would then be ~1000 times the noise, the fit still "done").
void RequireFlangeReach(const std::string& path, const std::vector<Isometry3>& flanges) {
  double farthest_mm = 0;
  for (const Isometry3& f : flanges) farthest_mm = std::max(farthest_mm, f.translation().norm());
  if (!flanges.empty() && farthest_mm < kMinFlangeReachMm) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "every flange position is within %.3g mm of the robot base (kMinFlangeReachMm = %g mm): are "
                  "the translations in metres? (--flange-units m)",
                  farthest_mm, kMinFlangeReachMm);
    throw InputError({path, 0, "flange_units"}, text);
  }
}

// The cells of a matrix-per-line row: separated by spaces, tabs or commas.
std::vector<std::string> SplitNumberCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char ch : line) {
    if (ch == ' ' || ch == '\t' || ch == ',' || ch == '\r') {
      if (!cell.empty()) cells.push_back(cell), cell.clear();
    } else {
      cell += ch;
    }
  }
  if (!cell.empty()) cells.push_back(cell);
  return cells;
}

bool IsDataLine(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t\r");
  return first != std::string::npos && line[first] != '#';
}

// True when the first line that is neither blank nor a comment holds only numbers.
bool FirstDataLineIsNumbers(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!IsDataLine(line)) continue;
    for (const std::string& c : SplitNumberCells(line)) {
      char* end = nullptr;
      std::strtod(c.c_str(), &end);
      if (end == c.c_str() || *end != '\0') return false;
    }
    return true;
  }
  return false;
}

// One row-major 4x4 (16 numbers, last row 0 0 0 1) or 3x4 (12 numbers) base_from_flange per line.
std::vector<Isometry3> MatrixPerLinePoses(const std::string& text, const std::string& path, double scale) {
  std::istringstream in(text);
  std::string line;
  std::vector<Isometry3> poses;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!IsDataLine(line)) continue;
    const std::vector<std::string> cells = SplitNumberCells(line);
    if (cells.size() != 16 && cells.size() != 12)
      throw InputError({path, number, "matrix"}, "expected 16 (4x4) or 12 (3x4) numbers, row-major, got " +
                                                     std::to_string(cells.size()));
    CsvTable row;  // one row in the CSV checker's terms, for the rotation and range checks
    row.path = path;
    row.line_numbers = {number};
    std::vector<std::string> names;
    for (std::size_t i = 0; i < cells.size(); ++i)
      names.push_back("m" + std::to_string(i / 4) + std::to_string(i % 4));
    row.header = names;
    row.rows = {cells};
    if (cells.size() == 16) {
      const double last[4] = {row.Number(0, 12), row.Number(0, 13), row.Number(0, 14), row.Number(0, 15)};
      if (std::abs(last[0]) > 1e-9 || std::abs(last[1]) > 1e-9 || std::abs(last[2]) > 1e-9 ||
          std::abs(last[3] - 1.0) > 1e-9)
        throw InputError({path, number, "m30..m33"}, "the last row of a 4x4 pose must be 0 0 0 1");
    }
    const int rot[9] = {0, 1, 2, 4, 5, 6, 8, 9, 10};
    Isometry3 pose = Isometry3::Identity();
    pose.linear() = PrintedRotation(row, 0, rot, "m00..m22");
    pose.translation() = Vec3(FlangeMm(row, 0, 3, scale), FlangeMm(row, 0, 7, scale), FlangeMm(row, 0, 11, scale));
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace

std::vector<FlangePoseObservation> ReadFlangePoseObservations(const std::string& path, const std::string& flange_units,
                                                              const kinematics::RobotModel* model) {
  const double scale = FlangeUnitScale(path, flange_units);
  const CsvTable t = ReadCsv(path);
  std::vector<FlangePoseObservation> obs;
  if (t.Column("q1", false) >= 0) {
    if (!model) {
      throw InputError({path, 1, "q1"},
                       "the flange poses are given as joints (q1..q6): a robot model is needed to turn them into "
                       "flange poses");
    }
    for (const BoardPoseObservation& o : BoardPosesFromTable(t))
      obs.push_back({kinematics::BaseFromFlange(*model, o.q_controller), o.camera_from_board});
    return obs;
  }
  const FlangeColumns flange(t);
  const BoardColumns board(t);
  const CovarianceColumns covariance(t);
  std::vector<Isometry3> flanges;
  for (std::size_t r = 0; r < t.size(); ++r) {
    FlangePoseObservation o;
    o.camera_from_board = board.Pose(t, r);
    o.camera_from_board_covariance = covariance.Covariance(t, r);
    o.base_from_flange = flange.Pose(t, r, scale);
    flanges.push_back(o.base_from_flange);
    obs.push_back(o);
  }
  RequireFlangeReach(path, flanges);
  return obs;
}

std::vector<Isometry3> ReadFlangePoses(const std::string& path, const std::string& flange_units,
                                       const kinematics::RobotModel* model) {
  const double scale = FlangeUnitScale(path, flange_units);
  const std::string text = ReadTextFile(path);
  if (!FirstDataLineIsNumbers(text)) {
    const CsvTable t = ParseCsv(text, path);
    std::vector<Isometry3> poses;
    if (t.Column("q1", false) >= 0) {
      if (!model)
        throw InputError({path, 1, "q1"},
                         "the flange poses are given as joints (q1..q6): a robot model is needed to turn them into "
                         "flange poses");
      for (std::size_t r = 0; r < t.size(); ++r) {
        kinematics::JointVector q;
        for (int i = 0; i < kinematics::kNumJoints; ++i)
          q[i] = DegToRad(t.Bounded(r, t.Column("q" + std::to_string(i + 1)), kinematics::kMaxAbsJointDeg,
                                    "kMaxAbsJointDeg"));
        poses.push_back(kinematics::BaseFromFlange(*model, q));
      }
      return poses;
    }
    const FlangeColumns flange(t);
    for (std::size_t r = 0; r < t.size(); ++r) poses.push_back(flange.Pose(t, r, scale));
    RequireFlangeReach(path, poses);
    return poses;
  }
  const std::vector<Isometry3> poses = MatrixPerLinePoses(text, path, scale);
  RequireFlangeReach(path, poses);
  return poses;
}

std::vector<FlangePoseObservation> ReadCameraPosesWithFlange(const std::string& path,
                                                             const std::vector<Isometry3>& base_from_flange) {
  const CsvTable t = ReadCsv(path);
  const BoardColumns board(t);
  const CovarianceColumns covariance(t);
  const int pose = t.Column("pose", false);
  if (pose < 0 && t.size() != base_from_flange.size())
    throw InputError({path, 0, "poses"}, std::to_string(t.size()) + " camera poses, but " +
                                             std::to_string(base_from_flange.size()) + " flange poses");
  std::vector<FlangePoseObservation> obs;
  for (std::size_t r = 0; r < t.size(); ++r) {
    FlangePoseObservation o;
    std::size_t index = r;
    if (pose >= 0) {
      const long long number = t.Integer(r, pose);
      if (number < 1 || number > static_cast<long long>(base_from_flange.size()))
        throw InputError({path, t.line_numbers[r], "pose"}, "pose " + std::to_string(number) + " is not one of the " +
                                                                std::to_string(base_from_flange.size()) +
                                                                " flange poses");
      index = static_cast<std::size_t>(number - 1);
    }
    o.base_from_flange = base_from_flange[index];
    o.camera_from_board = board.Pose(t, r);
    o.camera_from_board_covariance = covariance.Covariance(t, r);
    obs.push_back(o);
  }
  return obs;
}

std::string FormatFlangePoseObservations(const std::vector<FlangePoseObservation>& obs, FlangePoseForm form,
                                         const std::string& flange_units, const std::string& comment) {
  const double scale = 1.0 / FlangeUnitScale("", flange_units);
  const int digits = flange_units == "m" ? 9 : 6;
  std::vector<std::string> header = {"pose"};
  if (form == FlangePoseForm::kMatrix) {
    for (int i = 0; i < 12; ++i) header.push_back("flange_m" + std::to_string(i / 4) + std::to_string(i % 4));
  } else {
    header.insert(header.end(), {"flange_x", "flange_y", "flange_z"});
    if (form == FlangePoseForm::kQuaternion) {
      header.insert(header.end(), {"flange_qw", "flange_qx", "flange_qy", "flange_qz"});
    } else {
      header.insert(header.end(), {"flange_a", "flange_b", "flange_c"});
    }
  }
  header.insert(header.end(), {"x", "y", "z", "a", "b", "c"});
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    std::vector<std::string> row = {std::to_string(i + 1)};
    const Isometry3& f = obs[i].base_from_flange;
    if (form == FlangePoseForm::kMatrix) {
      for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(f.linear()(r, k), 12));
        row.push_back(FormatFixed(scale * f.translation()[r], digits));
      }
    } else {
      for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(scale * f.translation()[k], digits));
      if (form == FlangePoseForm::kQuaternion) {
        const Eigen::Quaterniond q(f.linear());
        for (double v : {q.w(), q.x(), q.y(), q.z()}) row.push_back(FormatFixed(v, 12));
      } else {
        const KukaAbc abc = KukaAbcFromRotation(f.linear());
        for (double v : {abc.a, abc.b, abc.c}) row.push_back(FormatFixed(RadToDeg(v), 9));
      }
    }
    const Isometry3& p = obs[i].camera_from_board;
    for (int k = 0; k < 3; ++k) row.push_back(FormatFixed(p.translation()[k], 6));
    const KukaAbc abc = KukaAbcFromRotation(p.linear());
    for (double v : {abc.a, abc.b, abc.c}) row.push_back(FormatFixed(RadToDeg(v), 9));
    rows.push_back(row);
  }
  return FormatCsv(header, rows, comment);
}

std::string HandEyeResultJson(const HandEyeResult& result, const HandEyeSummary& summary,
                              const EyeInHandRefinement* refinement) {
  nlohmann::json j;
  j["setup"] = "camera on a stand (AX = ZB)";
  j["method"] = summary.method;
  j["refined"] = summary.refined;
  if (refinement) j["refinement"] = internal::RefinementJson(*refinement, "camera_from_base", "camera frame");
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
  internal::RequirePoseNoise(sigma_deg, sigma_mm);
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
