// Checks of the independent generators against closed forms and finite differences (issue 15).
// These test the generators themselves, not ramtk's diagnose.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common.h"
#include "fringe_gen.h"
#include "laser_gen.h"
#include "mdh.h"
#include "robot_gen.h"

namespace indep {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::string kKr150 = std::string(RAMTK_DATASETS_DIR) + "/robots/kuka_kr150_r3100.yaml";

std::string RunCommand(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) output.append(buf, n);
  pclose(pipe);
  return output;
}

// The generators' own MDH chain against `ramtk fk` (a peer: the project's kinematics) on three
// shipped models, including a dh model with a negated joint 1.
TEST(IndependentMdh, MatchesRamtkFk) {
  const std::vector<std::string> models = {"kuka_kr150_r3100.yaml", "kawasaki_bx200l.yaml", "ur10.yaml"};
  const std::vector<std::array<double, 6>> poses = {{10, -60, 100, 30, 45, -20}, {-35.5, -80, 120, -150, -70, 170}};
  for (const auto& file : models) {
    const std::string path = std::string(RAMTK_DATASETS_DIR) + "/robots/" + file;
    const Robot robot = LoadRobot(path);
    for (const auto& q_deg : poses) {
      if (&q_deg != &poses.front() && file != models.front())
        continue;  // one pose on the others: each call starts a process
      std::ostringstream joints;
      for (int i = 0; i < 6; ++i) joints << (i ? "," : "") << q_deg[i];
      const std::string out = RunCommand(std::string("\"") + RAMTK_BINARY + "\" fk --robot \"" + path +
                                         "\" --joints=" + joints.str() + " --json");
      const nlohmann::json j = nlohmann::json::parse(out, nullptr, false);
      ASSERT_FALSE(j.is_discarded()) << out;
      const nlohmann::json& rot = j["base_from_flange"]["matrix"];  // 4x4 rows; the rotation is its top-left 3x3
      const nlohmann::json& pos = j["base_from_flange"]["position_mm"];
      Joints q;
      for (int i = 0; i < 6; ++i) q(i) = q_deg[i] * kDeg;
      const Eigen::Isometry3d t = BaseFromFlange(robot, q);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.linear()(r, c), rot[r][c].get<double>(), 1e-9) << file;
        EXPECT_NEAR(t.translation()(r), pos[r].get<double>(), 1e-7) << file;  // mm
      }
    }
  }
}

// τ = z·Σ(p − o)×m g must be −∂V/∂q of the generator's own potential energy.
TEST(IndependentCompliance, GravityTorqueIsMinusEnergyGradient) {
  const Robot robot = LoadRobot(kKr150);
  const ComplianceModel model = Kr150Compliance(1.0);
  Rng rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    Joints q;
    q << rng.Uniform(-1, 1), rng.Uniform(-1.8, -0.5), rng.Uniform(1.0, 2.2), rng.Uniform(-3, 3), rng.Uniform(-2, 2),
        rng.Uniform(-3, 3);
    const Joints tau = GravityTorque(robot, model, q);
    for (int i = 0; i < 6; ++i) {
      const double h = 1e-6;
      Joints qp = q, qm = q;
      qp(i) += h;
      qm(i) -= h;
      const double dv = (GravityPotential(robot, model, qp) - GravityPotential(robot, model, qm)) / (2 * h);
      // Central difference error ~h²·V''' (≈1e-8 N·m) plus rounding ~1e-16·V/h (≈1e-6 N·m).
      EXPECT_NEAR(tau(i), -dv, 1e-4 + 1e-8 * std::fabs(dv)) << "joint " << i + 1;
    }
    EXPECT_NEAR(tau(0), 0.0, 1e-9);  // joint 1 turns about the vertical: gravity does no work
  }
}

// The deflection is the minimum of the total energy E(Δ) = V(q + Δ) + ½ Σ k_i Δ_i².
TEST(IndependentCompliance, DeflectionIsEnergyStationaryPoint) {
  const Robot robot = LoadRobot(kKr150);
  const ComplianceModel model = Kr150Compliance(1.0);
  Joints q;
  q << 0.2, -1.1, 1.9, 0.7, -0.9, 0.3;
  const Joints dq = ComplianceDeflection(robot, model, q);
  auto energy = [&](const Joints& d) {
    double e = GravityPotential(robot, model, q + d);
    for (int i = 0; i < 6; ++i) e += 0.5 * model.stiffness_nm_per_rad[i] * d(i) * d(i);
    return e;
  };
  EXPECT_GT(std::fabs(dq(1)), 1e-5);  // joint 2 carries the arm: a deflection of order 1e-4 rad
  for (int i = 0; i < 6; ++i) {
    const double h = 1e-7;
    Joints p = dq, m = dq;
    p(i) += h;
    m(i) -= h;
    const double grad = (energy(p) - energy(m)) / (2 * h);
    // A residual gradient g means an error g/k in Δ; require it below 1e-9 rad.
    EXPECT_LT(std::fabs(grad) / model.stiffness_nm_per_rad[i], 1e-9) << "joint " << i + 1;
  }
}

