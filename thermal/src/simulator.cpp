#include "ramtk/thermal/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include "ramtk/core/csv.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/inverse.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::thermal {

using kinematics::JointVector;
using kinematics::kNumJoints;
using kinematics::kNumParams;
using kinematics::ParamIndex;
using kinematics::ParamKind;
using kinematics::ParamVector;
using kinematics::RobotModel;
using Vec6 = Eigen::Matrix<double, 6, 1>;

std::string ThermalSimOptions::Validate() const {
  if (cycles < 2) return "cycles must be >= 2 (the cold reference and at least one warm cycle)";
  if (!(cycle_period_s > 0.0)) return "cycle_period_s must be > 0";
  if (duty.empty()) return "duty needs at least one phase";
  for (const DutyPhase& p : duty) {
    if (!(p.duration_s > 0.0) || !(p.duty >= 0.0 && p.duty <= 1.0))
      return "duty phases need duration > 0, duty in [0,1]";
  }
  for (const HeatSource& h : sources) {
    if (h.joint < 0 || h.joint >= kNumJoints) return "heat source joint out of range";
    if (!(h.tau_heat_s > 0.0 && h.tau_cool_s > 0.0)) return "heat source time constants must be > 0";
  }
  if (!(structure_tau_s > 0.0)) return "structure_tau_s must be > 0";
  for (const ParamDrift& d : drifts) {
    if (d.param < 0 || d.param >= kNumParams) return "drift parameter out of range";
    if (d.per_kelvin.size() != kNumJoints) return "drift per_kelvin needs 6 values";
  }
  if (ball_poses < 1 || monitoring_points < 1) return "ball_poses and monitoring_points must be >= 1";
  for (const auto& [field, value] : {std::pair<const char*, double>{"sensor_noise_mm", sensor_noise_mm},
                                     {"tool_sensor_noise_mm", tool_sensor_noise_mm},
                                     {"repeatability_mm", repeatability_mm}}) {
    if (std::string bad = CheckNoise(field, value, kMaxNoiseMm, "mm"); !bad.empty()) return bad;
  }
  if (std::string bad = CheckNoise("temperature_noise_k", temperature_noise_k, kMaxNoiseK, "K"); !bad.empty()) {
    return bad;
  }
  if (!setup.has_tool_sensor) return "setup needs flange_from_tool_sensor for the monitoring points";
  return "";
}

