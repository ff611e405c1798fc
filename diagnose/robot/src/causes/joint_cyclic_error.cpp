// Joint cyclic error (encoder eccentricity, gear run-out): Δθ_j = a·sin q_j + b·cos q_j +
// c·sin 2q_j + d·cos 2q_j. Joints added greedily by held-out score (each must pay min_improvement),
// at most two.
#include <algorithm>
#include <cmath>

#include "../robot_fit_kit.h"
#include "ramtk/core/units.h"

namespace ramtk::diagnose::robot_detail {
namespace {

using kinematics::ParamKind;

// sin q, cos q, sin 2q, cos 2q of joint j (0-based) along its θ column.
std::vector<Mat3X> JointCols(const std::vector<Row>& rows, int j) {
  std::vector<Mat3X> cols;
  const int theta = kinematics::ParamIndex(ParamKind::kTheta, j + 1);
  for (const Row& r : rows) {
    Mat3X m(3, 4);
    const double q = r.q[j];
    m.col(0) = r.j_param.col(theta) * std::sin(q);
    m.col(1) = r.j_param.col(theta) * std::cos(q);
    m.col(2) = r.j_param.col(theta) * std::sin(2 * q);
    m.col(3) = r.j_param.col(theta) * std::cos(2 * q);
    cols.push_back(m);
  }
  return cols;
}

// The model extended so far and the best next joint.
struct CyclicStep {
  double score = INFINITY;
  int joint = -1;
  int added = 0;
  Design design;
  CvResult cv;
  std::vector<std::pair<std::string, double>> keys;
};

// The best joint (not in `joints`) and number of terms to add to `current`: once per turn
// (eccentricity: sin/cos q) or once and twice per turn (+ sin/cos 2q).
CyclicStep BestNextJoint(const Context& ctx, const Design& current, int current_k, const std::vector<int>& joints) {
  static const char* kTerm[4] = {"sin_q", "cos_q", "sin_2q", "cos_2q"};
  CyclicStep best;
  for (int j = 0; j < 6; ++j) {
    if (std::find(joints.begin(), joints.end(), j) != joints.end()) continue;
    for (const int terms : {2, 4}) {
      const std::vector<Mat3X> all = JointCols(ctx.rows->rows, j);
      const std::vector<Mat3X> cols =
          SelectColumns(all, terms == 2 ? std::vector<int>{0, 1} : std::vector<int>{0, 1, 2, 3});
      const std::vector<int> keep = IndependentColumns(PooledBlocks(current), cols);
      if (keep.empty()) continue;
      std::vector<std::string> names;
      std::vector<std::pair<std::string, double>> ks;
      for (int k : keep) {
        names.push_back("q" + std::to_string(j + 1) + "_" + kTerm[k]);
        ks.emplace_back("joint" + std::to_string(j + 1) + "_" + kTerm[k] + "_deg", kDegPerRad);
      }
      Design d = current;
      AddStaticColumns(SelectColumns(cols, keep), names, &d);
      CvResult cv = Cv(ctx, d);
      const int added = static_cast<int>(keep.size());
      // A joint whose fitted cycle is beyond a plausible amplitude is aliased with something
      // else (the set-up, another joint): it is not offered.
      bool plausible = cv.full.ok;
      for (int k = 0; k < added && plausible; ++k) {
        plausible = std::abs(cv.full.s[d.ns - added + k]) * kDegPerRad <= PlausibilityBounds{}.cyclic_deg;
      }
      if (!plausible) continue;
      const double sc = Score(cv.heldout_ss, ctx.base_cv.heldout_n, current_k + added);
      if (sc < best.score)
        best.score = sc, best.joint = j, best.design = std::move(d), best.cv = std::move(cv), best.keys = ks,
        best.added = added;
    }
  }
  return best;
}

void FitJointCyclicError(const Context& ctx, CauseOutput out) {
  Design current = ctx.base;
  double current_score = Score(ctx.base_cv.heldout_ss, ctx.base_cv.heldout_n, 0);
  int current_k = 0;
  std::vector<int> joints;
  std::vector<std::pair<std::string, double>> keys;
  CvResult current_cv;
  while (joints.size() < 2) {
    CyclicStep best = BestNextJoint(ctx, current, current_k, joints);
    if (best.joint < 0 || !(best.score < current_score - ctx.min_improvement)) break;
    joints.push_back(best.joint);
    current = std::move(best.design);
    current_cv = std::move(best.cv);
    current_score = best.score;
    current_k += best.added;
    keys.insert(keys.end(), best.keys.begin(), best.keys.end());
  }
  if (joints.empty()) {
    out.notes->push_back("joint_cyclic_error: no joint's cyclic terms improve the held-out score");
    return;
  }
  Evaluated e;
  e.design = current;
  e.cv = current_cv;
  e.fit = MakeFit("joint_cyclic_error", current_k, e.cv);
  ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, keys, &e.fit);
  std::string list;
  for (int j : joints) {
    list += (list.empty() ? "q" : ", q") + std::to_string(j + 1);
    const auto value = [&](const std::string& k) {
      const auto it = e.fit.parameters.find(k);
      return it == e.fit.parameters.end() ? 0.0 : it->second;
    };
    const double a = value("joint" + std::to_string(j + 1) + "_sin_q_deg");
    const double b = value("joint" + std::to_string(j + 1) + "_cos_q_deg");
    e.fit.parameters["joint" + std::to_string(j + 1) + "_amplitude_1q_deg"] = std::hypot(a, b);
  }
  e.note = "joint_cyclic_error: sin/cos of q and 2q on " + list;
  out.evaluated->push_back(std::move(e));
}

}  // namespace

const RobotCauseCode kJointCyclicError{1, "", false, FitJointCyclicError, nullptr, nullptr};

}  // namespace ramtk::diagnose::robot_detail
