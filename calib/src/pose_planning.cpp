#include "ramtk/calib/pose_planning.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>

#include "ramtk/calib/robot_calibration_sim.h"
#include "ramtk/calib/robot_identifiability.h"
#include "ramtk/calib/robot_model_eval.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::calib {

std::string PosePlanningOptions::Validate() const {
  if (num_poses < 1 || num_poses > 1000000) return "num_poses: expected 1..1e6";
  if (num_targets < 1 || num_targets > 100) return "num_targets: expected 1..100";
  if (six_d && targets_in_flange.size() > 1) return "targets_in_flange: 6-D data has one target (the tool origin)";
  if (!six_d && !targets_in_flange.empty() && static_cast<int>(targets_in_flange.size()) != num_targets) {
    return "targets_in_flange: expected num_targets targets";
  }
  if (!(position_sigma_mm > 0.0 && position_sigma_mm < 1e3)) return "position_sigma_mm: expected in (0, 1000) mm";
  if (!(rotation_sigma_deg > 0.0 && rotation_sigma_deg < 10.0)) return "rotation_sigma_deg: expected in (0, 10) deg";
  if (!(parallel_axes_deg >= 0.0 && parallel_axes_deg < 45.0)) return "parallel_axes_deg: expected 0..45";
  if (!(structural_tolerance > 0.0 && structural_tolerance < 1.0)) return "structural_tolerance: expected in (0, 1)";
  if (!(weak_tolerance >= structural_tolerance && weak_tolerance < 1.0)) {
    return "weak_tolerance: expected structural_tolerance..1";
  }
  if (exchange_passes < 0 || exchange_passes > 100) return "exchange_passes: expected 0..100";
  if (random_draws < 0 || random_draws > 10000) return "random_draws: expected 0..10000";
  return "";
}

Isometry3 PosePlanningOptions::DefaultTrackerFromBase() { return RobotCalibrationSimOptions::DefaultTrackerFromBase(); }

std::vector<Vec3> PosePlanningOptions::DefaultTargets(int count) {
  if (count <= 1) return {Vec3(20.0, -10.0, 120.0)};
  std::vector<Vec3> t = {Vec3(0.0, 0.0, 150.0)};
  for (int k = 1; k < count; ++k) {
    const double a = 2.0 * M_PI * (k - 1) / (count - 1);
    t.push_back(Vec3(80.0 * std::cos(a), 80.0 * std::sin(a), 100.0));
  }
  return t;
}

namespace {

double LogDetSmall(const Eigen::MatrixXd& s) {
  const Eigen::LLT<Eigen::MatrixXd> llt(s);
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  return 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
}

}  // namespace

PosePlanner::PosePlanner(const kinematics::RobotChain& nominal, std::vector<Eigen::VectorXd> candidates,
                         const PosePlanningOptions& options)
    : options_(options), candidates_(std::move(candidates)) {
  ThrowIfInvalid(options.Validate(), "PosePlanningOptions");
  const int n = nominal.NumJoints();
  if (candidates_.empty()) throw InputError({"", 0, "candidates"}, "no candidate joint configurations");
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    if (candidates_[i].size() != n) {
      throw InputError({"", 0, "candidates"}, "candidate " + std::to_string(i + 1) + " has " +
                                                  std::to_string(candidates_[i].size()) + " joints, the robot " +
                                                  std::to_string(n));
    }
  }
  std::vector<Vec3> targets = options.targets_in_flange;
  if (targets.empty()) targets = PosePlanningOptions::DefaultTargets(options.six_d ? 1 : options.num_targets);
  ModelFrame frame;
  frame.chain = &nominal;
  frame.layout = UnknownLayout(n, static_cast<int>(targets.size()), options.six_d, 0);
  frame.base_rotation = options.tracker_from_base.linear();
  const UnknownLayout& L = frame.layout;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(L.size);
  x.segment(L.kin, nominal.NumParams()) = nominal.Params();
  x.segment<3>(L.base + 3) = options.tracker_from_base.translation();
  for (std::size_t k = 0; k < targets.size(); ++k) x.segment<3>(L.targets + 3 * k) = targets[k];

  rows_ = L.RowsPerPose();
  Eigen::MatrixXd whitening = Eigen::MatrixXd::Identity(rows_, rows_) / options.position_sigma_mm;
  if (L.rotation) whitening.bottomRightCorner(3, 3) = Mat3::Identity() / DegToRad(options.rotation_sigma_deg);
  const int m = static_cast<int>(candidates_.size());
  Eigen::MatrixXd all(static_cast<Eigen::Index>(m) * rows_, L.size);
  PoseInput pose;
  pose.torque = Eigen::VectorXd::Zero(n);
  pose.measured.assign(targets.size(), Vec3::Zero());
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  for (int i = 0; i < m; ++i) {
    pose.q = candidates_[i];
    EvaluatePose(frame, x, pose, &r, &j);
    all.middleRows(static_cast<Eigen::Index>(i) * rows_, rows_) = whitening * j;
  }

  // The identifiable unknowns, as CalibrateRobot decides them (no non-geometric terms).
  RobotCalibrationOptions calibration;
  calibration.parallel_axes_deg = options.parallel_axes_deg;
  std::vector<bool> candidate(L.size, false);
  for (int i = L.base; i < L.cyclic; ++i) candidate[i] = true;
  const std::vector<bool> links = LinkCandidates(nominal, calibration);
  for (int i = 0; i < nominal.NumParams(); ++i) candidate[L.kin + i] = links[i];
  const std::vector<std::string> names = UnknownNames(L);
  const IdentifiabilityAnalysis analysis = AnalyseIdentifiability(
      all, PreferenceOrder(L, candidate), names, options.structural_tolerance, options.weak_tolerance);
  std::vector<int> kept;
  for (int i = 0; i < L.size; ++i) {
    if (analysis.keep[i]) {
      kept.push_back(i);
    } else if (!analysis.status[i].empty()) {
      base_.eliminated.push_back(names[i] + ": " + analysis.status[i] + ", " + analysis.combination[i]);
    }
  }
  const int p = static_cast<int>(kept.size());
  if (p == 0) throw InputError({"", 0, "candidates"}, "no unknown is identifiable from these candidates");
  jacobian_.resize(all.rows(), p);
  file_scale_.resize(p);
  column_scale_.resize(p);
  for (int k = 0; k < p; ++k) {
    const int i = kept[k];
    jacobian_.col(k) = all.col(i);
    const bool angle = (i < L.base && kinematics::IsChainAngleParam(i - L.kin)) || (i >= L.base && i < L.base + 3) ||
                       (L.rotation && i >= L.tool && i < L.tool + 3);
    file_scale_[k] = angle ? RadToDeg(1.0) : 1.0;
    base_.names.push_back(names[i]);
    base_.units.push_back(angle ? "deg" : "mm");
    const double norm = all.col(i).norm();
    column_scale_[k] = norm > 0.0 ? std::sqrt(static_cast<double>(m)) / norm : 1.0;
  }
  base_.num_candidates = m;
  base_.rows_per_pose = rows_;
}

