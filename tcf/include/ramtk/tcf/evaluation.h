#pragma once
// Accuracy of the TCF methods against the simulator's truth over many seeds: the cross-laser
// solver (with and without self-calibration), the thesis's variants and the §4.1 baselines on the
// same simulated tool with the same robot repeatability. Used by `ramtk tcf compare` and tests.

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/tcf/baselines.h"
#include "ramtk/tcf/simulator.h"
#include "ramtk/tcf/tcf_solver.h"

namespace ramtk::tcf {

enum class TcfMethod {
  kCrossLaser,                   // ramtk: edges, β correction, ball-nose tip, self-calibration on
  kCrossLaserNoSelfCalibration,  // the same without latency / beam-offset self-calibration
  kThesisCorrected,              // thesis: crossing midpoints (4-9), β correction (4-29), apex on the beam (4-14)
  kThesisUncorrected,            // thesis without the β correction (β taken as 90°)
  kFourPoint,                    // §4.1.1, position only
  kSevenPoint,                   // §4.1.1
  kParallelLaser,                // §4.1.2
};
const char* TcfMethodName(TcfMethod method);
// Solver options of the cross-laser variants.
TcfSolverOptions SolverOptionsFor(TcfMethod method);

struct MethodAccuracy {
  TcfMethod method = TcfMethod::kCrossLaser;
  int runs = 0;
  int failures = 0;         // runs that threw InputError
  double tcp_rms_mm = 0.0;  // RMS over runs of |TCP − truth|
  double tcp_max_mm = 0.0;
  double axis_rms_deg = 0.0;            // RMS over runs of the tool-axis angle error (NaN if no axis)
  double predicted_tcp_sigma_mm = 0.0;  // cross-laser: RMS of the solver's own 1-sigma (0 otherwise)
};

struct EvaluationOptions {
  TcfSimulationOptions simulation;  // seed is replaced per run
  int runs = 20;
  std::uint64_t first_seed = 1;
  std::vector<TcfMethod> methods = {TcfMethod::kCrossLaser,      TcfMethod::kCrossLaserNoSelfCalibration,
                                    TcfMethod::kThesisCorrected, TcfMethod::kThesisUncorrected,
                                    TcfMethod::kFourPoint,       TcfMethod::kSevenPoint,
                                    TcfMethod::kParallelLaser};
  // Operator noise of the touch-up baselines (see TouchUpSimulationOptions).
  double touch_sigma_mm = 0.1;
  double align_sigma_deg = 0.5;
  std::string Validate() const;
};

std::vector<MethodAccuracy> EvaluateMethods(const EvaluationOptions& options);
// Markdown table of the rows.
std::string FormatAccuracyTable(const std::vector<MethodAccuracy>& rows);

}  // namespace ramtk::tcf