// Photon shot noise + read noise + quantisation: var(DN) = G·(I − black) + G²σ_r² + 1/12, a + b·I with
// b = G. The slope is fitted from 6 intensity levels; its tolerance comes from the sampling error
// of a variance (σ²·√(2/(n−1))).
TEST(IndependentFringeSensor, PhotonNoiseVarianceIsLinearInIntensity) {
  for (double gain : {1.0, 4.0, 16.0}) {
    SensorModel sensor;
    sensor.gain_dn_per_e = gain;
    Rng rng(11 + static_cast<int>(gain));
    const int n = 40000;
    std::vector<double> xs, ys, ws;
    const double full_well = (65535.0 - sensor.black_level_dn) / gain;
    for (double f : {0.05, 0.2, 0.4, 0.6, 0.8, 0.95}) {
      const double mean_e = f * full_well;
      double s = 0, s2 = 0;
      for (int k = 0; k < n; ++k) {
        const double v = SensePixel(sensor, mean_e, rng);
        s += v;
        s2 += v * v;
      }
      const double mean = s / n, var = (s2 - n * mean * mean) / (n - 1);
      const double expected = gain * gain * (mean_e + sensor.read_noise_e * sensor.read_noise_e) + 1.0 / 12;
      EXPECT_NEAR(mean, sensor.black_level_dn + gain * mean_e, 5 * std::sqrt(expected / n)) << gain;
      EXPECT_NEAR(var, expected, 5 * expected * std::sqrt(2.0 / (n - 1))) << "gain " << gain << " f " << f;
      xs.push_back(mean);
      ys.push_back(var);
      ws.push_back(1.0 / (expected * expected * 2.0 / (n - 1)));
    }
    // Weighted least squares for var = a + b·I.
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < xs.size(); ++i) {
      sw += ws[i];
      sx += ws[i] * xs[i];
      sy += ws[i] * ys[i];
      sxx += ws[i] * xs[i] * xs[i];
      sxy += ws[i] * xs[i] * ys[i];
    }
    const double det = sw * sxx - sx * sx;
    const double b = (sw * sxy - sx * sy) / det, b_sigma = std::sqrt(sw / det);
    EXPECT_NEAR(b, gain, 4 * b_sigma) << "slope of the noise-level function";
  }
}

TEST(IndependentFringeSensor, SoftKneeIsLinearBelowAndSmoothAtTheKnee) {
  const double knee = 30000, range = 65000;
  EXPECT_DOUBLE_EQ(SoftKnee(12345, knee, range), 12345);
  const double h = 1e-3;
  EXPECT_NEAR((SoftKnee(knee + h, knee, range) - SoftKnee(knee, knee, range)) / h, 1.0, 1e-6);
  EXPECT_LE(SoftKnee(1e9, knee, range), range);  // never exceeds the range
  EXPECT_LT(SoftKnee(knee + 35000, knee, range), range);
  EXPECT_NEAR(SoftKnee(knee + 10000, knee, range), knee + 35000 * std::tanh(10000.0 / 35000), 1e-9);
}