PoseSetQuality PosePlanner::Evaluate(const std::vector<int>& poses) const {
  const int p = num_unknowns();
  PoseSetQuality q;
  q.poses = static_cast<int>(poses.size());
  Eigen::MatrixXd js(static_cast<Eigen::Index>(poses.size()) * rows_, p);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (poses[i] < 0 || poses[i] >= num_candidates()) {
      throw InputError({"", 0, "poses"}, "index " + std::to_string(poses[i]) + " is not a candidate");
    }
    js.middleRows(static_cast<Eigen::Index>(i) * rows_, rows_) =
        jacobian_.middleRows(static_cast<Eigen::Index>(poses[i]) * rows_, rows_);
  }
  q.sigma = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::infinity());
  if (js.rows() < p) return q;
  const ObservabilityIndices indices = ComputeObservabilityIndices(js);
  q.condition_number = indices.condition_number;
  q.observability_index = indices.observability_index;
  q.noise_amplification_index = indices.noise_amplification_index;
  q.full_rank = std::isfinite(q.condition_number) && q.condition_number < 1e12;
  const Eigen::MatrixXd information = js.transpose() * js;
  q.log_det = LogDetSmall(information);
  if (!q.full_rank) return q;
  // Column-scaled inverse for accuracy, then back to the unknowns' units.
  const Eigen::MatrixXd scaled = column_scale_.asDiagonal() * information * column_scale_.asDiagonal();
  const Eigen::MatrixXd inverse = scaled.ldlt().solve(Eigen::MatrixXd::Identity(p, p));
  for (int k = 0; k < p; ++k) {
    q.sigma[k] = std::sqrt(std::max(0.0, inverse(k, k))) * column_scale_[k] * file_scale_[k];
  }
  return q;
}

std::vector<int> PosePlanner::RandomSet(int num_poses, std::uint64_t seed) const {
  const int m = num_candidates();
  std::vector<int> all(m);
  std::iota(all.begin(), all.end(), 0);
  std::mt19937_64 rng(seed);
  const int k = std::min(num_poses, m);
  for (int i = 0; i < k; ++i) {
    std::uniform_int_distribution<int> pick(i, m - 1);
    std::swap(all[i], all[pick(rng)]);
  }
  all.resize(k);
  std::sort(all.begin(), all.end());
  return all;
}

