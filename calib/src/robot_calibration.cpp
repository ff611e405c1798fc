#include "ramtk/calib/robot_calibration.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <functional>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/core/units.h"
#include "ramtk/calib/robot_identifiability.h"
#include "robot_calibration_internal.h"

namespace ramtk::calib {

using detail::CalibrationProblem;
using calib::UnknownLayout;
using kinematics::ChainParamIndex;
using kinematics::ParamKind;

std::string RobotCalibrationOptions::Validate() const {
  if (!(parallel_axes_deg >= 0.0 && parallel_axes_deg < 45.0)) return "parallel_axes_deg: expected 0..45";
  if (!(structural_tolerance > 0.0 && structural_tolerance < 1.0)) return "structural_tolerance: expected in (0, 1)";
  if (!(weak_tolerance >= structural_tolerance && weak_tolerance < 1.0)) {
    return "weak_tolerance: expected structural_tolerance..1";
  }
  if (!(position_sigma_mm > 0.0 && position_sigma_mm < 1e3)) return "position_sigma_mm: expected in (0, 1000) mm";
  if (!(rotation_sigma_deg > 0.0 && rotation_sigma_deg < 10.0)) return "rotation_sigma_deg: expected in (0, 10) deg";
  if (!(loss_scale > 0.0 && std::isfinite(loss_scale))) return "loss_scale: expected > 0";
  if (cyclic_harmonics < 0 || cyclic_harmonics > 4) return "cyclic_harmonics: expected 0..4";
  if (!(min_term_gain >= 0.0 && min_term_gain < 1.0)) return "min_term_gain: expected 0..1";
  if (!(min_joint_range_deg >= 0.0)) return "min_joint_range_deg: expected >= 0";
  if (!(min_spread_fraction >= 0.0 && min_spread_fraction < 1.0)) return "min_spread_fraction: expected 0..1";
  if (folds < 2 || folds > 100) return "folds: expected 2..100";
  if (max_iterations < 1 || max_iterations > 10000) return "max_iterations: expected 1..10000";
  if (num_threads < 1 || num_threads > 256) return "num_threads: expected 1..256";
  return "";
}

std::string RobotCalibrationSummary::BriefReport() const {
  std::ostringstream s;
  s.precision(4);
  s << TerminationName(termination) << ": " << num_poses << " poses, " << num_identified << " unknowns identified ("
    << num_eliminated << " eliminated), RMS per coordinate " << before.rms_per_coordinate_mm << " -> "
    << after.rms_per_coordinate_mm << " mm, held-out " << held_out.rms_per_coordinate_mm << " mm (predicted "
    << predicted_held_out_mm << "), cond " << condition_number;
  return s.str();
}

std::vector<std::string> UnknownNames(const UnknownLayout& L) {
  std::vector<std::string> names(L.size);
  for (int i = 0; i < kinematics::kParamsPerLink * L.num_joints; ++i) names[L.kin + i] = kinematics::ChainParamName(i);
  const char* axes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    names[L.base + k] = std::string("base_r") + axes[k];
    names[L.base + 3 + k] = std::string("base_") + axes[k];
    if (L.rotation) names[L.tool + k] = std::string("tool_r") + axes[k];
  }
  for (int t = 0; t < L.num_targets; ++t) {
    for (int k = 0; k < 3; ++k) names[L.targets + 3 * t + k] = "target" + std::to_string(t + 1) + "_" + axes[k];
  }
  for (int j = 0; j < L.num_joints; ++j) {
    for (int h = 1; h <= L.harmonics; ++h) {
      const int c = L.cyclic + 2 * (L.harmonics * j + h - 1);
      names[c] = "cyc_s" + std::to_string(h) + "_j" + std::to_string(j + 1);
      names[c + 1] = "cyc_c" + std::to_string(h) + "_j" + std::to_string(j + 1);
    }
    names[L.compliance + j] = "compliance_j" + std::to_string(j + 1);
  }
  return names;
}

