// Independent robot / ball-measurement generator; see robot_gen.h and README.md for the physics.
#include "robot_gen.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace indep {
namespace {

constexpr double kDeg = M_PI / 180.0;

// KR 150 R3100-class joint limits (controller degrees), from the public data sheet of the class.
constexpr double kLimitLo[6] = {-185, -140, -120, -350, -125, -350};
constexpr double kLimitHi[6] = {185, -5, 168, 350, 125, 350};

struct Setup {
  Eigen::Isometry3d sensor_from_base;
  Eigen::Vector3d ball_in_flange;
  Eigen::Vector3d sensor_in_base;
  Eigen::Vector3d work_point_in_base;
};

Setup MakeSetup(Rng& rng) {
  Setup s;
  s.ball_in_flange = Eigen::Vector3d(rng.Uniform(30, 50), rng.Uniform(-15, 5), rng.Uniform(280, 320));
  s.work_point_in_base =
      Eigen::Vector3d(2000 + rng.Uniform(-100, 100), 300 + rng.Uniform(-100, 100), 1000 + rng.Uniform(-100, 100));
  const Eigen::Vector3d to_sensor =
      Eigen::Vector3d(0.6 + rng.Uniform(-0.1, 0.1), -0.3 + rng.Uniform(-0.1, 0.1), 0.75).normalized();
  s.sensor_in_base = s.work_point_in_base + 700.0 * to_sensor;  // 700 mm working distance
  const Eigen::Vector3d z = -to_sensor;                          // the sensor looks at the work point
  const Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d base_from_sensor = Eigen::Isometry3d::Identity();
  base_from_sensor.linear() << x, y, z;
  base_from_sensor.translation() = s.sensor_in_base;
  s.sensor_from_base = base_from_sensor.inverse();
  return s;
}

bool WithinLimits(const Joints& q) {
  for (int i = 0; i < 6; ++i) {
    if (q(i) < kLimitLo[i] * kDeg || q(i) > kLimitHi[i] * kDeg) return false;
  }
  return std::fabs(q(4)) > 15 * kDeg;  // keep away from the wrist singularity
}

double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

// Taught poses: ball centres spread over the sensor's 400×300×150 mm field, the ball stick
// within 45° of the line of sight (the flange never hides the ball), random spin about the stick.
std::vector<Joints> MakePoses(const Robot& robot, const Setup& setup, int count, Rng& rng) {
  std::vector<Joints> poses;
  const Eigen::Isometry3d base_from_sensor = setup.sensor_from_base.inverse();
  const Eigen::Vector3d to_sensor = -base_from_sensor.linear().col(2);
  int attempts = 0;
  while (static_cast<int>(poses.size()) < count) {
    if (++attempts > 200 * count) throw std::runtime_error("robot generator: cannot reach the sensor field");
    const Eigen::Vector3d ball_in_sensor(rng.Uniform(-200, 200), rng.Uniform(-150, 150), 700 + rng.Uniform(-75, 75));
    const Eigen::Vector3d ball = base_from_sensor * ball_in_sensor;
    // Stick direction: uniform over the 45° cone about the line of sight.
    const double cone = std::acos(1 - rng.Uniform() * (1 - std::cos(45 * kDeg)));
    const double azimuth = rng.Uniform(-M_PI, M_PI);
    const Eigen::Vector3d perp = to_sensor.unitOrthogonal();
    const Eigen::Vector3d stick =
        (Eigen::AngleAxisd(azimuth, to_sensor) * Eigen::AngleAxisd(cone, perp) * to_sensor).normalized();
    const Eigen::Matrix3d align =
        Eigen::Quaterniond::FromTwoVectors(setup.ball_in_flange.normalized(), stick).toRotationMatrix();
    Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
    target.linear() = Eigen::AngleAxisd(rng.Uniform(-M_PI, M_PI), stick) * align;
    target.translation() = ball - target.linear() * setup.ball_in_flange;
    const double q1 = -std::atan2(target.translation().y(), target.translation().x());
    bool found = false;
    for (double q4 : {0.0, -90.0, 90.0, 180.0}) {
      for (double q5 : {45.0, -45.0}) {
        Joints start;
        start << q1, -60 * kDeg, 100 * kDeg, q4 * kDeg, q5 * kDeg, 0;
        Joints q;
        if (!SolvePose(robot, target, start, &q)) continue;
        q(0) = Wrap(q(0));
        q(3) = Wrap(q(3));
        q(5) = Wrap(q(5));
        if (!WithinLimits(q)) continue;
        poses.push_back(q);
        found = true;
        break;
      }
      if (found) break;
    }
  }
  return poses;
}

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

nlohmann::json Rows(const Eigen::Isometry3d& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    rows.push_back({t.linear()(r, 0), t.linear()(r, 1), t.linear()(r, 2), t.translation()(r)});
  }
  return rows;
}

}  // namespace

