// Private to the fringe diagnosis: what the candidates of the fringe cause table
// (ramtk/diagnose/engine/fringe_causes.def) share, and their fit functions (causes/*.cpp). Every
// candidate is fitted on the training tiles and scored on the held-out tiles.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "fringe_internal.h"
#include "ramtk/diagnose/fringe/extra_cause.h"

namespace ramtk::diagnose::fringe {

constexpr double kPi = 3.14159265358979323846;

// Weight of residual sample k (σ̄/σ(I), 1 without a noise-level function).
inline double W(const FringeFit& fit, size_t k) { return fit.weight.empty() ? 1.0 : fit.weight[k]; }

// What every candidate's fit gets: the per-pixel fit, its pixels by tile and the tiles' folds.
struct CandidateContext {
  const FringeFit* fit = nullptr;
  std::vector<std::vector<int>> by_tile;  // pixel indices per tile
  std::vector<int> fold_of_tile;
  std::vector<long> count;                // finite residual samples per tile
  int folds = 5;
  double sigma = 1.0;                     // noise floor (for the parameter sigmas)
};

std::vector<std::vector<int>> PixelsByTile(const FringeFit& fit);

// Held-out and training RMS from per-fold choices: `ssr_for(fold, tile)` is the SSR of `tile` under
// the model fitted without `fold`.
void CrossValidate(const std::vector<int>& fold_of_tile, int folds, const std::vector<long>& count,
                   const std::function<double(int, int)>& ssr_for, CandidateFit* c);

// A linear extension: r ≈ M·c with M (frames × m) built per pixel.
using BasisFn = std::function<void(const FringeFit&, const PixelFit&, Eigen::Ref<Eigen::MatrixXd>)>;
// Fitted on ctx's tiles and folds, the parameter sigmas at ctx's noise floor.
CandidateFit FitLinear(const CandidateContext& ctx, const std::string& name, int m, const BasisFn& basis,
                       const std::function<std::string(int)>& key, const std::function<double(int, double)>& scale);

// prefix + two-digit i + suffix ("step_03_error_deg").
std::string Numbered(const std::string& prefix, int i, const std::string& suffix);

// A row the fringe model cannot fit (its effect leaves the ideal model exact, or another part of
// the diagnosis reports it); never called.
CandidateFit NotFitted(const CandidateContext& ctx);

// The sequence of a fitted set as registered causes see it (fringe_extra.cpp).
FringeSequenceView SequenceViewOf(const FringeFit& fit);
// Fits a registered cause (fringe_extra.cpp).
CandidateFit FitRegistered(const CandidateContext& ctx, const FringeLinearCause& cause);

// The fit of every table row, declared from the table.
#define RAMTK_FRINGE_CAUSE(name, fit, lo, hi, either_sign, visible, parameters, plausible, help) \
  CandidateFit fit(const CandidateContext& ctx);
#include "ramtk/diagnose/engine/fringe_causes.def"

}  // namespace ramtk::diagnose::fringe
