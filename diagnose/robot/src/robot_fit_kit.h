// Private to the robot diagnosis: what the causes' fits share (causes/*.cpp, robot_candidates.cpp):
// identifiability of added columns, drift columns, cross-validation of a design and the fitted
// values in report units.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "robot_causes.h"

namespace ramtk::diagnose::robot_detail {

// Pooled blocks of a design for the independence check: static and per-cycle columns side by side.
std::vector<Mat3X> PooledBlocks(const Design& d);
// Per row, the columns ∂/∂X of `params` (ParamVector indices).
std::vector<Mat3X> ParamBlocks(const std::vector<Row>& rows, const std::vector<int>& params);
// Parameters among `params` not aliased with the design's columns (nor with earlier ones).
std::vector<int> Identifiable(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params,
                              double rtol = 1e-5);
// Per-cycle parameters among `params` not aliased with the design's per-cycle columns. Static
// columns are left out of this check: a per-cycle copy of a static direction (d6 against the ball
// offset) still varies from cycle to cycle, which the shared static parameter cannot follow.
std::vector<int> IdentifiablePerCycle(const std::vector<Row>& rows, const Design& d, const std::vector<int>& params);

// Drift terms of the thermal candidates: per-cycle parameters (power −1) or static columns of a
// parameter times τ^power, in design order.
struct ThermalTerms {
  std::vector<std::pair<int, int>> cycle;   // (param, -1), per-cycle columns after the base's
  std::vector<std::pair<int, int>> smooth;  // (param, power), static columns after the base's
};
// Adds drift columns of `params`; returns the number of parameters added (0: all aliased).
int AddDrift(const Context& ctx, const std::vector<int>& params, bool per_cycle, Design* d, ThermalTerms* terms);

// Held-out score: n·ln(ss/n) + 2k.
double Score(double ss, int n, int k);
CandidateFit MakeFit(const std::string& effect, int k, const CvResult& cv);
// Static parameters of the design from column `first` on, with units, into the fit.
void ReportStatic(const Design& d, const CvResult& cv, int first, double sigma,
                  const std::vector<std::pair<std::string, double>>& key_and_factor, CandidateFit* f);
// Report key (name + suffix + unit) and factor to report units of a ParamVector index.
std::pair<std::string, double> ParamKey(int p, const std::string& suffix = "");
// The drift of each added parameter per cycle (file units: mm, µrad) and its range over the cycles.
void ReportDrift(const Context& ctx, const CvResult& cv, const ThermalTerms& terms, const std::vector<int>& params,
                 Evaluated* e);
Design WithParams(const Context& ctx, const Design& start, const std::vector<int>& params, bool per_cycle);
CvResult Cv(const Context& ctx, const Design& d);

// A candidate of static errors of the identifiable parameters among `pool` (report keys: name +
// `suffix` + unit); with rtol > 1e-5 the weakly observable ones are left out with a note.
void FitStaticParams(const Context& ctx, CauseOutput out, const std::string& effect, const std::vector<int>& pool,
                     const std::string& suffix, double rtol = 1e-5);
// A candidate made of extra constant-coefficient columns (the kept ones of `cols`).
void FitColumns(const Context& ctx, CauseOutput out, const std::string& effect, const std::vector<Mat3X>& cols,
                const std::vector<int>& keep, const std::vector<std::string>& col_names,
                const std::vector<std::pair<std::string, double>>& keys);

// Parameter pools of the model (structural zeros left out): joint zeros θ, every angle.
std::vector<int> ThetaParams(const kinematics::RobotModel& model);
std::vector<int> AngleParams(const kinematics::RobotModel& model);

}  // namespace ramtk::diagnose::robot_detail