namespace {

// File units per internal unit (deg per rad for angles; compliance in deg per kg·m).
double FileScale(const UnknownLayout& L, int i) {
  if (i >= L.kin && i < L.base) return kinematics::IsChainAngleParam(i - L.kin) ? RadToDeg(1.0) : 1.0;
  if (i >= L.base && i < L.base + 3) return RadToDeg(1.0);
  if (L.rotation && i >= L.tool && i < L.tool + 3) return RadToDeg(1.0);
  if (i >= L.cyclic && i < L.compliance) return RadToDeg(1.0);
  if (i >= L.compliance) return RadToDeg(1.0) * 1000.0;
  return 1.0;
}

const char* FileUnit(const UnknownLayout& L, int i) {
  if (i >= L.compliance) return "deg/(kg·m)";
  return FileScale(L, i) == 1.0 ? "mm" : "deg";
}

// Whitening of one pose: per target L⁻¹ of its covariance (or 1/σ), the rotation rows 1/σ_rot.
Eigen::MatrixXd Whitening(const kinematics::TrackerPose& pose, const UnknownLayout& L, double sigma_mm,
                          double sigma_rot_rad) {
  const int rows = L.RowsPerPose();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(rows, rows);
  for (int k = 0; k < L.num_targets; ++k) {
    const kinematics::TargetMeasurement& t = pose.targets[k];
    if (t.has_covariance) {
      const Eigen::LLT<Mat3> llt(t.covariance_mm2);
      if (llt.info() != Eigen::Success) {
        throw InputError({"", pose.line, "covariance"}, "the covariance of target " + std::to_string(k + 1) +
                                                            " is not positive definite");
      }
      w.block<3, 3>(3 * k, 3 * k) = llt.matrixL().solve(Mat3::Identity());
    } else {
      w.block<3, 3>(3 * k, 3 * k) = Mat3::Identity() / sigma_mm;
    }
  }
  if (L.rotation) w.block<3, 3>(3 * L.num_targets, 3 * L.num_targets) = Mat3::Identity() / sigma_rot_rad;
  return w;
}

// The set-up in closed form with the links as they are: M·y − R_i·p_k − u = t_i with M = R_tbᵀ
// (linear in M, u and the targets), M projected onto SO(3), then targets and translation again.
void LinearSetup(CalibrationProblem* problem, Eigen::VectorXd* x) {
  const UnknownLayout& L = problem->frame.layout;
  const kinematics::RobotChain chain = ChainFromUnknowns(problem->frame, *x);
  const int n = static_cast<int>(problem->poses.size());
  std::vector<Isometry3> flange(n);
  for (int i = 0; i < n; ++i) flange[i] = kinematics::ChainBaseFromFlange(chain, problem->poses[i].q);
  const int cols = 12 + 3 * L.num_targets;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * n * L.num_targets, cols);
  Eigen::VectorXd b(3 * n * L.num_targets);
  int row = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < L.num_targets; ++k) {
      const Vec3& y = problem->poses[i].measured[k];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) a(row + r, 3 * r + c) = y[c];
        a(row + r, 9 + r) = -1.0;
      }
      a.block<3, 3>(row, 12 + 3 * k) = -flange[i].linear();
      b.segment<3>(row) = flange[i].translation();
      row += 3;
    }
  }
  const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
  Mat3 m;
  m << sol[0], sol[1], sol[2], sol[3], sol[4], sol[5], sol[6], sol[7], sol[8];
  const Mat3 r_tb = NearestRotation(m).transpose();
  // Targets and translation with the rotation fixed: R_tb·R_i·p_k + t = y − R_tb·t_i.
  Eigen::MatrixXd a2 = Eigen::MatrixXd::Zero(3 * n * L.num_targets, 3 + 3 * L.num_targets);
  Eigen::VectorXd b2(3 * n * L.num_targets);
  row = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < L.num_targets; ++k) {
      a2.block<3, 3>(row, 0) = Mat3::Identity();
      a2.block<3, 3>(row, 3 + 3 * k) = r_tb * flange[i].linear();
      b2.segment<3>(row) = problem->poses[i].measured[k] - r_tb * flange[i].translation();
      row += 3;
    }
  }
  const Eigen::VectorXd sol2 = a2.colPivHouseholderQr().solve(b2);
  problem->frame.base_rotation = r_tb;
  x->segment<3>(L.base).setZero();
  x->segment<3>(L.base + 3) = sol2.head<3>();
  for (int k = 0; k < L.num_targets; ++k) x->segment<3>(L.targets + 3 * k) = sol2.segment<3>(3 + 3 * k);
  if (L.rotation) {
    Mat3 sum = Mat3::Zero();
    for (int i = 0; i < n; ++i) sum += (r_tb * flange[i].linear()).transpose() * problem->poses[i].measured_rotation;
    problem->frame.tool_rotation = NearestRotation(sum);
    x->segment<3>(L.tool).setZero();
  }
}