ComplianceModel Kr150Compliance(double scale) {
  // Lumped masses (README.md): total arm ≈ 1070 kg; the rotating column (link 1) carries no
  // torque about a joint that gravity loads, so only its share of the total is listed for reference.
  // Link frames of the KR150 model at θ = 0: frame 2 sits at the elbow end of the upper arm
  // (x2 along the arm, the arm spans x2 ∈ [−1350, 0]), frame 4 at the wrist centre, etc.
  ComplianceModel m;
  m.masses = {
      {1, 400.0, Eigen::Vector3d(-150, 0, 0)},     // rotating column + A1/A2/A3 motors
      {2, 180.0, Eigen::Vector3d(-675, 0, 0)},     // upper arm, mid-length
      {3, 150.0, Eigen::Vector3d(-41, 0, -150)},   // elbow housing with the A4–A6 motors behind axis 3
      {4, 60.0, Eigen::Vector3d(0, -700, 0)},      // forearm tube, mid-length (y4 runs along the forearm)
      {5, 25.0, Eigen::Vector3d(0, 0, 0)},         // wrist at the wrist centre
      {6, 10.0, Eigen::Vector3d(20, 0, 150)},      // flange + ball tool
  };
  const double k[6] = {5.0e6, 5.0e6, 3.0e6, 5.0e5, 5.0e5, 2.0e5};
  for (int i = 0; i < 6; ++i) m.stiffness_nm_per_rad[i] = scale > 0 ? k[i] / scale : 1e300;
  return m;
}

double GravityPotential(const Robot& robot, const ComplianceModel& model, const Joints& q_rad) {
  const auto frames = LinkFrames(robot, q_rad);
  double v = 0;
  for (const LumpedMass& mass : model.masses) {
    const Eigen::Vector3d p_m = frames[mass.link] * mass.com_in_link * 1e-3;
    v -= mass.mass_kg * model.gravity_in_base.dot(p_m);
  }
  return v;
}

Joints GravityTorque(const Robot& robot, const ComplianceModel& model, const Joints& q_rad) {
  const auto frames = LinkFrames(robot, q_rad);
  Joints tau = Joints::Zero();
  for (int i = 0; i < 6; ++i) {  // joint i+1 turns about Z of frame i through its origin
    const Eigen::Vector3d axis = frames[i].linear().col(2);
    const Eigen::Vector3d origin = frames[i].translation();
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (const LumpedMass& mass : model.masses) {
      if (mass.link < i + 1) continue;
      const Eigen::Vector3d arm_m = (frames[mass.link] * mass.com_in_link - origin) * 1e-3;
      moment += arm_m.cross(mass.mass_kg * model.gravity_in_base);
    }
    tau(i) = robot.joints[i].sign * axis.dot(moment);
  }
  return tau;
}

Joints ComplianceDeflection(const Robot& robot, const ComplianceModel& model, const Joints& q_rad) {
  Joints dq = Joints::Zero();
  for (int iter = 0; iter < 20; ++iter) {
    const Joints tau = GravityTorque(robot, model, q_rad + dq);
    Joints next;
    for (int i = 0; i < 6; ++i) next(i) = tau(i) / model.stiffness_nm_per_rad[i];
    const double change = (next - dq).cwiseAbs().maxCoeff();
    dq = next;
    if (change < 1e-15) break;
  }
  return dq;
}

