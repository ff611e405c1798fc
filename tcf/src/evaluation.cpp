// Method comparison against simulated truth.
#include "ramtk/tcf/evaluation.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "ramtk/core/error.h"
#include "ramtk/core/units.h"

namespace ramtk::tcf {

const char* TcfMethodName(TcfMethod m) {
  switch (m) {
    case TcfMethod::kCrossLaser:
      return "cross-laser (ramtk, self-calibrated)";
    case TcfMethod::kCrossLaserNoSelfCalibration:
      return "cross-laser (ramtk, no self-calibration)";
    case TcfMethod::kThesisCorrected:
      return "cross-laser (thesis, beta corrected)";
    case TcfMethod::kThesisUncorrected:
      return "cross-laser (thesis, beta ignored)";
    case TcfMethod::kFourPoint:
      return "4-point";
    case TcfMethod::kSevenPoint:
      return "7-point";
    case TcfMethod::kParallelLaser:
      return "parallel laser";
  }
  return "?";
}

TcfSolverOptions SolverOptionsFor(TcfMethod m) {
  TcfSolverOptions o;
  switch (m) {
    case TcfMethod::kCrossLaser:
      break;
    case TcfMethod::kCrossLaserNoSelfCalibration:
      o.self_calibrate_latency = false;
      o.self_calibrate_beam_offset = false;
      o.self_calibrate_speed = false;
      break;
    case TcfMethod::kThesisCorrected:
    case TcfMethod::kThesisUncorrected:
      o.crossing_model = CrossingModel::kThesisMidpoints;
      o.tip_model = TipTriggerModel::kApexAtBeamLine;
      o.self_calibrate_latency = false;
      o.self_calibrate_beam_offset = false;
      o.self_calibrate_speed = false;
      o.correct_oblique_beams = m == TcfMethod::kThesisCorrected;
      break;
    default:
      break;
  }
  return o;
}

std::string EvaluationOptions::Validate() const {
  if (runs < 1) return "runs must be >= 1";
  if (!(touch_sigma_mm >= 0.0) || !(align_sigma_deg >= 0.0)) return "operator noise must be >= 0";
  return simulation.Validate();
}

std::vector<MethodAccuracy> EvaluateMethods(const EvaluationOptions& opt) {
  ThrowIfInvalid(opt.Validate(), "EvaluationOptions");
  std::vector<MethodAccuracy> rows;
  std::vector<double> tcp_ss(opt.methods.size(), 0.0), axis_ss(opt.methods.size(), 0.0),
      sig_ss(opt.methods.size(), 0.0);
  for (TcfMethod m : opt.methods) rows.push_back({m});
  for (int run = 0; run < opt.runs; ++run) {
    TcfSimulationOptions so = opt.simulation;
    so.seed = opt.first_seed + run;
    const TcfSimulation sim = SimulateTcf(so);
    const TcfTruth& truth = sim.truth;
    for (std::size_t k = 0; k < opt.methods.size(); ++k) {
      const TcfMethod m = opt.methods[k];
      Vec3 tcp, axis;
      bool has_axis = true;
      try {
        switch (m) {
          case TcfMethod::kFourPoint:
          case TcfMethod::kSevenPoint: {
            TouchUpSimulationOptions t;
            t.seed = so.seed * 7919 + 17;
            t.repeatability_mm = so.repeatability_mm;
            t.touch_sigma_mm = opt.touch_sigma_mm;
            t.align_sigma_deg = opt.align_sigma_deg;
            const BaselineResult r = m == TcfMethod::kFourPoint ? SimulateFourPoint(truth.flange_from_tcp, t)
                                                                : SimulateSevenPoint(truth.flange_from_tcp, t);
            tcp = r.tcp_in_flange;
            axis = r.axis_in_flange;
            has_axis = r.has_axis;
            break;
          }
          case TcfMethod::kParallelLaser: {
            ParallelLaserSimulationOptions p;
            p.seed = so.seed * 104729 + 3;
            p.repeatability_mm = so.repeatability_mm;
            p.timing_jitter_s = so.timing_jitter_s;
            p.beam_width_mm = truth.beam_width_mm;
            p.tool_radius_mm = so.tool_radius_mm;
            p.nominal_tool_length_mm = so.nominal_tool_length_mm;
            const BaselineResult r = SimulateParallelLaser(truth.flange_from_tcp, p);
            tcp = r.tcp_in_flange;
            axis = r.axis_in_flange;
            break;
          }
          default: {
            TcfSolverOptions o = SolverOptionsFor(m);
            o.repeatability_sigma_mm = so.repeatability_mm;
            o.timing_sigma_s = std::max(so.timing_jitter_s, 1e-7);
            if (m != TcfMethod::kCrossLaser) o.repeatability_sigma_mm = o.timing_sigma_s = 0.0;
            const TcfSummary s = SolveTcf(sim.events, sim.motion, sim.calibrated_sensor, o);
            tcp = s.solution.tcp_in_flange;
            axis = s.solution.axis_in_flange;
            sig_ss[k] += s.tcp_sigma_mm * s.tcp_sigma_mm;
            break;
          }
        }
      } catch (const InputError&) {
        ++rows[k].failures;
        continue;
      }
      const double e = (tcp - truth.tcp_in_flange).norm();
      tcp_ss[k] += e * e;
      rows[k].tcp_max_mm = std::max(rows[k].tcp_max_mm, e);
      if (has_axis) {
        const double a = RadToDeg(std::acos(std::clamp(axis.normalized().dot(truth.axis_in_flange), -1.0, 1.0)));
        axis_ss[k] += a * a;
      } else {
        axis_ss[k] = std::numeric_limits<double>::quiet_NaN();
      }
      ++rows[k].runs;
    }
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int n = std::max(1, rows[k].runs);
    rows[k].tcp_rms_mm = std::sqrt(tcp_ss[k] / n);
    rows[k].axis_rms_deg = std::sqrt(axis_ss[k] / n);
    rows[k].predicted_tcp_sigma_mm = std::sqrt(sig_ss[k] / n);
  }
  return rows;
}

std::string FormatAccuracyTable(const std::vector<MethodAccuracy>& rows) {
  std::string out =
      "| method | runs | failed | TCP RMS (mm) | TCP max (mm) | axis RMS (deg) | predicted TCP 1σ (mm) |\n"
      "|---|---|---|---|---|---|---|\n";
  char buf[256];
  for (const MethodAccuracy& r : rows) {
    char axis[32], pred[32];
    if (std::isnan(r.axis_rms_deg)) {
      std::snprintf(axis, sizeof(axis), "—");
    } else {
      std::snprintf(axis, sizeof(axis), "%.4f", r.axis_rms_deg);
    }
    if (r.predicted_tcp_sigma_mm > 0) {
      std::snprintf(pred, sizeof(pred), "%.4f", r.predicted_tcp_sigma_mm);
    } else {
      std::snprintf(pred, sizeof(pred), "—");
    }
    std::snprintf(buf, sizeof(buf), "| %s | %d | %d | %.4f | %.4f | %s | %s |\n", TcfMethodName(r.method), r.runs,
                  r.failures, r.tcp_rms_mm, r.tcp_max_mm, axis, pred);
    out += buf;
  }
  return out;
}

}  // namespace ramtk::tcf