std::vector<bool> SetupFree(const UnknownLayout& L) {
  std::vector<bool> free(L.size, false);
  for (int i = L.base; i < L.cyclic; ++i) free[i] = true;
  return free;
}

}  // namespace

// |α| within parallel_axes_deg of 0 or 180° offers β.
std::vector<bool> LinkCandidates(const kinematics::RobotChain& chain, const RobotCalibrationOptions& o) {
  std::vector<bool> c(chain.NumParams(), false);
  for (int i = 0; i < chain.NumParams(); ++i) c[i] = !chain.structural_zero[i];
  const double limit = std::sin(DegToRad(o.parallel_axes_deg));
  for (int j = 0; j < chain.NumJoints(); ++j) {
    if (std::abs(std::sin(chain.links[j].alpha)) < limit) c[ChainParamIndex(ParamKind::kBeta, j)] = true;
  }
  return c;
}

std::vector<int> PreferenceOrder(const UnknownLayout& L, const std::vector<bool>& candidate) {
  std::vector<int> order;
  auto add = [&](int i) {
    if (candidate[i]) order.push_back(i);
  };
  for (int i = L.base; i < L.cyclic; ++i) add(i);
  for (int j = 0; j < L.num_joints; ++j) {
    for (ParamKind k : {ParamKind::kTheta, ParamKind::kA, ParamKind::kAlpha, ParamKind::kBeta}) {
      add(L.kin + ChainParamIndex(k, j));
    }
  }
  for (int j = 0; j < L.num_joints; ++j) add(L.kin + ChainParamIndex(ParamKind::kD, j));
  for (int i = L.cyclic; i < L.size; ++i) add(i);
  return order;
}

