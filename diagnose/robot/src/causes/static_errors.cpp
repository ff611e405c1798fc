// Static errors of the kinematic parameters: joint zeros, link lengths, axis twists, the whole
// static calibration; backlash (not testable without the direction of approach).
#include <cmath>

#include "../robot_fit_kit.h"
#include "ramtk/core/units.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::diagnose::robot_detail {
namespace {

using kinematics::kNumParams;
using kinematics::ParamIndex;
using kinematics::ParamKind;

void FitJointOffset(const Context& ctx, CauseOutput out) {
  FitStaticParams(ctx, out, "joint_offset", ThetaParams(ctx.input->model), "_offset");
}

void FitLinkLengthError(const Context& ctx, CauseOutput out) {
  FitStaticParams(ctx, out, "link_length_error", thermal::TraditionalParams(ctx.input->model), "_error");
}

// Static twists of the joint axes (α, and β where consecutive axes are near-parallel, thesis
// §2.2.3), or the whole static kinematic calibration as one candidate (every link parameter the
// set-up does not absorb). β is offered on near-parallel axes also when the file is DH.
std::vector<int> OfferedParams(const kinematics::RobotModel& model, bool twists_only) {
  std::vector<int> out;
  for (int p = 0; p < kNumParams; ++p) {
    const int j = kinematics::ParamJointOf(p);
    const bool parallel = std::abs(std::sin(model.links[j].alpha)) < std::sin(DegToRad(10.0));
    const ParamKind kind = kinematics::ParamKindOf(p);
    const bool offered = !model.structural_zero[p] || (kind == ParamKind::kBeta && parallel);
    if (offered && (!twists_only || kind == ParamKind::kAlpha || kind == ParamKind::kBeta)) out.push_back(p);
  }
  return out;
}

// Weakly observable directions would carry model error into wild values: a column must keep
// 0.1% of its norm outside the others' span (as the robot calibration's weak tolerance).
void FitAxisMisalignment(const Context& ctx, CauseOutput out) {
  FitStaticParams(ctx, out, "axis_misalignment", OfferedParams(ctx.input->model, true), "_twist", 1e-3);
}

void FitGeometric(const Context& ctx, CauseOutput out) {
  FitStaticParams(ctx, out, "geometric", OfferedParams(ctx.input->model, false), "_error", 1e-3);
}

void FitBacklash(const Context&, CauseOutput out) {
  out.notes->push_back("backlash: not testable (the data carry no direction of approach)");
}

// θ2..θ5: θ1 turns like the sensor frame, θ6 like the ball offset.
void PlantJointOffset(PlantContext* p) {
  const int j = 1 + p->random.Pick(4);
  const double delta = p->random.Sign() * p->random.Uniform(0.004, 0.03);
  p->truth->links[j].theta0 += DegToRad(delta);
  p->draw->truth["theta" + std::to_string(j + 1) + "_offset_deg"] = delta;
  p->draw->description = "theta" + std::to_string(j + 1) + " zero off by " + Fmt(delta) + " deg";
}

void PlantLinkLengthError(PlantContext* p) {
  static const int params[4] = {ParamIndex(ParamKind::kA, 0), ParamIndex(ParamKind::kA, 1),
                                ParamIndex(ParamKind::kA, 2), ParamIndex(ParamKind::kD, 3)};
  const int k = params[p->random.Pick(4)];
  const double delta = p->random.Sign() * p->random.Uniform(0.1, 1.0);
  kinematics::ParamVector x = p->truth->Params();
  x[k] += delta;
  p->truth->SetParams(x);
  p->draw->truth[kinematics::ParamName(k) + "_error_mm"] = delta;
  p->draw->description = kinematics::ParamName(k) + " off by " + Fmt(delta) + " mm";
}

}  // namespace

const RobotCauseCode kJointOffset{1, "", false, FitJointOffset, PlantJointOffset, nullptr};
const RobotCauseCode kLinkLengthError{1, "", false, FitLinkLengthError, PlantLinkLengthError, nullptr};
const RobotCauseCode kAxisMisalignment{1, "", false, FitAxisMisalignment, nullptr, nullptr};
const RobotCauseCode kGeometric{1, "", false, FitGeometric, nullptr, nullptr};
const RobotCauseCode kBacklash{1, "", false, FitBacklash, nullptr, nullptr};

}  // namespace ramtk::diagnose::robot_detail