// A pillbox PSF of radius r: its impulse response summed over one column kx must be the share of
// the disc's area inside the strip [kx − ½, kx + ½]: (F(kx + ½) − F(kx − ½))/(πr²) with
// F(x) = r²·asin(x/r) + x·√(r² − x²) (x clamped to [−r, r]). The kernel integrates each cell with a
// 256-node midpoint rule (error < 1e-5 pixel per cell), far inside the 1e-4 tolerance.
TEST(IndependentFringeOptics, PillboxMatchesTheDiscStripAreas) {
  for (double r : {1.5, 3.0, 4.5}) {
    const int w = 41, h = 41;
    std::vector<float> img(w * h, 0.0f);
    img[20 * w + 20] = 1.0f;
    PillboxBlur(img, w, h, r);
    auto area_left_of = [r](double x) {
      x = std::clamp(x, -r, r);
      return r * r * std::asin(x / r) + x * std::sqrt(r * r - x * x);
    };
    double sum = 0;
    for (int x = 0; x < w; ++x) {
      double column = 0;
      for (int y = 0; y < h; ++y) column += img[y * w + x];
      sum += column;
      const double expected = (area_left_of(x - 20 + 0.5) - area_left_of(x - 20 - 0.5)) / (M_PI * r * r);
      EXPECT_NEAR(column, expected, 1e-4) << "r " << r << " column " << x - 20;
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
}

// Exact Poisson draws: mean and variance equal the rate on both sides of the algorithm switch.
TEST(IndependentRandom, PoissonMeanAndVarianceEqualTheRate) {
  Rng rng(5);
  for (double rate : {0.7, 6.0, 12.0, 300.0, 50000.0}) {
    const int n = 100000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double k = rng.Poisson(rate);
      s += k;
      s2 += k * k;
    }
    const double mean = s / n, var = (s2 - n * mean * mean) / (n - 1);
    EXPECT_NEAR(mean, rate, 5 * std::sqrt(rate / n)) << rate;
    EXPECT_NEAR(var, rate, 5 * rate * std::sqrt((2.0 + 1.0 / rate) / n)) << rate;
  }
}

// Same seed, same bytes; another seed, other data (robot and laser; the fringe renderer draws in the
// same fixed order).
TEST(IndependentGenerators, FixedSeedIsDeterministic) {
  const auto dir = std::filesystem::temp_directory_path() / "indep_gen_test_robot";
  std::filesystem::remove_all(dir);
  auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  GenOptions o;
  o.kind = "robot";
  o.effect = "joint_compliance";
  o.robot_path = kKr150;
  o.seed = 3;
  o.out_dir = (dir / "a").string();
  GenerateRobot(o);
  o.out_dir = (dir / "b").string();
  GenerateRobot(o);
  o.seed = 4;
  o.out_dir = (dir / "c").string();
  GenerateRobot(o);
  EXPECT_EQ(read(dir / "a" / "ball.csv"), read(dir / "b" / "ball.csv"));
  EXPECT_NE(read(dir / "a" / "ball.csv"), read(dir / "c" / "ball.csv"));
  const nlohmann::json truth = nlohmann::json::parse(read(dir / "a" / "truth.json"));
  EXPECT_EQ(truth["expected_verdict"], "joint_compliance");
  o.kind = "laser";
  o.effect = "speed_ripple";
  o.out_dir = (dir / "d").string();
  GenerateLaser(o);
  o.out_dir = (dir / "e").string();
  GenerateLaser(o);
  EXPECT_EQ(read(dir / "d" / "laser_log.csv"), read(dir / "e" / "laser_log.csv"));
  EXPECT_EQ(nlohmann::json::parse(read(dir / "d" / "truth.json"))["expected_verdict"], "unexplained");
  std::filesystem::remove_all(dir);
}

// Line-to-segment distance against brute force over the segment (the line part is a projection).
TEST(IndependentLaser, LineSegmentDistanceMatchesBruteForce) {
  Rng rng(21);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p(rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-5, 5));
    const Eigen::Vector3d d = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    const Eigen::Vector3d a(rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-5, 5));
    const Eigen::Vector3d b(rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-5, 5));
    double best = 1e300;
    const int n = 20000;
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector3d x = a + (b - a) * (static_cast<double>(i) / n);
      best = std::min(best, (x - p - d * d.dot(x - p)).norm());
    }
    // Sampling at spacing |b − a|/n moves the minimum by at most that spacing.
    EXPECT_NEAR(LineSegmentDistance(p, d, a, b), best, (b - a).norm() / n + 1e-12);
    EXPECT_LE(LineSegmentDistance(p, d, a, b), best + 1e-12);
  }
}