namespace {

struct Stage {
  std::vector<bool> free;
  detail::Elimination elimination;
};

Stage IdentifyAndSolve(CalibrationProblem* problem, const std::vector<bool>& candidate,
                       const std::vector<std::string>& names, const RobotCalibrationOptions& options, Eigen::VectorXd* x,
                       RobotCalibrationSummary* summary) {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  detail::StackResiduals(*problem, *x, {}, &r, &j);
  Stage stage;
  stage.elimination = detail::AnalyseIdentifiability(j, PreferenceOrder(problem->frame.layout, candidate), names,
                                                     options.structural_tolerance, options.weak_tolerance);
  stage.free = stage.elimination.keep;
  // A fit needs more equations than unknowns, and its held-out check needs the same of each fold's
  // training share: else the "fit" is exact and every figure after it meaningless.
  const int p = static_cast<int>(std::count(stage.free.begin(), stage.free.end(), true));
  const int m = static_cast<int>(r.size());
  const int m_train = m - (m + options.folds - 1) / options.folds;
  if (m_train <= p + 2) {
    throw InputError({"", 0, "poses"},
                     std::to_string(problem->poses.size()) + " poses give " + std::to_string(m) + " equations for " +
                         std::to_string(p) + " identifiable unknowns; with " + std::to_string(options.folds) +
                         "-fold hold-out each fit would see " + std::to_string(m_train) +
                         ": measure more poses (at least " +
                         std::to_string((p + 3) * options.folds / (options.folds - 1) / problem->frame.layout.RowsPerPose() + 1) +
                         ")");
  }
  const detail::SolveResult solved = detail::SolveUnknowns(*problem, stage.free, {}, options, options.max_iterations, x);
  detail::Recentre(problem, x);
  summary->iterations += solved.iterations;
  summary->termination = solved.termination;
  return stage;
}

std::vector<std::vector<Vec3>> PositionResiduals(const CalibrationProblem& problem, const Eigen::VectorXd& x,
                                                 std::vector<double>* rotation_deg) {
  const UnknownLayout& L = problem.frame.layout;
  std::vector<std::vector<Vec3>> out;
  for (const PoseInput& pose : problem.poses) {
    Eigen::VectorXd r;
    EvaluatePose(problem.frame, x, pose, &r, nullptr);
    std::vector<Vec3> p;
    for (int k = 0; k < L.num_targets; ++k) p.push_back(r.segment<3>(3 * k));
    out.push_back(p);
    if (L.rotation && rotation_deg != nullptr) rotation_deg->push_back(RadToDeg(r.tail<3>().norm()));
  }
  return out;
}

// Re-weights by variance components: σ_pos and σ_rot set to their residual RMS per component.
void EstimateSigmas(CalibrationProblem* problem, const Eigen::VectorXd& x, RobotCalibrationSummary* summary,
                    const kinematics::TrackerMeasurements& data) {
  std::vector<double> rot;
  const ResidualStats s = detail::StatsOf(PositionResiduals(*problem, x, &rot), rot);
  const double sigma_mm = std::max(s.rms_per_coordinate_mm, 1e-6);
  const double sigma_rot = std::max(DegToRad(s.rms_rotation_deg) / std::sqrt(3.0), 1e-9);
  summary->position_sigma_mm = sigma_mm;
  summary->rotation_sigma_deg = RadToDeg(sigma_rot);
  for (std::size_t i = 0; i < problem->poses.size(); ++i) {
    problem->poses[i].whitening = Whitening(data.poses[i], problem->frame.layout, sigma_mm, sigma_rot);
  }
}

double HeldOutRms(const CalibrationProblem& problem, const std::vector<bool>& free, const RobotCalibrationOptions& o,
                  const Eigen::VectorXd& x, std::vector<std::vector<Vec3>>* residuals) {
  *residuals = detail::HeldOutResiduals(problem, free, o, x);
  return detail::StatsOf(*residuals).rms_per_coordinate_mm;
}

void CheckInput(const kinematics::RobotChain& nominal, const kinematics::TrackerMeasurements& data) {
  if (data.num_joints != nominal.NumJoints()) {
    throw InputError({"", 0, "joints"}, "the measurements have " + std::to_string(data.num_joints) +
                                            " joints, the robot " + std::to_string(nominal.NumJoints()));
  }
  if (data.poses.empty()) throw InputError({"", 0, ""}, "no poses");
  for (const kinematics::TrackerPose& p : data.poses) {
    if (p.targets.size() != data.target_names.size() || static_cast<int>(p.q_rad.size()) != data.num_joints) {
      throw InputError({"", p.line, ""}, "every pose must hold every target and every joint");
    }
  }
}

// Joint ranges and the spread of the measured targets, with the warnings they call for.
void Coverage(const kinematics::RobotChain& nominal, const kinematics::TrackerMeasurements& data,
              const RobotCalibrationOptions& options, RobotCalibrationSummary* summary) {
  const int n = nominal.NumJoints();
  std::vector<double> lo(n, 1e300), hi(n, -1e300);
  Vec3 mean = Vec3::Zero();
  for (const kinematics::TrackerPose& p : data.poses) {
    for (int j = 0; j < n; ++j) {
      lo[j] = std::min(lo[j], p.q_rad[j]);
      hi[j] = std::max(hi[j], p.q_rad[j]);
    }
    mean += p.targets[0].position_mm;
  }
  mean /= static_cast<double>(data.poses.size());
  double spread = 0.0;
  for (const kinematics::TrackerPose& p : data.poses) spread += (p.targets[0].position_mm - mean).squaredNorm();
  summary->workspace_spread_mm = std::sqrt(spread / data.poses.size());
  summary->reach_mm = kinematics::ChainReachMm(nominal);
  std::string narrow;
  for (int j = 0; j < n; ++j) {
    summary->joint_range_deg.push_back(RadToDeg(hi[j] - lo[j]));
    if (summary->joint_range_deg.back() < options.min_joint_range_deg) {
      char text[64];
      std::snprintf(text, sizeof text, "%sjoint %d over %.1f deg", narrow.empty() ? "" : ", ", j + 1,
                    summary->joint_range_deg.back());
      narrow += text;
    }
  }
  if (!narrow.empty()) {
    summary->warnings.push_back("the poses move " + narrow + " only: the calibration predicts other joint values by "
                                "extrapolation");
  }
  if (summary->workspace_spread_mm < options.min_spread_fraction * summary->reach_mm) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the targets spread %.0f mm (RMS about their centroid) against a reach of %.0f mm: the poses cover "
                  "a small part of the workspace",
                  summary->workspace_spread_mm, summary->reach_mm);
    summary->warnings.push_back(text);
  }
}

