// ramtk thermal compensate: corrected joints for the taught poses and the monitoring residuals.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/core/parse.h"
#include "ramtk/core/units.h"
#include "ramtk/thermal/compensation.h"
#include "ramtk/thermal/thermal_report.h"
#include "thermal_inputs.h"

namespace ramtk::tools {
namespace {

using namespace thermal;

// ---------------------------------------------------------------- thermal compensate
struct CompensateOptions {
  ExperimentInputs in;
  int cycle = -1;  // -1: the last cycle
  double threshold_mm = 0.1;
  std::string out_path;
  std::string out_report;  // report.html
};

int RunCompensate(const CompensateOptions& opt, Provenance provenance) {
  CheckOutputs(opt.in, {{"--out", opt.out_path}, {"--report", opt.out_report}});
  for (const std::string& f : {opt.in.robot_path, opt.in.setup_path, opt.in.ball_path, opt.in.monitoring_path})
    AddProvenanceFile(&provenance, f);
  const LoadedExperiment e = Load(opt.in);
  const ThermalExperiment ex = MakeExperiment(e.model, e.setup, e.ball, e.monitoring);
  const DriftModel dm(e.model, e.setup, e.ball.taught);
  IdentificationOptions id = MakeIdOptions(opt.in, e, dm, ParseParamList(opt.in.params, e.model, "--params"));
  if (!GuardIdentification(opt.in, dm, &id)) return kExitNoSolution;
  const std::vector<int>& params = id.params;
  IdentificationSummary is;
  const Eigen::MatrixXd x_mon = IdentifyForMonitoring(ex, dm, id, &is);
  const MonitoringModel mon(e.model, e.setup, e.monitoring);
  LambdaOptions lo;
  lo.threshold_mm = opt.threshold_mm;
  const Eigen::MatrixXd before = mon.Uncompensated();
  const Eigen::MatrixXd after = mon.Residuals(x_mon);
  const int col = opt.cycle < 0 ? e.monitoring.NumCycles() - 1 : e.monitoring.Find(opt.cycle);
  if (col < 0)
    throw InputError({opt.in.monitoring_path, 0, "--cycle"}, "cycle " + std::to_string(opt.cycle) + " not found");
  CompensationSummary cs;
  const ParamVector dx = x_mon.col(col);
  const auto corrected = CompensateTaughtPoses(e.model, dx, e.monitoring.taught, {}, &cs);
  // What the identification's noise leaves in each compensated point: J Σ_x Jᵀ with Σ_x the
  // identified drift's covariance of this cycle.
  const std::vector<Mat3> point_cov =
      CompensatedPointCovariances(mon, params, is.covariance[static_cast<std::size_t>(ex.ball_column[col])]);
  Eigen::VectorXd mon_sigma(3 * mon.NumPoints());
  for (int k = 0; k < mon.NumPoints(); ++k) {
    for (int a = 0; a < 3; ++a) mon_sigma[3 * k + a] = std::sqrt(std::max(0.0, point_cov[k](a, a)));
  }
  std::string csv = "point,q1,q2,q3,q4,q5,q6,dq1,dq2,dq3,dq4,dq5,dq6,cov_xx,cov_yy,cov_zz,cov_xy,cov_xz,cov_yz\n";
  for (int k = 0; k < e.monitoring.NumPoses(); ++k) {
    csv += std::to_string(e.monitoring.ids[k]);
    for (int j = 0; j < kinematics::kNumJoints; ++j) csv += Fmt(",%.9f", RadToDeg(corrected[k][j]));
    for (int j = 0; j < kinematics::kNumJoints; ++j)
      csv += Fmt(",%.9f", RadToDeg(corrected[k][j] - e.monitoring.taught[k][j]));
    const Mat3& c = point_cov[k];
    for (double v : {c(0, 0), c(1, 1), c(2, 2), c(0, 1), c(0, 2), c(1, 2)}) csv += Fmt(",%.10g", v);
    csv += "\n";
  }
  std::cout << is.BriefReport() << "\n"
            << is.covariance_scaling << "\n"
            << "params " << ParamListToString(params) << ", poses "
            << (id.poses.empty() ? std::string("all") : IntList(PoseIds(e, id))) << "\n"
            << "identified drift at cycle " << e.monitoring.cycles[col].cycle << " (mm, deg; value ± sigma):";
  for (std::size_t k = 0; k < params.size(); ++k) {
    std::cout << " " << kinematics::ParamName(params[k]) << "="
              << ValueWithSigma(params[k], dx[params[k]], is.Sigma(static_cast<int>(k), ex.ball_column[col]));
  }
  std::cout << "\n"
            << "monitoring points recomputed with the identified drift (" << e.monitoring.NumPoses() << " points x "
            << e.monitoring.NumCycles() << " cycles):\n"
            << "  lambda (RMS over cycles < " << opt.threshold_mm << " mm): before " << Fmt("%.2f", Lambda(before, lo))
            << " %, after " << Fmt("%.2f", Lambda(after, lo)) << " %\n"
            << "  RMS residual: before " << Fmt("%.4f", std::sqrt(before.squaredNorm() / before.size()))
            << " mm, after " << Fmt("%.4f", std::sqrt(after.squaredNorm() / after.size())) << " mm\n"
            << "corrected joints for the taught monitoring poses at cycle " << e.monitoring.cycles[col].cycle << ": "
            << cs.BriefReport() << "\n";
  if (mon_sigma.size() > 0) {
    std::vector<double> v(mon_sigma.data(), mon_sigma.data() + mon_sigma.size());
    std::sort(v.begin(), v.end());
    std::cout << "predicted sigma of the compensated monitoring directions from the identification noise: median "
              << Fmt("%.4f", v[v.size() / 2]) << " mm, largest " << Fmt("%.4f", v.back()) << " mm\n";
  }
  if (cs.converged != cs.poses) {
    std::cerr << "ramtk: error: " << cs.message << "; nothing written\n";
    return kExitNoSolution;
  }
  // Every output is assembled first and written as one unit.
  std::vector<std::pair<std::string, std::string>> files;
  if (!opt.out_path.empty()) files.emplace_back(opt.out_path, csv);
  if (!opt.out_report.empty()) {
    CompensationReportInput in;
    in.monitoring_sigma_mm = mon_sigma;
    in.experiment = &ex;
    in.params = params;
    in.before = before, in.after = after, in.delta_x = x_mon;
    in.threshold_mm = opt.threshold_mm;
    in.cycle_column = col;
    for (int k = 0; k < e.monitoring.NumPoses(); ++k) {
      std::vector<double> q(6), t(6);
      for (int j = 0; j < 6; ++j) q[j] = RadToDeg(corrected[k][j]), t[j] = RadToDeg(e.monitoring.taught[k][j]);
      in.corrected_deg.push_back(q), in.taught_deg.push_back(t);
    }
    in.drift_model = &dm;
    in.identification_options = id;
    in.identification = is;
    report::HtmlReport page = CompensationReport(in);
    page.AddProvenance(provenance);
    files.emplace_back(opt.out_report, page.Page());
  }
  StampOutputs(&files, provenance);
  WriteFilesAtomically(files);
  for (const auto& f : files) std::cout << "wrote " << f.first << "\n";
  return kExitOk;
}

}  // namespace

void RegisterThermalCompensate(CLI::App* thermal, int* exit_code) {
  auto opt = std::make_shared<CompensateOptions>();
  CLI::App* sub = thermal->add_subcommand("compensate", "Corrected joints for the taught poses; monitoring residuals");
  AddInputs(sub, &opt->in, true);
  sub->add_option("--params", opt->in.params, "Parameters to identify")->required();
  sub->add_option("--poses", opt->in.poses, "Ball pose positions to use (default all)");
  sub->add_option("--pose-budget", opt->in.pose_budget, "Choose this many poses D-optimally");
  sub->add_option("--cycle", opt->cycle, "Cycle whose drift corrects the taught poses (default: last)");
  sub->add_option("--threshold-mm", opt->threshold_mm, "λ threshold (mm)");
  sub->add_option("--out", opt->out_path,
                  "Corrected joints CSV (deg) with each compensated point's covariance (base frame, mm^2)");
  sub->add_option("--report", opt->out_report,
                  "Write one self-contained HTML page: monitoring error per cycle, identified drift, corrected joints");
  AddGuardOptions(sub, &opt->in);
  sub->callback([opt, exit_code, sub]() { *exit_code = RunCompensate(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
