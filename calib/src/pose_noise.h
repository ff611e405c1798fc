#pragma once
// Simulated pose noise shared by the hand-eye simulators (not installed): the pose turned by a
// rotation vector of N(0, σ_rot²) per axis (applied on the left, in the target frame) and moved by
// N(0, σ_t²) per axis. The draws come in the order rotation x, y, z, then translation x, y, z.
#include <Eigen/Geometry>
#include <random>

#include "ramtk/core/error.h"
#include "ramtk/core/rotation.h"
#include "ramtk/core/units.h"

namespace ramtk::calib::internal {

// InputError unless both noise levels are usable σ (core/error.h CheckNoise): the hand-eye
// simulators' one check.
inline void RequirePoseNoise(double sigma_deg, double sigma_mm) {
  ThrowIfInvalid(CheckNoise("sigma_deg", sigma_deg, kMaxNoiseDeg, "deg"), "pose noise");
  ThrowIfInvalid(CheckNoise("sigma_mm", sigma_mm, kMaxNoiseMm, "mm"), "pose noise");
}

inline Isometry3 PerturbPose(const Isometry3& pose, double sigma_deg, double sigma_mm, std::mt19937& rng,
                             std::normal_distribution<double>& unit_normal) {
  Isometry3 noisy = pose;
  const Vec3 w(unit_normal(rng), unit_normal(rng), unit_normal(rng));
  if (w.norm() > 0.0)
    noisy.linear() =
        Eigen::AngleAxisd(DegToRad(sigma_deg) * w.norm(), w.normalized()).toRotationMatrix() * pose.linear();
  noisy.translation() += sigma_mm * Vec3(unit_normal(rng), unit_normal(rng), unit_normal(rng));
  return noisy;
}

}  // namespace ramtk::calib::internal