ThermalSimOptions ThesisPreset(std::uint64_t seed) {
  ThermalSimOptions o;
  o.seed = seed;
  o.setup.sensor_from_base = ThesisSensorFromBase();
  o.setup.ball_in_flange = ThesisBallInFlange();
  // Re-place the sensor for the representative model's base frame: keep eq. (5-1)'s rotation and
  // put the field-of-view centre (700 mm along the sensor's Z) at (1500, -1300, 300) mm in base.
  const Mat3 r = o.setup.sensor_from_base.linear();
  const Vec3 fov_centre_in_base(1500.0, -1300.0, 300.0);
  const Vec3 sensor_origin_in_base = fov_centre_in_base - o.sensor_working_distance_mm * r.row(2).transpose();
  o.setup.sensor_from_base.translation() = -r * sensor_origin_in_base;
  // Tool sensor: 150 mm beside and 200 mm ahead of the flange, looking 20° off the flange axis.
  o.setup.flange_from_tool_sensor = Isometry3::Identity();
  o.setup.flange_from_tool_sensor.linear() = RotX(DegToRad(-20.0));
  o.setup.flange_from_tool_sensor.translation() = Vec3(0.0, 150.0, 200.0);
  o.setup.has_tool_sensor = true;
  // Heating at full duty for 110 min (warm-up, then near steady), then 70 min at 10 % (cooling).
  o.duty = {{110.0 * 60.0, 1.0}, {70.0 * 60.0, 0.1}};
  o.sources = {{0, 8.0, 2400, 3600}, {1, 12.0, 2100, 3300}, {2, 10.0, 1800, 3000},
               {3, 7.0, 1500, 2700}, {4, 6.0, 1200, 2400},  {5, 5.0, 1200, 2400}};
  auto drift = [](ParamKind kind, int joint, std::vector<double> per_k) {
    return ParamDrift{ParamIndex(kind, joint), std::move(per_k)};
  };
  // Magnitudes: lengths from steel/aluminium expansion of the links (~10 µm/K per metre); angle
  // coefficients chosen so that λ before compensation and with the traditional set land in the
  // ranges of thesis Table 5-2 (43–49 % and 74–87 %); ~0.3–0.5 mm at the ball after 2 h.
  const double urad = 1e-6;
  o.drifts = {
      drift(ParamKind::kD, 3, {0, 0, 0.008, 0.006, 0, 0}),         // d4: forearm expansion
      drift(ParamKind::kD, 5, {0, 0, 0, 0, 0.004, 0.005}),         // d6: wrist to flange
      drift(ParamKind::kA, 0, {0.004, 0.003, 0, 0, 0, 0}),         // a1: shoulder offset
      drift(ParamKind::kA, 1, {0, 0.008, 0.008, 0, 0, 0}),         // a2: upper arm
      drift(ParamKind::kA, 2, {0, 0, 0.005, 0, 0, 0}),             // a3: elbow housing
      drift(ParamKind::kAlpha, 2, {0, 0, 6 * urad, 0, 0, 0}),      // α3: elbow bearing tilt
      drift(ParamKind::kAlpha, 3, {0, 0, 0, -12.5 * urad, 0, 0}),  // α4: wrist tilt
      drift(ParamKind::kBeta, 1, {0, 5 * urad, 0, 0, 0, 0}),       // β2: upper-arm bending
  };
  return o;
}

namespace {

double DutyAt(const ThermalSimOptions& o, double t) {
  double start = 0.0;
  for (const DutyPhase& p : o.duty) {
    if (t < start + p.duration_s) return p.duty;
    start += p.duration_s;
  }
  return o.duty.back().duty;
}

// Housing and structure temperature rises on a 1 s grid.
class Timeline {
 public:
  Timeline(const ThermalSimOptions& o, double end_s) : options_(o) {
    const int n = static_cast<int>(std::ceil(end_s / kStep)) + 2;
    housing_.resize(n);
    structure_.resize(n);
    Vec6 h = Vec6::Zero(), s = Vec6::Zero();
    housing_[0] = h;
    structure_[0] = s;
    for (int i = 1; i < n; ++i) {
      const double duty = DutyAt(o, (i - 0.5) * kStep);
      const Vec6 h_old = h;
      for (const HeatSource& src : o.sources) {
        const double target = src.gain_k * duty;
        const double tau = target > h[src.joint] ? src.tau_heat_s : src.tau_cool_s;
        h[src.joint] = target + (h[src.joint] - target) * std::exp(-kStep / tau);
      }
      // The structure follows the housing's mean over the step (second-order accurate).
      const Vec6 h_mid = 0.5 * (h_old + h);
      s = h_mid + (s - h_mid) * std::exp(-kStep / o.structure_tau_s);
      housing_[i] = h;
      structure_[i] = s;
    }
  }
  void At(double t, Vec6* housing, Vec6* structure) const {
    const double x = std::clamp(t / kStep, 0.0, static_cast<double>(housing_.size() - 2));
    const int i = static_cast<int>(x);
    const double f = x - i;
    if (housing) *housing = (1 - f) * housing_[i] + f * housing_[i + 1];
    if (structure) *structure = (1 - f) * structure_[i] + f * structure_[i + 1];
  }
  ParamVector Drift(double t) const {
    Vec6 s;
    At(t, nullptr, &s);
    ParamVector x = ParamVector::Zero();
    for (const ParamDrift& d : options_.drifts) {
      for (int j = 0; j < kNumJoints; ++j) x[d.param] += d.per_kelvin[j] * s[j];
    }
    return x;
  }