void GenerateRobot(const GenOptions& o) {
  const std::string& effect = o.effect;
  const bool known = effect == "none" || effect == "joint_compliance" || effect == "joint_cyclic_error" ||
                     effect == "link_length_error" || effect == "thermal_length_drift" || effect == "joint_offset";
  if (!known) throw std::runtime_error("robot: unknown effect '" + effect + "'");
  const Robot nominal = LoadRobot(o.robot_path);
  Rng rng(0x9e3779b97f4a7c15ULL ^ (static_cast<std::uint64_t>(o.seed) * 1000003ULL + 17));

  const int num_poses = 20, num_cycles = 30;
  const double cycle_s = 360.0, pose_s = 6.0;  // 30 cycles × 6 min = 3 h
  const Setup setup = MakeSetup(rng);
  const std::vector<Joints> poses = MakePoses(nominal, setup, num_poses, rng);

  // Noise (README.md): sensor σ per axis in its own frame (depth worse than lateral), servo
  // (repeatability) σ per joint.
  const Eigen::Vector3d sensor_sigma_mm(0.010, 0.010, 0.020);
  const double servo_sigma_deg[6] = {0.0004, 0.0004, 0.0004, 0.0010, 0.0010, 0.0020};

  Truth truth;
  truth.kind = "robot";
  truth.effect = effect;
  truth.expected = effect;
  truth.accepted = {effect};
  nlohmann::json& par = truth.parameters;
  par["sensor_sigma_mm"] = {sensor_sigma_mm.x(), sensor_sigma_mm.y(), sensor_sigma_mm.z()};
  par["servo_sigma_deg"] = std::vector<double>(servo_sigma_deg, servo_sigma_deg + 6);
  par["num_cycles"] = num_cycles;
  par["num_poses"] = num_poses;

  // Effect parameters.
  Robot actual = nominal;
  double compliance_scale = 0;
  int cyclic_joint = -1;
  double cyclic_amp_rad = 0, cyclic_phase = 0;
  // thermal: lengths that grow, with their temperature column and steady-state rise
  struct Growth { std::string name; double* length; double nominal; int temp_joint; };
  std::vector<Growth> growth;
  double alpha_per_k = 11.5e-6, tau_s = 45 * 60.0;
  std::array<double, 6> rise_k{};                     // steady-state temperature rise per joint
  std::array<double, 6> ambient_k{};
  for (int j = 0; j < 6; ++j) ambient_k[j] = 22.0 + rng.Uniform(-0.5, 0.5);
  const bool thermal = effect == "thermal_length_drift";
  if (effect == "joint_compliance") {
    compliance_scale = std::isnan(o.magnitude) ? 1.0 : o.magnitude;
    par["compliance_scale"] = compliance_scale;
    const ComplianceModel model = Kr150Compliance(compliance_scale);
    par["stiffness_nm_per_rad"] = model.stiffness_nm_per_rad;
    nlohmann::json masses = nlohmann::json::array();
    for (const auto& m : model.masses) {
      masses.push_back({{"link", m.link}, {"mass_kg", m.mass_kg}, {"com_in_link_mm", {m.com_in_link.x(), m.com_in_link.y(), m.com_in_link.z()}}});
    }
    par["lumped_masses"] = masses;
  } else if (effect == "joint_cyclic_error") {
    const int choices[3] = {3, 4, 5};  // joints 4, 5, 6 turn over wide ranges in the pose set
    cyclic_joint = choices[static_cast<int>(rng.Uniform() * 3) % 3];
    cyclic_amp_rad = (std::isnan(o.magnitude) ? 0.02 : o.magnitude) * kDeg;
    cyclic_phase = rng.Uniform(-M_PI, M_PI);
    par["joint"] = cyclic_joint + 1;
    par["amplitude_deg"] = cyclic_amp_rad / kDeg;
    par["phase_deg"] = cyclic_phase / kDeg;
    par["law"] = "q_actual = q + amplitude * sin(q + phase) on that joint (once per joint turn)";
    truth.explaining_variable = "q" + std::to_string(cyclic_joint + 1);
    truth.accepted.push_back("unexplained:" + truth.explaining_variable);
  } else if (effect == "link_length_error") {
    const double mag = std::isnan(o.magnitude) ? 0.5 : o.magnitude;
    const int pick = static_cast<int>(rng.Uniform() * 3) % 3;
    const double sign = rng.Uniform() < 0.5 ? -1 : 1;
    const char* names[3] = {"a2", "a3", "d4"};
    double* lengths[3] = {&actual.joints[1].a_mm, &actual.joints[2].a_mm, &actual.joints[3].d_mm};
    *lengths[pick] += sign * mag;
    par["parameter"] = names[pick];
    par["error_mm"] = sign * mag;
  } else if (effect == "joint_offset") {
    const double mag = std::isnan(o.magnitude) ? 0.02 : o.magnitude;
    const int joint = 1 + static_cast<int>(rng.Uniform() * 4) % 4;  // joints 2..5
    const double sign = rng.Uniform() < 0.5 ? -1 : 1;
    actual.joints[joint].theta0_rad += sign * mag * kDeg;
    par["joint"] = joint + 1;
    par["offset_deg"] = sign * mag;
  } else if (thermal) {
    const double scale = std::isnan(o.magnitude) ? 1.0 : o.magnitude;
    rise_k = {6.0 * scale, 10.0 * scale, 9.0 * scale, 12.0 * scale, 8.0 * scale, 6.0 * scale};
    growth = {{"d1", &actual.joints[0].d_mm, nominal.joints[0].d_mm, 0},
              {"a1", &actual.joints[0].a_mm, nominal.joints[0].a_mm, 0},
              {"a2", &actual.joints[1].a_mm, nominal.joints[1].a_mm, 1},
              {"d4", &actual.joints[3].d_mm, nominal.joints[3].d_mm, 3}};
    par["expansion_per_k"] = alpha_per_k;
    par["time_constant_s"] = tau_s;
    par["temperature_rise_k"] = rise_k;
    nlohmann::json g = nlohmann::json::array();
    for (const auto& gr : growth) {
      g.push_back({{"parameter", gr.name}, {"temperature_column", "temp_j" + std::to_string(gr.temp_joint + 1)},
                   {"final_growth_mm", alpha_per_k * gr.nominal * rise_k[gr.temp_joint]}});
    }
    par["growing_lengths"] = g;
    par["law"] = "T_j(t) = ambient + rise_j (1 - exp(-t / tau)); L(t) = L0 (1 + alpha (T_j(t) - T_j(0)))";
    truth.accepted.push_back("temperature_driven_drift");
  } else {
    // none: the robot at thermal steady state, noise and repeatability only
  }
  if (!thermal) {  // steady state: a warm robot at constant temperature
    for (int j = 0; j < 6; ++j) ambient_k[j] += 8.0 + 2.0 * j;
  }
  const ComplianceModel compliance = Kr150Compliance(compliance_scale);

  std::ostringstream csv;
  csv << "cycle,time_s,pose,q1,q2,q3,q4,q5,q6,x,y,z,temp_j1,temp_j2,temp_j3,temp_j4,temp_j5,temp_j6\n";
  double sum_sq_effect = 0;
  int count = 0;
  for (int c = 0; c < num_cycles; ++c) {
    for (int p = 0; p < num_poses; ++p) {
      const double t = c * cycle_s + p * pose_s;
      std::array<double, 6> temp{};
      for (int j = 0; j < 6; ++j) {
        const double heat = thermal ? rise_k[j] * (1 - std::exp(-t / tau_s)) : 0.0;
        temp[j] = ambient_k[j] + heat;
      }
      for (const auto& gr : growth) {
        *gr.length = gr.nominal * (1 + alpha_per_k * (temp[gr.temp_joint] - ambient_k[gr.temp_joint]));
      }
      const Joints& q = poses[p];
      Joints q_act = q;
      if (compliance_scale > 0) q_act += ComplianceDeflection(actual, compliance, q);
      if (cyclic_joint >= 0) q_act(cyclic_joint) += cyclic_amp_rad * std::sin(q(cyclic_joint) + cyclic_phase);
      const Eigen::Vector3d clean = setup.sensor_from_base * (BaseFromFlange(actual, q_act) * setup.ball_in_flange);
      const Eigen::Vector3d nominal_ball =
          setup.sensor_from_base * (BaseFromFlange(nominal, q) * setup.ball_in_flange);
      sum_sq_effect += (clean - nominal_ball).squaredNorm();
      ++count;
      Joints q_servo = q_act;
      for (int j = 0; j < 6; ++j) q_servo(j) += servo_sigma_deg[j] * kDeg * rng.Normal();
      Eigen::Vector3d ball = setup.sensor_from_base * (BaseFromFlange(actual, q_servo) * setup.ball_in_flange);
      for (int k = 0; k < 3; ++k) ball(k) += sensor_sigma_mm(k) * rng.Normal();
      csv << c << ',' << Fixed(t, 1) << ',' << p + 1;
      for (int j = 0; j < 6; ++j) csv << ',' << Fixed(q(j) / kDeg, 6);
      for (int k = 0; k < 3; ++k) csv << ',' << Fixed(ball(k), 5);
      for (int j = 0; j < 6; ++j) csv << ',' << Fixed(temp[j] + 0.05 * rng.Normal(), 3);
      csv << '\n';
    }
  }
  par["effect_rms_mm"] = std::sqrt(sum_sq_effect / count);  // before any set-up fit absorbs part of it

  std::filesystem::create_directories(o.out_dir);
  WriteFileAtomic(o.out_dir + "/ball.csv", csv.str());
  nlohmann::json setup_json;
  setup_json["sensor_from_base"] = Rows(setup.sensor_from_base);
  setup_json["ball_in_flange_mm"] = {setup.ball_in_flange.x(), setup.ball_in_flange.y(), setup.ball_in_flange.z()};
  WriteFileAtomic(o.out_dir + "/setup.json", setup_json.dump(2) + "\n");
  WriteTruth(o.out_dir, truth, o);
}

}  // namespace indep
