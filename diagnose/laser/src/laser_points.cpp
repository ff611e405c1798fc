// Sensor-frame calibration points (thesis Table 5-3) against the ideal device.
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "ramtk/diagnose/laser/detail/laser_fit.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/diagnose/laser/laser.h"
#include "ramtk/diagnose/engine/model_selection.h"
#include "ramtk/diagnose/engine/plot.h"
#include "ramtk/diagnose/engine/statistics.h"

namespace ramtk::diagnose {
namespace {

using laser_detail::CandidateOutcome;
using laser_detail::CandidateSpec;
using laser_detail::ResidualModel;

// Parameter layout: frame origin (3, mm), small frame rotation (3, deg), pin half-widths of the
// horizontal and vertical passes (2, mm), then the effects: β (deg), z_x − z_y (mm).
enum Param { kOx, kOy, kOz, kRx, kRy, kRz, kHalfH, kHalfV, kBeta, kOffset, kNumParams };

// One scalar observation: the flange coordinate along a pass at a state change.
struct Observation {
  std::string label;  // "A1".."D4"
  bool x_beam = true;
  bool vertical = false;  // k = 3, 4: z; else the coordinate along the horizontal scan
  int scan_axis = 1;      // horizontal scan along base X (0) or Y (1)
  double sign = 1.0;      // +1: the pin edge reaches the beam ahead of the flange (first event)
  double value = 0.0;     // observed coordinate (mm)
  double across = 0.0;    // the flange's base coordinate across the scan (fixes the beam point)
};

std::vector<Observation> Observations(const std::map<std::string, Vec3>& p, const std::string& file) {
  std::vector<Observation> obs;
  for (const char point : std::string("ABCD")) {
    const std::string l(1, point);
    auto at = [&](int k) -> const Vec3& {
      auto it = p.find(l + std::to_string(k));
      if (it == p.end()) throw InputError({file, 0, l + std::to_string(k)}, "calibration point missing");
      return it->second;
    };
    const Vec3 scan = at(2) - at(1);
    const int axis = std::abs(scan.x()) > std::abs(scan.y()) ? 0 : 1;
    const double dir = scan(axis) >= 0 ? 1.0 : -1.0;
    const double vdir = at(3).z() >= at(4).z() ? 1.0 : -1.0;
    for (int k = 1; k <= 4; ++k) {
      Observation o;
      o.label = l + std::to_string(k);
      o.x_beam = point == 'A' || point == 'B';
      o.vertical = k >= 3;
      o.scan_axis = axis;
      o.across = at(k)(1 - axis);
      o.value = o.vertical ? at(k).z() : at(k)(axis);
      // k = 1 (3): blocked, the flange is short of the beam by the half width; k = 2 (4): past it.
      o.sign = (k % 2 == 1 ? -1.0 : 1.0) * (o.vertical ? -vdir : dir);
      obs.push_back(o);
    }
  }
  return obs;
}

Eigen::VectorXd Predict(const std::vector<Observation>& obs, const Isometry3& frame0, const Eigen::VectorXd& q) {
  const Vec3 w(DegToRad(q(kRx)), DegToRad(q(kRy)), DegToRad(q(kRz)));
  Mat3 r = frame0.linear();
  if (w.norm() > 0) r = r * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  const Vec3 origin(q(kOx), q(kOy), q(kOz));
  const double beta = DegToRad(q(kBeta));
  Eigen::VectorXd pred(obs.size());
  for (size_t i = 0; i < obs.size(); ++i) {
    const Observation& o = obs[i];
    const Vec3 p = origin + (o.x_beam ? 0.5 : -0.5) * q(kOffset) * r.col(2);
    const Vec3 d = o.x_beam ? Vec3(r.col(0)) : Vec3(std::cos(beta) * r.col(0) + std::sin(beta) * r.col(1));
    const int a = o.scan_axis, c = 1 - a;
    const double s = (o.across - p(c)) / d(c);  // the beam point below the pass
    const Vec3 hit = p + s * d;
    if (o.vertical) {
      pred(i) = hit.z() + o.sign * q(kHalfV);
    } else {
      // Along an oblique beam the pin travels half_width / |cos| between contact and the centre line.
      const Vec3 normal = Vec3::UnitZ().cross(d).normalized();
      pred(i) = hit(a) + o.sign * q(kHalfH) / std::max(1e-6, std::abs(normal(a)));
    }
  }
  return pred;
}

}  // namespace

Diagnosis DiagnoseSensorPoints(const std::map<std::string, Vec3>& flange_in_base, const DiagnoseOptions& options) {
  const std::vector<Observation> obs = Observations(flange_in_base, options.data);
  const tcf::SensorFrame frame = tcf::CalibrateSensorFrame(tcf::BeamPointsFromFlangePositions(flange_in_base));
  Isometry3 frame0 = frame.base_from_lasersensor;
  Eigen::VectorXd values(obs.size());
  double half_h = 0, half_v = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    values(i) = obs[i].value;
    (obs[i].vertical ? half_v : half_h) += obs[i].sign * obs[i].value / 4.0;  // Σ over pairs: 2·half / 8·2
  }