// Non-geometric terms (cyclic joint errors, compliance), each kept when the held-out RMS drops by
// min_term_gain: the problem, unknowns, stage and candidate set become the extended ones.
void TryTerms(const kinematics::RobotChain& nominal, const std::vector<std::string>& names,
              const RobotCalibrationOptions& options,
              const std::function<void(const char*, std::size_t, std::size_t)>& report, CalibrationProblem* problem_io,
              Eigen::VectorXd* x_io, Stage* stage_io, std::vector<bool>* candidate_io, double* best_io,
              std::vector<std::vector<Vec3>>* held_io, RobotCalibrationSummary* summary_io) {
  CalibrationProblem& problem = *problem_io;
  Eigen::VectorXd& x = *x_io;
  Stage& stage = *stage_io;
  std::vector<bool>& candidate = *candidate_io;
  double& best = *best_io;
  std::vector<std::vector<Vec3>>& held = *held_io;
  RobotCalibrationSummary& summary = *summary_io;
  const UnknownLayout& L = problem.frame.layout;
  const int harmonics = options.try_cyclic ? options.cyclic_harmonics : 0;
  std::vector<std::pair<std::string, std::pair<int, int>>> groups;
  if (harmonics > 0) groups.push_back({"cyclic", {L.cyclic, L.compliance}});
  if (options.try_compliance && nominal.HasMasses()) groups.push_back({"compliance", {L.compliance, L.size}});
  if (options.try_compliance && !nominal.HasMasses()) {
    summary.warnings.push_back("compliance not tried: the robot file has no link masses");
  }
  for (const auto& group : groups) {
    report("terms", 0, groups.size());
    std::vector<bool> trial = candidate;
    for (int i = group.second.first; i < group.second.second; ++i) trial[i] = true;
    CalibrationProblem p2 = problem;
    Eigen::VectorXd x2 = x;
    RobotCalibrationSummary scratch;
    Stage s2;
    try {
      s2 = IdentifyAndSolve(&p2, trial, names, options, &x2, &scratch);
    } catch (const InputError& e) {
      summary.warnings.push_back(group.first + " terms not tried: " + e.message());
      continue;
    }
    std::vector<std::vector<Vec3>> held2;
    const double rms2 = HeldOutRms(p2, s2.free, options, x2, &held2);
    RAMTK_LOG(kInfo) << "calib robot: " << group.first << " terms: held-out " << rms2 << " mm against " << best
                     << " mm";
    if (rms2 < best * (1.0 - options.min_term_gain)) {
      best = rms2;
      held = held2;
      candidate = trial;
      problem = p2;
      x = x2;
      stage = s2;
      summary.iterations += scratch.iterations;
      summary.terms_kept.push_back(group.first);
    }
  }
}