 private:
  static constexpr double kStep = 1.0;
  const ThermalSimOptions& options_;
  std::vector<Vec6> housing_, structure_;
};

Mat3 RandomRotation(std::mt19937_64& rng, double max_angle) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Vec3 axis(n01(rng), n01(rng), n01(rng));
  axis.normalize();
  return Eigen::AngleAxisd(max_angle * std::cbrt(u01(rng)), axis).toRotationMatrix();
}

JointVector Deg(double a, double b, double c, double d, double e, double f) {
  JointVector q;
  q << DegToRad(a), DegToRad(b), DegToRad(c), DegToRad(d), DegToRad(e), DegToRad(f);
  return q;
}

bool WithinLimits(const JointVector& q) {
  // KR 150 R3100-class ranges (deg): A1 ±185, A2 −140..−5, A3 −120..155, A4 ±350, A5 ±125, A6 ±350;
  // |A5| > 10° keeps the wrist away from its singularity.
  const JointVector d = q * kDegPerRad;
  return std::abs(d[0]) < 185 && d[1] > -140 && d[1] < -5 && d[2] > -120 && d[2] < 155 && std::abs(d[3]) < 350 &&
         std::abs(d[4]) < 125 && std::abs(d[4]) > 10 && std::abs(d[5]) < 350;
}

std::vector<JointVector> PlaceBallPoses(const RobotModel& model, const ThermalSimOptions& o, std::mt19937_64& rng) {
  const Isometry3 base_from_sensor = o.setup.sensor_from_base.inverse();
  const Vec3 centre = base_from_sensor * Vec3(0, 0, o.sensor_working_distance_mm);
  const Vec3 sensor_origin = base_from_sensor.translation();
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  auto random_q = [&]() {
    return Deg(370 * u(rng), -72.5 + 135 * u(rng), 17.5 + 275 * u(rng), 360 * u(rng), 250 * u(rng), 360 * u(rng));
  };
  // Seeds: the random configurations whose balls are nearest the field centre (several arm and
  // wrist configurations, so the poses differ widely in all six joints, as §5.1 asks).
  std::vector<std::pair<double, JointVector>> candidates;
  for (int i = 0; i < 6000; ++i) {
    const JointVector q = random_q();
    if (!WithinLimits(q)) continue;
    candidates.emplace_back((kinematics::BaseFromFlange(model, q) * o.setup.ball_in_flange - centre).norm(), q);
  }
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const int num_seeds = std::min<int>(8, static_cast<int>(candidates.size()));
  if (num_seeds == 0) throw InputError({"", 0, "sensor_from_base"}, "no configuration reaches the sensor");
  std::vector<JointVector> poses;
  kinematics::InverseKinematicsOptions ik;
  ik.max_restarts = 1;
  for (int attempt = 0; attempt < 400 * o.ball_poses && static_cast<int>(poses.size()) < o.ball_poses; ++attempt) {
    const Vec3 in_sensor(o.sensor_field_mm.x() * u(rng), o.sensor_field_mm.y() * u(rng),
                         o.sensor_working_distance_mm + o.sensor_field_mm.z() * u(rng));
    const Vec3 ball = base_from_sensor * in_sensor;
    const JointVector& seed = candidates[attempt % num_seeds].second;
    Isometry3 target = Isometry3::Identity();
    target.linear() =
        RandomRotation(rng, DegToRad(o.ball_orientation_spread_deg)) * kinematics::BaseFromFlange(model, seed).linear();
    target.translation() = ball - target.linear() * o.setup.ball_in_flange;
    const auto sol = kinematics::SolveInverseKinematics(model, target, seed, ik);
    if (!sol.Converged() || !WithinLimits(sol.q_controller)) continue;
    // The flange must not hide the ball from the sensor.
    const Vec3 to_flange = (target.translation() - ball).normalized();
    const Vec3 to_sensor = (sensor_origin - ball).normalized();
    if (to_flange.dot(to_sensor) > std::cos(DegToRad(60.0))) continue;
    poses.push_back(sol.q_controller);
  }
  if (static_cast<int>(poses.size()) < o.ball_poses) {
    throw InputError({"", 0, "sensor_from_base"}, "could not place " + std::to_string(o.ball_poses) +
                                                      " reachable ball poses in the sensor's field of view");
  }
  return poses;
}

