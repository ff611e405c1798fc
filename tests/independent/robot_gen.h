// Independent robot / ball-measurement generator (issue 15): ball centres measured by a fixed
// sensor while the robot repeats taught poses, with one physical effect switched on.
#pragma once

#include "common.h"
#include "mdh.h"

#include <array>
#include <vector>

namespace indep {

// Lumped-mass gravity model of a serial arm: body k (1..6) is rigidly attached to link frame k.
struct LumpedMass {
  int link = 0;                 // 1..6: the link frame the mass moves with
  double mass_kg = 0;
  Eigen::Vector3d com_in_link;  // centre of mass in that link frame, mm
};

struct ComplianceModel {
  std::vector<LumpedMass> masses;
  std::array<double, 6> stiffness_nm_per_rad{};  // joint stiffness k_i, N·m/rad
  Eigen::Vector3d gravity_in_base{0, 0, -9.80665};  // m/s²
};

// The representative KR150-class model of README.md (masses from the public total weight,
// stiffness of the order published for 150–240 kg robots); `scale` multiplies every compliance 1/k.
ComplianceModel Kr150Compliance(double scale);

// Potential energy of the lumped masses, J (joint angles in model space θ_i = θ0 + sign·q + offset,
// i.e. what LinkFrames uses).
double GravityPotential(const Robot& robot, const ComplianceModel& model, const Joints& q_rad);

// Gravity generalised torque about each joint axis, N·m: τ_i = z_{i-1} · Σ_{k≥i} (p_k − o_{i-1}) × m_k g
// (the joint-i axis is Z_{i-1} through the origin of frame i−1). In controller-angle terms (the
// derivative with respect to q_i carries sign_i); τ = −∂V/∂q.
Joints GravityTorque(const Robot& robot, const ComplianceModel& model, const Joints& q_rad);

// Static deflection Δq (controller space, rad) at which the joint springs balance gravity:
// k_i·Δq_i = τ_i(q + Δq), solved by fixed-point iteration (converges since |∂τ/∂q| ≪ k).
Joints ComplianceDeflection(const Robot& robot, const ComplianceModel& model, const Joints& q_rad);

// Writes ball.csv, setup.json and truth.json for options.effect into options.out_dir.
void GenerateRobot(const GenOptions& options);

}  // namespace indep