// The identified unknowns, their covariance (options.covariance) and the predicted held-out RMS.
void Covariance(const CalibrationProblem& problem, const Eigen::VectorXd& x, const Stage& stage,
                const RobotCalibrationOptions& options, RobotCalibration* result_io,
                RobotCalibrationSummary* summary_io) {
  RobotCalibration& result = *result_io;
  RobotCalibrationSummary& summary = *summary_io;
  const UnknownLayout& L = problem.frame.layout;
  for (int i = 0; i < L.size; ++i) {
    if (stage.free[i]) result.identified.push_back(i);
  }
  Eigen::VectorXd r;
  Eigen::MatrixXd jac;
  detail::StackResiduals(problem, x, {}, &r, &jac);
  const int m = static_cast<int>(r.size());
  const int p = static_cast<int>(result.identified.size());
  Eigen::MatrixXd ji(m, p);
  for (int k = 0; k < p; ++k) ji.col(k) = jac.col(result.identified[k]);
  const Eigen::MatrixXd information = ji.transpose() * ji;
  const Eigen::MatrixXd inverse = information.ldlt().solve(Eigen::MatrixXd::Identity(p, p));
  summary.reduced_chi2 = r.squaredNorm() / std::max(1, m - p);
  if (options.covariance == CovarianceKind::kScaled) {
    result.covariance = inverse * summary.reduced_chi2;
  } else if (options.covariance == CovarianceKind::kSandwich) {
    Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(p, p);
    const int rows = L.RowsPerPose();
    for (int i = 0; i < m / rows; ++i) {
      const Eigen::VectorXd g = ji.middleRows(rows * i, rows).transpose() * r.segment(rows * i, rows);
      meat += g * g.transpose();
    }
    result.covariance = inverse * meat * inverse;
  } else {
    result.covariance = inverse;
  }
  // Predicted held-out RMS per coordinate: the residual scale plus the parameters' uncertainty.
  {
    double sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < problem.poses.size(); ++i) {
      Eigen::VectorXd ri;
      Eigen::MatrixXd jp;
      EvaluatePose(problem.frame, x, problem.poses[i], &ri, &jp);
      Eigen::MatrixXd jpi(jp.rows(), p);
      for (int k = 0; k < p; ++k) jpi.col(k) = jp.col(result.identified[k]);
      for (int t = 0; t < L.num_targets; ++t) {
        sum += (jpi.middleRows(3 * t, 3) * result.covariance * jpi.middleRows(3 * t, 3).transpose()).trace();
        count += 3;
      }
    }
    const double model = summary.after.rms_per_coordinate_mm;
    summary.predicted_held_out_mm = std::sqrt(model * model * m / std::max(1, m - p) + sum / std::max(1, count));
  }
}

// Every unknown offered, with its nominal and fitted value in file units and its status.
void TableOfUnknowns(const UnknownLayout& L, const std::vector<std::string>& names, const Eigen::VectorXd& x_nominal,
                     const Eigen::VectorXd& x, const Stage& stage, const RobotCalibrationOptions& options,
                     bool has_masses, RobotCalibration* result_io, RobotCalibrationSummary* summary_io) {
  RobotCalibration& result = *result_io;
  RobotCalibrationSummary& summary = *summary_io;
  const int harmonics = options.try_cyclic ? options.cyclic_harmonics : 0;
  for (int i = 0; i < L.size; ++i) {
    CalibrationUnknown u;
    u.name = names[i];
    u.unit = FileUnit(L, i);
    const double scale = FileScale(L, i);
    u.nominal = x_nominal[i] * scale;
    u.value = x[i] * scale;
    if (i >= L.base && i < L.cyclic) u.nominal = u.value;  // the set-up has no nominal
    if (stage.free[i]) {
      u.status = "identified";
      const int k = static_cast<int>(std::find(result.identified.begin(), result.identified.end(), i) -
                                     result.identified.begin());
      u.sigma = std::sqrt(std::max(0.0, result.covariance(k, k))) * scale;
    } else if (!stage.elimination.status[i].empty()) {
      u.status = stage.elimination.status[i];
      u.independence = stage.elimination.independence[i];
      u.combination = stage.elimination.combination[i];
    } else if (i >= L.cyclic) {
      u.status = "not_kept";
    } else {
      u.status = "fixed";
    }
    const bool offered = i < L.cyclic || (i < L.compliance && harmonics > 0) ||
                         (i >= L.compliance && options.try_compliance && has_masses);
    if (!offered) continue;
    result.unknowns.push_back(u);
    if (u.status == "not_identifiable" || u.status == "weak") ++summary.num_eliminated;
  }
}

}  // namespace

