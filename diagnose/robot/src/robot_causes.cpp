// The robot causes: the table's rows joined with their code, the causes registered at run time,
// and the hidden-effect generator's random draws they share.
#include "robot_causes.h"

#include <algorithm>

#include "ramtk/core/error.h"
#include "robot_fit_kit.h"

namespace ramtk::diagnose::robot_detail {
namespace {

std::vector<RobotCause>& Registry() {
  static std::vector<RobotCause> causes = {
#define RAMTK_ROBOT_CAUSE(name, code, parameters, plausible, help) {#name, code, nullptr},
#include "ramtk/diagnose/engine/robot_causes.def"
  };
  return causes;
}

}  // namespace

const std::vector<RobotCause>& RobotCauses() { return Registry(); }

const RobotCauseCode* FindRobotCause(const std::string& name) {
  for (const RobotCause& c : Registry())
    if (c.name == name) return &c.code;
  return nullptr;
}

double HiddenRandom::U01() { return std::uniform_real_distribution<double>(0.0, 1.0)(*rng); }
double HiddenRandom::Uniform(double a, double b) { return a + (b - a) * U01(); }
double HiddenRandom::Sign() { return U01() < 0.5 ? -1.0 : 1.0; }
int HiddenRandom::Pick(int n) { return std::min(n - 1, static_cast<int>(U01() * n)); }
Eigen::Vector3d HiddenRandom::Unit() {
  std::normal_distribution<double> n01;
  Eigen::Vector3d v(n01(*rng), n01(*rng), n01(*rng));
  return v.normalized();
}

void FitExtraCause(const Context& ctx, CauseOutput out, const RobotColumnCause& cause) {
  std::vector<Mat3X> cols;
  for (const Row& r : ctx.rows->rows) {
    RobotCauseRow view;
    view.q = r.q, view.time_h = r.time_h, view.cycle = r.cycle, view.j_param = r.j_param, view.j_setup = r.j_setup;
    cols.push_back(cause.columns(view));
  }
  const std::vector<int> keep = IndependentColumns(PooledBlocks(ctx.base), cols);
  if (keep.empty()) {
    out.notes->push_back(std::string(cause.info.name) + ": not testable (every column aliased with the current model)");
    return;
  }
  std::vector<std::string> names;
  std::vector<std::pair<std::string, double>> keys;
  for (int k : keep) names.push_back(cause.keys[k]), keys.emplace_back(cause.keys[k], cause.factors[k]);
  FitColumns(ctx, out, cause.info.name, cols, keep, names, keys);
}

}  // namespace ramtk::diagnose::robot_detail

namespace ramtk::diagnose {

std::string RobotColumnCause::Validate() const {
  if (info.name == nullptr || *info.name == '\0') return "info.name: must not be empty";
  if (info.kind != DataKind::kRobot) return "info.kind: must be robot";
  if (info.description == nullptr || info.parameters == nullptr || info.plausible == nullptr)
    return "info: description, parameters and plausible must not be null";
  if (keys.empty()) return "keys: at least one coefficient";
  if (factors.size() != keys.size()) return "factors: one per key";
  if (!columns) return "columns: must be set";
  return "";
}

void RegisterRobotCause(const RobotColumnCause& cause) {
  ThrowIfInvalid(cause.Validate(), "RobotColumnCause");
  if (robot_detail::FindRobotCause(cause.info.name) != nullptr || IsKnownCause(cause.info.name))
    throw InputError({"", 0, "RobotColumnCause"}, std::string("cause '") + cause.info.name + "' is already registered");
  RegisterEffect(cause.info);
  robot_detail::RobotCause c;
  c.name = cause.info.name;
  c.code.drift = cause.drift;
  c.extra = std::make_shared<const RobotColumnCause>(cause);
  robot_detail::Registry().push_back(std::move(c));
}

}  // namespace ramtk::diagnose
