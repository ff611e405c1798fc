// Fringe causes registered at run time (extra_cause.h): their registry and their fit.
#include "ramtk/diagnose/fringe/extra_cause.h"

#include "fringe_fit_kit.h"
#include "ramtk/core/error.h"

namespace ramtk::diagnose {
namespace {

std::vector<FringeLinearCause>& Registry() {
  static std::vector<FringeLinearCause> causes;
  return causes;
}

}  // namespace

std::string FringeLinearCause::Validate() const {
  if (info.name == nullptr || *info.name == '\0') return "info.name: must not be empty";
  if (info.kind != DataKind::kFringe) return "info.kind: must be fringe";
  if (info.description == nullptr || info.parameters == nullptr || info.plausible == nullptr)
    return "info: description, parameters and plausible must not be null";
  if (keys.empty()) return "keys: at least one coefficient";
  if (!basis) return "basis: must be set";
  return "";
}

void RegisterFringeCause(const FringeLinearCause& cause) {
  ThrowIfInvalid(cause.Validate(), "FringeLinearCause");
  if (IsKnownCause(cause.info.name))
    throw InputError({"", 0, "FringeLinearCause"}, std::string("cause '") + cause.info.name + "' is already registered");
  RegisterEffect(cause.info);
  Registry().push_back(cause);
}

const std::vector<FringeLinearCause>& RegisteredFringeCauses() { return Registry(); }

namespace fringe {

FringeSequenceView SequenceViewOf(const FringeFit& fit) {
  FringeSequenceView v;
  v.frames = fit.frames;
  v.phase_frame = fit.phase_frame;
  v.gray_frame = fit.gray_frame;
  for (int k = 0; k < fit.steps; ++k) v.step_shift_rad.push_back(StepShift(k, fit.steps));
  return v;
}

CandidateFit FitRegistered(const CandidateContext& ctx, const FringeLinearCause& cause) {
  const FringeSequenceView seq = SequenceViewOf(*ctx.fit);
  const auto basis = [&](const FringeFit&, const PixelFit& p, Eigen::Ref<Eigen::MatrixXd> mat) {
    FringePixelView view;
    view.x = p.x, view.y = p.y, view.a = p.a, view.b = p.b, view.phi = p.phi, view.u = p.u;
    cause.basis(seq, view, mat);
  };
  return FitLinear(
      ctx, cause.info.name, static_cast<int>(cause.keys.size()), basis, [&](int i) { return cause.keys[i]; },
      [](int, double v) { return v; });
}

}  // namespace fringe
}  // namespace ramtk::diagnose