RobotCalibration CalibrateRobot(const kinematics::RobotChain& nominal, const kinematics::TrackerMeasurements& data,
                                const RobotCalibrationOptions& options, RobotCalibrationSummary* summary_out) {
  ThrowIfInvalid(options.Validate(), "RobotCalibrationOptions");
  CheckInput(nominal, data);
  RobotCalibrationSummary local;
  RobotCalibrationSummary& summary = summary_out != nullptr ? *summary_out : local;
  summary = RobotCalibrationSummary{};
  const int n = nominal.NumJoints();
  const bool rotation = options.use_rotation && data.has_rotation;
  const int harmonics = options.try_cyclic ? options.cyclic_harmonics : 0;
  CalibrationProblem problem;
  problem.frame.chain = &nominal;
  problem.frame.layout = UnknownLayout(n, static_cast<int>(data.target_names.size()), rotation, harmonics);
  const UnknownLayout& L = problem.frame.layout;
  const std::vector<std::string> names = UnknownNames(L);
  for (const kinematics::TrackerPose& p : data.poses) {
    PoseInput in;
    in.q = Eigen::Map<const Eigen::VectorXd>(p.q_rad.data(), n);
    in.torque = kinematics::GravityTorques(nominal, in.q);
    for (const auto& t : p.targets) in.measured.push_back(t.position_mm);
    if (rotation) in.measured_rotation = *p.tracker_from_tool_rotation;
    in.whitening = Whitening(p, L, options.position_sigma_mm, DegToRad(options.rotation_sigma_deg));
    problem.poses.push_back(std::move(in));
  }
  summary.num_poses = static_cast<int>(data.poses.size());
  summary.num_targets = L.num_targets;
  summary.used_rotation = rotation;
  summary.position_sigma_mm = options.position_sigma_mm;
  summary.rotation_sigma_deg = options.rotation_sigma_deg;

  Eigen::VectorXd x = Eigen::VectorXd::Zero(L.size);
  x.segment(L.kin, nominal.NumParams()) = nominal.Params();
  const Eigen::VectorXd x_nominal = x;
  const std::function<void(const char*, std::size_t, std::size_t)> report = [&](const char* stage, std::size_t done,
                                                                                 std::size_t total) {
    if (options.progress && !options.progress({stage, done, total})) throw InputError({"", 0, ""}, "cancelled");
  };

  // 1. The set-up with the nominal links: the "before" figures.
  report("setup", 0, 1);
  LinearSetup(&problem, &x);
  std::vector<bool> free = SetupFree(L);
  detail::SolveUnknowns(problem, free, {}, options, options.max_iterations, &x);
  detail::Recentre(&problem, &x);
  std::vector<double> rot_before;
  const auto before = PositionResiduals(problem, x, &rot_before);
  summary.before = detail::StatsOf(before, rot_before);
  for (const auto& p : before) summary.residuals_before.push_back(p[0]);

  // 2. The links, with identifiability first.
  std::vector<bool> candidate = free;
  if (options.identify_links) {
    const std::vector<bool> links = LinkCandidates(nominal, options);
    for (int i = 0; i < nominal.NumParams(); ++i) candidate[L.kin + i] = links[i];
  }
  report("links", 0, 1);
  Stage stage = IdentifyAndSolve(&problem, candidate, names, options, &x, &summary);
  if (options.estimate_sigmas) {
    EstimateSigmas(&problem, x, &summary, data);
    stage = IdentifyAndSolve(&problem, candidate, names, options, &x, &summary);
  }

  // The links alone, for the robot file (the terms below refit the links with them).
  const Eigen::VectorXd x_links = x;
  const CalibrationProblem problem_links = problem;

  // 3. Non-geometric terms, each kept when the held-out RMS drops by min_term_gain.
  std::vector<std::vector<Vec3>> held;
  double best = HeldOutRms(problem, stage.free, options, x, &held);
  summary.held_out_geometric = detail::StatsOf(held);
  TryTerms(nominal, names, options, report, &problem, &x, &stage, &candidate, &best, &held, &summary);
  summary.held_out = detail::StatsOf(held);
  for (const auto& p : held) summary.residuals_held_out.push_back(p[0]);

  // 4. The result, its covariance and the table of unknowns.
  std::vector<double> rot_after;
  const auto after = PositionResiduals(problem, x, &rot_after);
  summary.after = detail::StatsOf(after, rot_after);
  for (const auto& p : after) summary.residuals_after.push_back(p[0]);

  RobotCalibration result;
  result.chain = ChainFromUnknowns(problem.frame, x);
  result.links_only = ChainFromUnknowns(problem_links.frame, x_links);
  for (int j = 0; j < n; ++j) {
    if (candidate[L.kin + ChainParamIndex(ParamKind::kBeta, j)]) {
      for (kinematics::RobotChain* c : {&result.chain, &result.links_only}) {
        c->structural_zero[ChainParamIndex(ParamKind::kBeta, j)] = false;
        c->convention = kinematics::Convention::kMdh;
      }
    }
  }
  result.tracker_from_base.linear() = problem.frame.base_rotation;
  result.tracker_from_base.translation() = x.segment<3>(L.base + 3);
  for (int k = 0; k < L.num_targets; ++k) result.targets_in_flange.push_back(x.segment<3>(L.targets + 3 * k));
  if (rotation) result.flange_from_tool_rotation = problem.frame.tool_rotation;
  result.cyclic = Eigen::MatrixXd::Zero(n, 2 * harmonics);
  result.compliance = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < 2 * harmonics; ++c) result.cyclic(j, c) = x[L.cyclic + 2 * harmonics * j + c];
    result.compliance[j] = x[L.compliance + j];
  }

  Covariance(problem, x, stage, options, &result, &summary);

  TableOfUnknowns(problem.frame.layout, names, x_nominal, x, stage, options, nominal.HasMasses(), &result, &summary);
  summary.num_identified = static_cast<int>(result.identified.size());
  summary.condition_number = stage.elimination.condition_number;
  summary.observability_index = stage.elimination.observability_index;
  summary.noise_amplification_index = stage.elimination.noise_amplification_index;
  Coverage(nominal, data, options, &summary);
  if (summary.held_out.rms_per_coordinate_mm > 2.0 * summary.after.rms_per_coordinate_mm) {
    summary.warnings.push_back("held-out error is more than twice the fit's: the poses may not support prediction "
                               "beyond them (add poses spread over the workspace)");
  }
  if (summary.termination == Termination::kSuccess && summary.num_eliminated > 0) {
    summary.message = std::to_string(summary.num_eliminated) + " unknowns eliminated as not identifiable";
  }
  return result;
}

