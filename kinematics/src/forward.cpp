#include "ramtk/kinematics/forward.h"

#include <cmath>

namespace ramtk::kinematics {

Isometry3 LinkTransform(const LinkParams& link, double theta_in) {
  const double theta = link.theta0 + theta_in;
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(link.alpha), sa = std::sin(link.alpha);
  // β is a structural zero on most joints: skip its trigonometry then.
  const double cb = link.beta == 0.0 ? 1.0 : std::cos(link.beta);
  const double sb = link.beta == 0.0 ? 0.0 : std::sin(link.beta);
  // Rot(Z,θ)·Rot(X,α)·Rot(Y,β) expanded (eq. 2-18; the thesis's printed (2,2) entry is a typo
  // for cα·cθ).
  Mat3 r;
  r << ct * cb - sa * st * sb, -st * ca, ct * sb + sa * st * cb,
       st * cb + sa * ct * sb, ct * ca, st * sb - ct * sa * cb,
       -ca * sb, sa, ca * cb;
  Isometry3 t = Isometry3::Identity();
  t.linear() = r;
  t.translation() = Vec3(link.a * ct, link.a * st, link.d);
  return t;
}

ChainFrames ComputeChainFrames(const RobotModel& model, const JointVector& q_controller) {
  const JointVector theta_in = model.ModelFromController(q_controller);
  ChainFrames frames;
  frames.base_from_link[0] = Isometry3::Identity();
  frames.link_from_previous[0] = Isometry3::Identity();
  for (int i = 1; i <= kNumJoints; ++i) {
    frames.link_from_previous[i] = LinkTransform(model.links[i - 1], theta_in[i - 1]);
    frames.base_from_link[i] = frames.base_from_link[i - 1] * frames.link_from_previous[i];
  }
  return frames;
}

Isometry3 BaseFromFlange(const RobotModel& model, const JointVector& q_controller) {
  const JointVector theta_in = model.ModelFromController(q_controller);
  Isometry3 t = Isometry3::Identity();
  for (int i = 0; i < kNumJoints; ++i) t = t * LinkTransform(model.links[i], theta_in[i]);
  return t;
}

}  // namespace ramtk::kinematics