// KUKA A, B, C: R = RotZ(A)·RotY(B)·RotX(C) (docs/conventions.md), recovered for B in (−90°, 90°).
TEST(IndependentLaser, KukaAbcRoundTrip) {
  Rng rng(22);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d abc(rng.Uniform(-179, 179), rng.Uniform(-89, 89), rng.Uniform(-179, 179));
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(abc.x() * kDeg, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(abc.y() * kDeg, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(abc.z() * kDeg, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    EXPECT_LT((KukaAbcDeg(r) - abc).norm(), 1e-9);
  }
}

// A laser set: every beam alternates blocked/clear from blocked, and each blocked interval of a
// circle obeys the chord law: with the circle centre at distance e from the beam and the tool's
// in-plane radius ρ, the tool blocks while |e + R sin φ| < ρ, an angular width
// w = asin((ρ + e)/R) + asin((ρ − e)/R) (e < ρ) or asin((e + ρ)/R) − asin((e − ρ)/R) (e > ρ).
// By the convexity of asin, w ≥ 2·asin(ρ/R); w grows with e, and e ≤ 3√2 mm (apex offset)
// + 26·tan 4° (tilt at the upper circle) + 0.1 ≈ 6.1 mm gives w ≤ 1.17·2·asin(ρ/R). ρ = 2.5 mm
// (the shank; ≥ 2.5/cos 4° along the tilt, < 0.3 % more).
TEST(IndependentLaser, LogAlternatesAndCircleBlockTimesFollowTheChordLaw) {
  const auto dir = std::filesystem::temp_directory_path() / "indep_gen_test_laser";
  std::filesystem::remove_all(dir);
  GenOptions o;
  o.kind = "laser";
  o.effect = "none";
  o.seed = 2;
  o.out_dir = dir.string();
  GenerateLaser(o);
  std::ifstream in(dir / "laser_log.csv");
  std::string line;
  std::getline(in, line);
  std::map<char, std::vector<std::pair<double, bool>>> beams;
  while (std::getline(in, line)) {
    double t;
    char beam;
    char state[16];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%c,%15s", &t, &beam, state), 3) << line;
    beams[beam].push_back({t, std::string(state) == "blocked"});
  }
  const double omega = M_PI, radius = 12;  // 180°/s, R = 12 mm
  for (const auto& [beam, ev] : beams) {
    ASSERT_GE(ev.size(), 8u);
    for (size_t i = 0; i < ev.size(); ++i) EXPECT_EQ(ev[i].second, i % 2 == 0) << beam << " event " << i;
    for (size_t i = 0; i + 1 < ev.size(); i += 2) {
      if (ev[i].first > 9.0) break;  // circles end at 9 s; the plunges follow
      const double width = (ev[i + 1].first - ev[i].first) * omega;
      const double nominal = 2 * std::asin(2.5 / radius);
      EXPECT_GT(width, nominal * 0.999) << beam;
      EXPECT_LT(width, nominal * 1.17) << beam;
    }
  }
  std::filesystem::remove_all(dir);
}

// A rendered clean set (`none`, gain 4): the N-step model A + B·cos(φ + δ_k) is exact for the
// phase frames (blur, pixel and projector apertures are linear and keep the sinusoid), so the
// fit residual must be the sensor noise alone: E Σ_k r_k² = (1 − 3/N)·Σ_k var_k with
// var_k = G·(I_k − black) + G²σ_r² + 1/12 (photon + read + quantisation noise).
TEST(IndependentFringe, CleanSetResidualIsThePhotonNoise) {
  const auto dir = std::filesystem::temp_directory_path() / "indep_gen_test_fringe";
  std::filesystem::remove_all(dir);
  GenOptions o;
  o.kind = "fringe";
  o.effect = "none";
  o.seed = 1;
  o.gain = 4;
  o.out_dir = dir.string();
  GenerateFringe(o);
  std::ifstream in(dir / "manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(in);
  const auto& files = manifest["cameras"]["left"];
  const int steps = manifest["sequence"][0]["steps"];
  ASSERT_EQ(files.size(), static_cast<size_t>(steps + manifest["sequence"][1]["bits"].get<int>()));
  std::vector<cv::Mat> frames;
  for (int k = 0; k < steps; ++k) {
    frames.push_back(cv::imread((dir / files[k].get<std::string>()).string(), cv::IMREAD_UNCHANGED));
    ASSERT_EQ(frames.back().type(), CV_16UC1);
  }
  const SensorModel sensor;  // black level and read noise of the generator
  const double g = o.gain;
  double observed = 0, predicted = 0;
  for (int y = 0; y < frames[0].rows; ++y) {
    for (int x = 0; x < frames[0].cols; ++x) {
      std::vector<double> v(steps);
      double a = 0, c = 0, s = 0;
      for (int k = 0; k < steps; ++k) {
        v[k] = frames[k].at<std::uint16_t>(y, x);
        const double d = 2 * M_PI * k / steps;
        a += v[k] / steps;
        c += 2.0 / steps * v[k] * std::cos(d);
        s += 2.0 / steps * v[k] * std::sin(d);
      }
      double var_sum = 0, res = 0;
      for (int k = 0; k < steps; ++k) {
        const double d = 2 * M_PI * k / steps;
        const double r = v[k] - (a + c * std::cos(d) + s * std::sin(d));
        res += r * r;
        var_sum += g * (v[k] - sensor.black_level_dn) + g * g * sensor.read_noise_e * sensor.read_noise_e + 1.0 / 12;
      }
      observed += res;
      predicted += (1.0 - 3.0 / steps) * var_sum;
    }
  }
  // 327680 pixels × 5 degrees of freedom: the ratio's sampling error is ≈ √(2/1.6e6) ≈ 0.1 %.
  EXPECT_NEAR(observed / predicted, 1.0, 0.01);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace indep
