// 4-point, 7-point and parallel-laser baselines (thesis §4.1) and their measurement simulation.
#include "ramtk/tcf/baselines.h"

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <random>

#include "ramtk/core/units.h"

namespace ramtk::tcf {
namespace {

Vec3 Gaussian3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma > 0 ? sigma : 1.0);
  if (!(sigma > 0)) return Vec3::Zero();
  return Vec3(n(rng), n(rng), n(rng));
}

}  // namespace

BaselineResult SolveFourPoint(const std::array<Isometry3, 4>& f) {
  // Eq. (4-2): 2 [p_i − p_1]^T x0 = |p_i|² − |p_1|², i = 2..4.
  Mat3 a;
  Vec3 b;
  const Vec3 p1 = f[0].translation();
  for (int i = 1; i < 4; ++i) {
    const Vec3 pi = f[i].translation();
    a.row(i - 1) = 2.0 * (pi - p1).transpose();
    b(i - 1) = pi.squaredNorm() - p1.squaredNorm();
  }
  const Vec3 p_ref = a.colPivHouseholderQr().solve(b);
  // Eq. (4-4): R_i t + p_i = p_ref for all i, least squares in t.
  Eigen::Matrix<double, 12, 3> m;
  Eigen::Matrix<double, 12, 1> rhs;
  for (int i = 0; i < 4; ++i) {
    m.block<3, 3>(3 * i, 0) = f[i].linear();
    rhs.segment<3>(3 * i) = p_ref - f[i].translation();
  }
  BaselineResult r;
  r.tcp_in_flange = m.colPivHouseholderQr().solve(rhs);
  r.residual_rms_mm = std::sqrt((m * r.tcp_in_flange - rhs).squaredNorm() / 4.0);
  return r;
}

BaselineResult SolveSevenPoint(const std::array<Isometry3, 4>& touch, const std::array<Isometry3, 3>& ax) {
  BaselineResult r = SolveFourPoint(touch);
  const Vec3 p8 = ax[0] * r.tcp_in_flange, p9 = ax[1] * r.tcp_in_flange, p10 = ax[2] * r.tcp_in_flange;
  const Vec3 z = (p10 - p9).normalized();
  const Vec3 y = z.cross((p9 - p8).normalized()).normalized();
  const Vec3 x = y.cross(z);
  Mat3 base_r_tool;
  base_r_tool << x, y, z;
  const Mat3 flange_r_tool = ax[0].linear().transpose() * base_r_tool;
  r.axis_in_flange = flange_r_tool.col(2);
  r.has_axis = true;
  return r;
}

namespace {

std::array<Isometry3, 4> SimulateTouches(const Isometry3& flange_from_tcp, const TouchUpSimulationOptions& o,
                                         std::mt19937_64& rng) {
  std::array<Isometry3, 4> out;
  const Mat3 down = Vec3(1.0, -1.0, -1.0).asDiagonal();  // Z_e pointing down
  for (int i = 0; i < 4; ++i) {
    // Dispersed orientations (thesis: "足够分散"): four azimuths and four different tilts, so the
    // four flange positions are not coplanar and eq. (4-2) is well conditioned.
    const double az = DegToRad(90.0 * i + 20.0);
    const double tilt = DegToRad(o.tilt_deg * (0.4 + 0.2 * i));
    Isometry3 f = Isometry3::Identity();
    f.linear() = RotZ(az) * RotX(tilt) * RotZ(-az) * down;
    // The operator puts the tip on the point (by eye); the controller records the pose it reached.
    const Vec3 tip = o.reference_point_in_base + Gaussian3(rng, o.touch_sigma_mm);
    f.translation() = tip - f.linear() * flange_from_tcp.translation();
    f.translation() += Gaussian3(rng, o.repeatability_mm);
    out[i] = f;
  }
  return out;
}

}  // namespace

BaselineResult SimulateFourPoint(const Isometry3& flange_from_tcp, const TouchUpSimulationOptions& o) {
  std::mt19937_64 rng(o.seed);
  return SolveFourPoint(SimulateTouches(flange_from_tcp, o, rng));
}

BaselineResult SimulateSevenPoint(const Isometry3& flange_from_tcp, const TouchUpSimulationOptions& o) {
  std::mt19937_64 rng(o.seed);
  const auto touches = SimulateTouches(flange_from_tcp, o, rng);
  // P5: the operator aligns the tool frame with the base by eye: base_R_tool = small error.
  const Vec3 err = Gaussian3(rng, DegToRad(o.align_sigma_deg));
  const Mat3 r_err =
      Eigen::AngleAxisd(err.norm(), err.norm() > 0 ? Vec3(err.normalized()) : Vec3::UnitZ()).toRotationMatrix();
  Isometry3 p5 = Isometry3::Identity();
  p5.linear() = r_err * flange_from_tcp.linear().transpose();
  p5.translation() = o.reference_point_in_base + Vec3(0, 0, 50) - p5.linear() * flange_from_tcp.translation();
  Isometry3 p6 = p5, p7 = p5;
  p6.translation() += o.move_mm * Vec3::UnitX();
  p7.translation() = p6.translation() + o.move_mm * Vec3::UnitZ();
  for (Isometry3* p : {&p5, &p6, &p7}) p->translation() += Gaussian3(rng, o.repeatability_mm);
  return SolveSevenPoint(touches, {p5, p6, p7});
}