void PlaceMonitoringPoints(const RobotModel& model, const ThermalSimOptions& o, std::mt19937_64& rng,
                           std::vector<JointVector>* poses, std::vector<Vec3>* points) {
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int attempt = 0; attempt < 100000 && static_cast<int>(poses->size()) < o.monitoring_points; ++attempt) {
    const double a5 = (u(rng) > 0 ? 1 : -1) * (20 + 90 * (u(rng) + 0.5));
    const JointVector q = Deg(120 * u(rng), -80 + 80 * u(rng), 85 + 110 * u(rng), 240 * u(rng), a5, 300 * u(rng));
    if (!WithinLimits(q)) continue;
    const Isometry3 base_from_tool = kinematics::BaseFromFlange(model, q) * o.setup.flange_from_tool_sensor;
    const Vec3 p = base_from_tool * Vec3(60 * u(rng), 60 * u(rng), o.tool_working_distance_mm);
    // A car body in front of the robot: 0.8–3 m ahead, up to 1.8 m high.
    if (p.x() < 800 || p.x() > 3000 || p.z() < 200 || p.z() > 1800) continue;
    poses->push_back(q);
    points->push_back(p);
  }
  if (static_cast<int>(poses->size()) < o.monitoring_points) {
    throw InputError({"", 0, "monitoring_points"}, "could not place the monitoring points");
  }
}

}  // namespace

ParamVector TrueDriftAt(const ThermalSimOptions& options, double time_s, Eigen::Matrix<double, 6, 1>* housing_c) {
  const Timeline timeline(options, time_s + 2.0);
  if (housing_c != nullptr) {
    Vec6 h;
    timeline.At(time_s, &h, nullptr);
    *housing_c = h.array() + options.ambient_c;
  }
  return timeline.Drift(time_s);
}

Vec3 ToolSensorReading(const RobotModel& warm_model, const ThermalSetup& setup, const JointVector& q,
                       const Vec3& point_in_base) {
  return (kinematics::BaseFromFlange(warm_model, q) * setup.flange_from_tool_sensor).inverse() * point_in_base;
}