namespace {

// The calibrated chain at q with the non-geometric terms folded into the joint offsets.
kinematics::RobotChain ChainAt(const RobotCalibration& c, const Eigen::VectorXd& q) {
  kinematics::RobotChain chain = c.chain;
  const int h = static_cast<int>(c.cyclic.cols()) / 2;
  const bool compliance = c.compliance.size() == chain.NumJoints() && c.compliance.any();
  const Eigen::VectorXd torque = compliance ? kinematics::GravityTorques(c.chain, q) : Eigen::VectorXd();
  for (int j = 0; j < chain.NumJoints(); ++j) {
    double extra = 0.0;
    for (int k = 1; k <= h; ++k) {
      extra += c.cyclic(j, 2 * (k - 1)) * std::sin(k * q[j]) + c.cyclic(j, 2 * (k - 1) + 1) * std::cos(k * q[j]);
    }
    if (compliance) extra += c.compliance[j] * torque[j];
    chain.mapping[j].offset += extra;
  }
  return chain;
}

}  // namespace

Vec3 PredictTarget(const RobotCalibration& c, const Eigen::VectorXd& q, int target) {
  return c.tracker_from_base * (kinematics::ChainBaseFromFlange(ChainAt(c, q), q) * c.targets_in_flange[target]);
}

Mat3 PredictToolRotation(const RobotCalibration& c, const Eigen::VectorXd& q) {
  return c.tracker_from_base.linear() * kinematics::ChainBaseFromFlange(ChainAt(c, q), q).linear() *
         c.flange_from_tool_rotation.value_or(Mat3::Identity());
}

ResidualStats EvaluateCalibration(const RobotCalibration& c, const kinematics::TrackerMeasurements& data,
                                  std::vector<Vec3>* residuals) {
  std::vector<std::vector<Vec3>> all;
  for (const kinematics::TrackerPose& p : data.poses) {
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(p.q_rad.data(), p.q_rad.size());
    std::vector<Vec3> r;
    for (std::size_t k = 0; k < p.targets.size() && k < c.targets_in_flange.size(); ++k) {
      r.push_back(PredictTarget(c, q, static_cast<int>(k)) - p.targets[k].position_mm);
    }
    if (residuals != nullptr && !r.empty()) residuals->push_back(r[0]);
    all.push_back(r);
  }
  return detail::StatsOf(all);
}

}  // namespace ramtk::calib