BaselineResult SimulateParallelLaser(const Isometry3& flange_from_tcp, const ParallelLaserSimulationOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const Vec3 tcp = flange_from_tcp.translation();
  const Vec3 axis = flange_from_tcp.linear().col(2);
  const double hw = 0.5 * o.beam_width_mm;
  const Vec3 beam_dir = Vec3::UnitY();
  const Vec3 beam_pt[2] = {o.upper_beam_point_in_base, o.upper_beam_point_in_base - Vec3(0, 0, o.beam_spacing_mm)};
  // Clearance of beam b from the tool (ball + cylinder) at flange pose f: < 0 is blocked.
  auto clearance = [&](int b, const Isometry3& f) {
    const Vec3 a = f.linear() * axis;
    const Vec3 c = f * tcp - o.tool_radius_mm * a;
    const Vec3 e = -a, w = c - beam_pt[b];
    const double bb = beam_dir.dot(e);
    double mu = std::max(0.0, (bb * beam_dir.dot(w) - e.dot(w)) / (1.0 - bb * bb));
    const Vec3 v = c + mu * e - beam_pt[b];
    return (v - v.dot(beam_dir) * beam_dir).norm() - o.tool_radius_mm - hw;
  };
  // A straight move of the flange from `start` along `dir` over `length`; returns the recorded
  // (programmed) flange positions at the state changes of beam b, in order.
  auto scan = [&](int b, const Isometry3& start, const Vec3& dir, double length) {
    const Vec3 offset = Gaussian3(rng, o.repeatability_mm);
    auto at = [&](double s) {
      Isometry3 f = start;
      f.translation() += s * dir + offset;
      return f;
    };
    std::vector<double> out;
    const int n = 4000;
    double prev = clearance(b, at(0.0));
    for (int i = 1; i <= n; ++i) {
      const double s1 = length * i / n, c1 = clearance(b, at(s1));
      if ((c1 < 0) != (prev < 0)) {
        double lo = length * (i - 1) / n, hi = s1;
        for (int k = 0; k < 60; ++k)
          ((clearance(b, at(0.5 * (lo + hi))) < 0) == (prev < 0) ? lo : hi) = 0.5 * (lo + hi);
        // Reported late by jitter -> the recorded position moves on by speed·jitter.
        out.push_back(0.5 * (lo + hi) + o.scan_speed_mm_s * o.timing_jitter_s * unit(rng));
      }
      prev = c1;
    }
    return out;
  };
  const Mat3 down = Vec3(1.0, -1.0, -1.0).asDiagonal();
  // Flange height so that the beams cut the tool ~5 mm and ~25 mm above the nominal tip.
  auto scan_start = [&](const Mat3& rot) {
    Isometry3 f = Isometry3::Identity();
    f.linear() = rot;
    f.translation() = beam_pt[1] + Vec3(-20.0, 0.0, 0.0) - rot * Vec3(0, 0, o.nominal_tool_length_mm - 5.0);
    return f;
  };
  // Constraints: at flange pose F, the axis crosses beam b's line (x = x_b at z = h_b).
  struct Constraint {
    Isometry3 f;
    int beam;
  };
  std::vector<Constraint> cons;
  for (const Mat3& rot : {Mat3(down), Mat3(down * RotZ(DegToRad(90.0)))}) {
    const Isometry3 start = scan_start(rot);
    for (int b = 0; b < 2; ++b) {
      const std::vector<double> s = scan(b, start, Vec3::UnitX(), 40.0);
      if (s.size() < 2) continue;
      Isometry3 f = start;
      f.translation() += 0.5 * (s[0] + s[1]) * Vec3::UnitX();
      cons.push_back({f, b});
    }
  }
  // Axis in the flange frame through (x1, y1, ζ1) and (x2, y2, ζ2); Gauss-Newton on x1, y1, x2, y2.
  const double z1 = o.nominal_tool_length_mm - 25.0, z2 = o.nominal_tool_length_mm - 5.0;
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
  auto residuals = [&](const Eigen::Vector4d& v) {
    Eigen::VectorXd r(cons.size());
    const Vec3 a1(v(0), v(1), z1), a2(v(2), v(3), z2);
    for (std::size_t i = 0; i < cons.size(); ++i) {
      const Vec3 b1 = cons[i].f * a1, b2 = cons[i].f * a2;
      const double h = beam_pt[cons[i].beam].z();
      const Vec3 p = b1 + (h - b1.z()) / (b2.z() - b1.z()) * (b2 - b1);
      r(i) = p.x() - beam_pt[cons[i].beam].x();
    }
    return r;
  };
  for (int it = 0; it < 10 && cons.size() >= 4; ++it) {
    const Eigen::VectorXd r0 = residuals(q);
    Eigen::MatrixXd j(r0.size(), 4);
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector4d dq = q;
      dq(k) += 1e-6;
      j.col(k) = (residuals(dq) - r0) / 1e-6;
    }
    q -= j.colPivHouseholderQr().solve(r0);
  }
  BaselineResult res;
  const Vec3 a1(q(0), q(1), z1), a2(q(2), q(3), z2);
  res.axis_in_flange = (a2 - a1).normalized();
  res.has_axis = true;
  // Eq. (4-7): lower the tool with its axis through the upper beam line until it is blocked; the
  // apex is then on the beam line.
  Isometry3 f = Isometry3::Identity();
  f.linear() = down;
  {
    const Vec3 tip_guess = a1 + (o.nominal_tool_length_mm - z1) / res.axis_in_flange.z() * res.axis_in_flange;
    f.translation() = beam_pt[0] + Vec3(0, 0, 10.0) - down * tip_guess;
  }
  const std::vector<double> s = scan(0, f, -Vec3::UnitZ(), 20.0);
  if (!s.empty()) {
    Isometry3 fe = f;
    fe.translation() += -s[0] * Vec3::UnitZ();
    const Vec3 b1 = fe * a1, b2 = fe * a2;
    const double h = beam_pt[0].z();
    const double mu = (h - b1.z()) / (b2.z() - b1.z());
    res.tcp_in_flange = a1 + mu * (a2 - a1);
  }
  return res;
}

}  // namespace ramtk::tcf