ThermalSimResult SimulateThermal(const RobotModel& model, const ThermalSimOptions& o) {
  ThrowIfInvalid(o.Validate(), "ThermalSimOptions");
  std::mt19937_64 rng(o.seed);
  ThermalSimResult r;
  r.setup = o.setup;
  r.ball_poses = PlaceBallPoses(model, o, rng);
  PlaceMonitoringPoints(model, o, rng, &r.monitoring_poses, &r.monitoring_points_in_base);
  for (const ParamDrift& d : o.drifts) r.drifting_params.push_back(d.param);
  std::sort(r.drifting_params.begin(), r.drifting_params.end());

  const double end = o.cycles * o.cycle_period_s;
  const Timeline timeline(o, end + 10.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto noise3 = [&](double sigma) { return Vec3(sigma * n01(rng), sigma * n01(rng), sigma * n01(rng)); };
  std::vector<std::string> temp_columns;
  for (int j = 0; j < kNumJoints; ++j) temp_columns.push_back("temp_j" + std::to_string(j + 1));
  r.ball.kind = kinematics::MeasurementKind::kBall;
  r.ball.extra_columns = temp_columns;
  r.monitoring.kind = kinematics::MeasurementKind::kMonitoring;
  r.monitoring.extra_columns = temp_columns;
  const ParamVector x0 = model.Params();
  RobotModel warm = model;
  auto row = [&](int cycle, double t, int index, const JointVector& q, const Vec3& pos) {
    kinematics::RobotMeasurement m;
    m.cycle = cycle;
    m.time_s = t;
    m.index = index;
    m.q_controller = q;
    m.position_mm = pos;
    Vec6 h;
    timeline.At(t, &h, nullptr);
    for (int j = 0; j < kNumJoints; ++j) {
      m.extra[temp_columns[j]] = o.ambient_c + h[j] + o.temperature_noise_k * n01(rng);
    }
    return m;
  };
  const int np = o.monitoring_points, nb = o.ball_poses;
  const double half = 0.5 * o.cycle_period_s;
  r.true_delta_x.resize(kNumParams, o.cycles);
  r.true_temperatures_c.resize(kNumJoints, o.cycles);
  r.true_delta_x_monitoring.resize(kNumParams, o.cycles * np);
  for (int c = 0; c < o.cycles; ++c) {
    const double t0 = c * o.cycle_period_s;
    r.cycle_time_s.push_back(t0);
    const double t_ball_mean = t0 + half + half * (nb - 1) / (2.0 * nb);
    for (int k = 0; k < np; ++k) {
      const double t = t0 + half * k / np;
      const ParamVector dx = timeline.Drift(o.drift_changes_within_cycle ? t : t_ball_mean);
      r.true_delta_x_monitoring.col(c * np + k) = dx;
      warm.SetParams(x0 + dx);
      const Vec3 shift = noise3(o.repeatability_mm);
      const Vec3 reading =
          ToolSensorReading(warm, o.setup, r.monitoring_poses[k], r.monitoring_points_in_base[k] - shift) +
          noise3(o.tool_sensor_noise_mm);
      r.monitoring.rows.push_back(row(c, t, k, r.monitoring_poses[k], reading));
    }
    r.true_delta_x.col(c) = timeline.Drift(t_ball_mean);
    r.truth_time_s.push_back(t_ball_mean);
    Vec6 h;
    timeline.At(t_ball_mean, &h, nullptr);
    r.true_temperatures_c.col(c) = h.array() + o.ambient_c;
    for (int i = 0; i < nb; ++i) {
      const double t = t0 + half + half * i / nb;
      warm.SetParams(x0 + timeline.Drift(o.drift_changes_within_cycle ? t : t_ball_mean));
      const Vec3 ball_in_base =
          kinematics::BaseFromFlange(warm, r.ball_poses[i]) * o.setup.ball_in_flange + noise3(o.repeatability_mm);
      const Vec3 reading = o.setup.sensor_from_base * ball_in_base + noise3(o.sensor_noise_mm);
      r.ball.rows.push_back(row(c, t, i, r.ball_poses[i], reading));
    }
  }
  return r;
}

std::string TruthTrajectoriesCsv(const ThermalSimResult& result) {
  std::vector<std::string> header = {"cycle", "time_s"};
  for (int j = 0; j < kNumJoints; ++j) header.push_back("temp_j" + std::to_string(j + 1));
  for (int p = 0; p < kNumParams; ++p) header.push_back(kinematics::ParamName(p));
  std::vector<std::vector<std::string>> rows;
  for (int c = 0; c < static_cast<int>(result.cycle_time_s.size()); ++c) {
    std::vector<std::string> row = {std::to_string(c), FormatFixed(result.truth_time_s[c], 3)};
    for (int j = 0; j < kNumJoints; ++j) row.push_back(FormatFixed(result.true_temperatures_c(j, c), 4));
    for (int p = 0; p < kNumParams; ++p) row.push_back(FormatSignificant(ToFileUnits(p, result.true_delta_x(p, c)), 9));
    rows.push_back(std::move(row));
  }
  return FormatCsv(header, rows,
                   "drifting parameters (truth): " + ParamListToString(result.drifting_params) +
                       "; parameter columns are drifts from the cold model in mm (d, a) and deg (theta, alpha, beta)");
}

}  // namespace ramtk::thermal