  ResidualModel model;
  model.names = {"origin_x_mm", "origin_y_mm", "origin_z_mm", "rot_x_deg", "rot_y_deg",
                 "rot_z_deg",   "half_h_mm",   "half_v_mm",   "beta_deg",  "offset_mm"};
  model.initial = Eigen::VectorXd::Zero(kNumParams);
  model.initial.head<3>() = frame0.translation();
  model.initial(kHalfH) = half_h / 2.0;
  model.initial(kHalfV) = half_v / 2.0;
  model.initial(kBeta) = 90.0;
  model.step = Eigen::VectorXd::Constant(kNumParams, 1e-4);
  model.residuals = [&](const Eigen::VectorXd& q) -> Eigen::VectorXd { return values - Predict(obs, frame0, q); };
  for (size_t i = 0; i < obs.size(); ++i) model.group.push_back(static_cast<int>(i));
  model.num_groups = static_cast<int>(obs.size());

  Diagnosis d;
  d.kind = DataKind::kLaser;
  d.data = options.data;
  d.unit = "mm";
  d.model = "ideal device (perpendicular intersecting beams)";
  const double sigma = options.noise > 0 ? options.noise : kSensorPointNoiseMm;
  d.noise_floor_rms = sigma;
  d.num_residuals = static_cast<int>(obs.size());
  const std::vector<int> base = {kOx, kOy, kOz, kRx, kRy, kRz, kHalfH, kHalfV};
  const std::vector<CandidateSpec> specs = {
      {kNoEffect, {}}, {"beam_non_perpendicular", {kBeta}}, {"beam_offset", {kOffset}}};
  std::vector<CandidateOutcome> outcomes;
  for (const CandidateSpec& s : specs)
    outcomes.push_back(laser_detail::EvaluateCandidate(model, base, s, model.num_groups));

  // Step 1-2: the ideal model's residual (scaled for the fitted frame) against the noise.
  const CandidateOutcome& ideal = outcomes.front();
  const Eigen::VectorXd r0 = model.residuals(ideal.full.params);
  const double n = r0.size(), dof_scale = std::sqrt(n / (n - base.size()));
  std::vector<double> scaled(r0.data(), r0.data() + r0.size());
  for (double& v : scaled) v *= dof_scale;
  const TestResult variance = VarianceTest(scaled, {sigma});
  std::vector<double> beam_var;
  for (const Observation& o : obs) beam_var.push_back(o.x_beam ? 1.0 : -1.0);
  const TestResult by_beam = TrendTest(scaled, {sigma}, beam_var, 1, "beam");
  const std::vector<double> holm = HolmCorrection({variance.p_value, by_beam.p_value});
  d.structure_p_value = std::min(holm[0], holm[1]);
  d.structure_found = d.structure_p_value < options.alpha;
  d.residual_rms = laser_detail::Rms(r0);
  d.findings.push_back(variance.Describe());
  d.findings.push_back(by_beam.Describe());

  const double min_improvement = 10.0;
  const int chosen = laser_detail::Conclude(outcomes, min_improvement, &d);
  if (d.cause == kUnexplained)
    d.explaining_variable = holm[1] < options.alpha ? "beam" : "none of the tested variables";
  const CandidateOutcome final_outcome = laser_detail::AddFurtherEffects(
      model, base, specs, outcomes, chosen, model.num_groups, min_improvement, "leave-one-out RMS", &d);
  const Eigen::VectorXd& final_resid = final_outcome.heldout_resid;

  if (!options.output_folder.empty()) {
    std::filesystem::create_directories(options.output_folder);
    report::Series before, after;
    before.label = "ideal device (held out)";
    after.label = "extended model (held out)";
    before.style = after.style = report::SeriesStyle::kLinesPoints;
    for (size_t i = 0; i < obs.size(); ++i) {
      before.x.push_back(static_cast<double>(i + 1));
      before.y.push_back(outcomes[0].heldout_resid(i));
      after.x.push_back(static_cast<double>(i + 1));
      after.y.push_back(final_resid(i));
    }
    AddFigure(OnePanel("residual_by_point",
                       "Leave-one-out residual of each flange coordinate, ideal device and extended model",
                       "Calibration points: leave-one-out residual",
                       "observation: A1–A4, B1–B4 (x beam), C1–C4, D1–D4 (y beam)", "residual (mm)",
                       {before, after}, sigma),
              options.output_folder, &d.pictures);
  }
  return d;
}

}  // namespace ramtk::diagnose
