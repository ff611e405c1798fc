// Joint compliance: Δθ_j = c_j·τ_j(q), τ the gravity torque about joint j (the robot file's link
// masses, else a generic load, robot_linear.h).
#include "../robot_fit_kit.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::diagnose::robot_detail {
namespace {

using kinematics::ParamKind;

void FitJointCompliance(const Context& ctx, CauseOutput out) {
  const std::vector<Row>& rows = ctx.rows->rows;
  std::vector<Mat3X> cols;
  const bool masses = ctx.input->chain.HasMasses();
  if (!masses) {
    out.notes->push_back(
        "joint_compliance: the robot file has no link masses; a generic load (0.1 kg/mm along the links, 20 kg at "
        "the ball) shapes the torques, so the fitted compliance values are relative, not physical");
  }
  for (const Row& r : rows) {
    Eigen::Matrix<double, 6, 1> tau;
    if (masses) {
      // kg·mm of the file's masses times g, in kN·m.
      tau = kinematics::GravityTorques(ctx.input->chain, r.q) * 9.81e-6;
    } else {
      tau = GravityTorques(ctx.input->model, r.q, ctx.rows->setup.ball_in_flange) / 1000.0;  // kN·m
    }
    Mat3X m(3, 5);
    for (int j = 1; j < 6; ++j) m.col(j - 1) = r.j_param.col(kinematics::ParamIndex(ParamKind::kTheta, j)) * tau[j];
    cols.push_back(m);
  }
  // Joints whose load hardly varies (joint 6 about the flange axis) would only add noise.
  Eigen::VectorXd size = Eigen::VectorXd::Zero(5);
  for (const Mat3X& m : cols) size += m.colwise().squaredNorm().transpose();
  std::vector<int> loaded;
  for (int j = 0; j < 5; ++j)
    if (size[j] > 0.01 * size.maxCoeff()) loaded.push_back(j);
  std::vector<int> keep;
  for (int k : IndependentColumns(PooledBlocks(ctx.base), SelectColumns(cols, loaded))) keep.push_back(loaded[k]);
  if (keep.empty()) return;
  std::vector<std::string> names;
  std::vector<std::pair<std::string, double>> keys;
  for (int k : keep) {
    names.push_back("c" + std::to_string(k + 2));
    keys.emplace_back("joint" + std::to_string(k + 2) + "_compliance_urad_per_kNm", 1e6);
  }
  FitColumns(ctx, out, "joint_compliance", cols, keep, names, keys);
}

// Joints 2 and 3 yield to the generic gravity load.
void PlantJointCompliance(PlantContext* p) {
  const double c2 = p->random.Uniform(30, 150), c3 = p->random.Uniform(30, 150);  // µrad per kN·m
  p->draw->truth["joint2_compliance_urad_per_kNm"] = c2;
  p->draw->truth["joint3_compliance_urad_per_kNm"] = c3;
  p->draw->description = "gravity compliance of joints 2, 3: " + Fmt(c2) + ", " + Fmt(c3) + " µrad/(kN·m)";
  const kinematics::RobotModel& model = *p->model;
  const Isometry3& sensor_from_base = p->result->setup.sensor_from_base;
  const Eigen::Vector3d& ball = p->result->setup.ball_in_flange;
  for (auto& m : p->result->ball.rows) {
    const Eigen::Matrix<double, 6, 1> tau = GravityTorques(model, m.q_controller, ball) / 1000.0;
    kinematics::RobotModel bent = model;
    bent.links[1].theta0 += c2 * 1e-6 * tau[1];
    bent.links[2].theta0 += c3 * 1e-6 * tau[2];
    m.position_mm += sensor_from_base.linear() * (kinematics::BaseFromFlange(bent, m.q_controller) * ball -
                                                  kinematics::BaseFromFlange(model, m.q_controller) * ball);
  }
}

}  // namespace

const RobotCauseCode kJointCompliance{1, "", false, FitJointCompliance, nullptr, PlantJointCompliance};

}  // namespace ramtk::diagnose::robot_detail
