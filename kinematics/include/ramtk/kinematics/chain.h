#pragma once
// A serial robot with any number of revolute joints (6 or 7 in practice): the same link model as
// RobotModel (thesis eq. 2-18, Trans(Z,d)·Rot(Z,θ)·Trans(X,a)·Rot(X,α)·Rot(Y,β)), the same file
// format (docs/formats.md), sized at run time. The robot calibration works on it; the 6-joint
// commands convert it to a RobotModel.
//
// Parameters are ordered by joint, then kind: [d1 θ1 a1 α1 β1, d2 θ2 ..., dN .. βN] (5N values;
// lengths mm, angles rad). Note that RobotModel's ParamVector is ordered by kind first.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/robot_model.h"

namespace ramtk::kinematics {

inline constexpr int kParamsPerLink = 5;
inline constexpr int kMaxChainJoints = 12;

// Mass of one link (or of the payload) for the gravity-load model.
struct LinkMass {
  double mass_kg = 0.0;
  Vec3 com_mm = Vec3::Zero();  // centre of mass in the link's own frame (after its transform)
};

struct RobotChain {
  std::string name;
  std::string source;
  Convention convention = Convention::kMdh;
  std::vector<LinkParams> links;     // N, base to flange
  std::vector<JointMapping> mapping;  // N
  std::vector<bool> structural_zero;  // 5N, in the chain's parameter order
  // Gravity-load data (optional: empty when the file has none). masses[i] belongs to link i+1.
  std::vector<LinkMass> masses;
  LinkMass payload;                    // in the flange frame
  Vec3 gravity_in_base = Vec3(0, 0, -1);  // direction of gravity in the base frame (unit)

  int NumJoints() const { return static_cast<int>(links.size()); }
  int NumParams() const { return kParamsPerLink * NumJoints(); }
  bool HasMasses() const { return !masses.empty(); }

  Eigen::VectorXd Params() const;
  void SetParams(const Eigen::VectorXd& params);
  // θ_in (rad) of every joint from controller joints (rad).
  Eigen::VectorXd ModelFromController(const Eigen::VectorXd& q_controller) const;
};

// Index of parameter `kind` of joint `joint` (0-based) in the chain's order.
constexpr int ChainParamIndex(ParamKind kind, int joint) { return kParamsPerLink * joint + static_cast<int>(kind); }
// "d1", "theta3", "beta2", ... for a chain index.
std::string ChainParamName(int index);
// -1 for an unknown name or one beyond num_joints.
int ChainParamIndexFromName(const std::string& name, int num_joints);
bool IsChainAngleParam(int index);

// base_from_flange for controller joints (rad).
Isometry3 ChainBaseFromFlange(const RobotChain& chain, const Eigen::VectorXd& q_controller);
// Every frame: base_from_link[i], i = 0..N (base_from_link[0] = identity).
std::vector<Isometry3> ChainLinkFrames(const RobotChain& chain, const Eigen::VectorXd& q_controller);

// Conversions. ToRobotModel throws InputError naming `field` when the chain has not 6 joints.
RobotChain ChainFromRobotModel(const RobotModel& model);
RobotModel RobotModelFromChain(const RobotChain& chain, const std::string& path, const std::string& field = "joints");

// Sum of |a| and |d| over the links (mm): the scale that turns angles into lengths.
double ChainReachMm(const RobotChain& chain);

// Gravity torque about each joint's model axis (+Z of the frame before its link, the direction of
// a positive θ_j) in kg·mm (mass times lever; multiply by g for N·mm) at controller joints q, from
// the chain's masses and payload. Zero without masses.
Eigen::VectorXd GravityTorques(const RobotChain& chain, const Eigen::VectorXd& q_controller);

}  // namespace ramtk::kinematics