std::vector<int> PosePlanner::Plan(PosePlanningSummary* summary_out) const {
  const int m = num_candidates();
  const int p = num_unknowns();
  const int n = options_.num_poses;
  if (n > m) {
    throw InputError({"", 0, "num_poses"}, std::to_string(n) + " poses asked from " + std::to_string(m) + " candidates");
  }
  if (n * rows_ < p) {
    throw InputError({"", 0, "num_poses"}, std::to_string(n) + " poses give " + std::to_string(n * rows_) +
                                               " measured values, fewer than the " + std::to_string(p) +
                                               " identifiable unknowns");
  }
  PosePlanningSummary summary = base_;
  // Column-normalised Jacobian (a candidate's average information has unit diagonal) and a tiny
  // ridge, so that the first greedy steps, before full rank, add the directions not yet covered.
  const Eigen::MatrixXd g = jacobian_ * column_scale_.asDiagonal();
  const double ridge = 1e-6;
  Eigen::MatrixXd a = ridge * Eigen::MatrixXd::Identity(p, p);
  const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(rows_, rows_);
  auto block = [&](int c) { return g.middleRows(static_cast<Eigen::Index>(c) * rows_, rows_); };
  // Gain log det(I + G_c A⁻¹ G_cᵀ) of adding each candidate to information `info`.
  Eigen::VectorXd gain(m);
  auto gains = [&](const Eigen::MatrixXd& info) {
    const Eigen::MatrixXd inverse = info.llt().solve(Eigen::MatrixXd::Identity(p, p));
    const Eigen::MatrixXd b = g * inverse;
    for (int c = 0; c < m; ++c) {
      const auto bc = b.middleRows(static_cast<Eigen::Index>(c) * rows_, rows_);
      gain[c] = LogDetSmall(eye + bc * block(c).transpose());
    }
  };
  std::vector<char> chosen(m, 0);
  std::vector<int> set;
  for (int step = 0; step < n; ++step) {
    gains(a);
    int best = -1;
    for (int c = 0; c < m; ++c) {
      if (!chosen[c] && (best < 0 || gain[c] > gain[best])) best = c;
    }
    chosen[best] = 1;
    set.push_back(best);
    a += block(best).transpose() * block(best);
    ++summary.greedy_steps;
  }
  for (int pass = 0; pass < options_.exchange_passes; ++pass) {
    ++summary.exchange_passes;
    bool improved = false;
    for (std::size_t k = 0; k < set.size(); ++k) {
      const int out = set[k];
      const Eigen::MatrixXd without = a - block(out).transpose() * block(out);
      gains(without);
      int best = out;
      for (int c = 0; c < m; ++c) {
        if (!chosen[c] && gain[c] > gain[best] + 1e-9) best = c;
      }
      if (best == out) continue;
      chosen[out] = 0;
      chosen[best] = 1;
      set[k] = best;
      a = without + block(best).transpose() * block(best);
      ++summary.exchanges;
      improved = true;
    }
    if (!improved) break;
  }
  std::sort(set.begin(), set.end());
  summary.planned = Evaluate(set);

  // Random sets of the same size for comparison.
  std::mt19937_64 seeds(options_.seed);
  Eigen::VectorXd sigma2 = Eigen::VectorXd::Zero(p);
  PoseSetQuality& rq = summary.random;
  rq.poses = n;
  for (int d = 0; d < options_.random_draws; ++d) {
    const PoseSetQuality q = Evaluate(RandomSet(n, seeds()));
    if (!q.full_rank) continue;
    ++summary.random_full_rank;
    sigma2 += q.sigma.array().square().matrix();
    rq.log_det += q.log_det;
    rq.condition_number += q.condition_number;
    rq.observability_index += q.observability_index;
    rq.noise_amplification_index += q.noise_amplification_index;
  }
  const int f = summary.random_full_rank;
  rq.full_rank = f > 0;
  if (f > 0) {
    rq.sigma = (sigma2 / f).array().sqrt().matrix();
    rq.log_det /= f;
    rq.condition_number /= f;
    rq.observability_index /= f;
    rq.noise_amplification_index /= f;
  } else {
    rq.sigma = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::infinity());
  }
  if (summary_out != nullptr) *summary_out = summary;
  return set;
}

std::string PosePlanningSummary::Table() const {
  std::ostringstream s;
  char line[200];
  std::snprintf(line, sizeof line, "%-12s %-4s %14s %14s %8s\n", "unknown", "unit", "planned sigma", "random sigma",
                "ratio");
  s << line;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double ps = planned.sigma.size() > static_cast<Eigen::Index>(k) ? planned.sigma[k] : 0.0;
    const double rs = random.sigma.size() > static_cast<Eigen::Index>(k) ? random.sigma[k] : 0.0;
    std::snprintf(line, sizeof line, "%-12s %-4s %14.6g %14.6g %8.3f\n", names[k].c_str(), units[k].c_str(), ps, rs,
                  rs > 0 && std::isfinite(rs) ? ps / rs : 0.0);
    s << line;
  }
  auto row = [&](const char* what, double a, double b) {
    std::snprintf(line, sizeof line, "%-17s %14.6g %14.6g\n", what, a, b);
    s << line;
  };
  row("log det(JtJ)", planned.log_det, random.log_det);
  row("condition number", planned.condition_number, random.condition_number);
  row("O1", planned.observability_index, random.observability_index);
  row("noise amp. index", planned.noise_amplification_index, random.noise_amplification_index);
  return s.str();
}

}  // namespace ramtk::calib
