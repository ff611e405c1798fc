#pragma once
// Identification of the drift as a function of time, each measurement at its own instant.
//
// DriftModel::Solve holds one ΔX per cycle. The poses of a cycle are measured one after another,
// so while the structure warms each pose sees a different drift; one constant ΔX then takes up
// that motion through the poses' differing sensitivities, and its error exceeds the σ its noise
// predicts (most for parameters with a short time constant). Here the drift is a continuous
// function of time, interpolated between knots at each cycle's mean pose time T_c (cubic, the
// slope at a knot from its neighbours; extended past the first and the last knot along the nearest
// segment), and every centre is modelled at its own time t_c,k:
//
//   P_c,k = Q_k + M_k · D(t_c,k) + e_c,k,   D(t) = X(t) − X(T_0),
//
// with Q_k the pose's centre at T_0 (one unknown 3-vector per pose), M_k its sensitivity
// (DriftModel, sensor frame) and e_c,k the centre's noise (its covariance) plus the robot's
// repeatability (σ²·I). The unknowns D_c = D(T_c), c ≥ 1, are what DriftModel::Solve estimates
// per cycle, now referred to an explicit instant; they and Q are solved jointly over all cycles by
// generalised least squares. Eliminating Q is the difference against the reference cycle, with
// the reference's noise shared by every difference (which the per-cycle solve leaves out).
//
// The drift's motion inside a cycle comes from the neighbouring cycles' knots, so what remains
// unmodelled is its departure from the interpolant: small when the cycles are close against the
// drift's time constants; it is not in the returned covariance.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ramtk/thermal/cycles.h"
#include "ramtk/thermal/identify.h"

namespace ramtk::thermal {

enum class DriftTimeModel {
  kConstantPerCycle,  // D constant over each cycle's poses: one ΔX per cycle, as DriftModel::Solve
  kPiecewiseLinear,   // D linear between neighbouring knots
  // D cubic between neighbouring knots (Hermite), its slope at each knot that of the parabola
  // through the knot and its two neighbours (one-sided at the first and last knot): reproduces a
  // drift quadratic in time exactly; with two cycles it is the linear model.
  kCubicHermite,
};

struct DriftInTimeOptions {
  // Parameters identified (ParamVector indices); empty: every free parameter of the model.
  std::vector<int> params;
  // Robot repeatability σ per axis (mm), added as σ²·I to every centre's covariance (the scan's
  // covariance does not hold it).
  double robot_noise_mm = 0.0;
  // How D(t) moves between the knots.
  DriftTimeModel model = DriftTimeModel::kCubicHermite;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

struct DriftInTimeResult {
  std::vector<int> params;     // identified parameters, in the options' order (or the free ones)
  DriftTimeModel model = DriftTimeModel::kCubicHermite;  // the interpolation identified with
  std::vector<double> time_s;  // per cycle, its knot T_c: the mean time of its poses, s
  // 30 × cycles: D(T_c) = X(T_c) − X(T_0) (mm, rad), zero outside params; column 0 is zero.
  Eigen::MatrixXd delta_x;
  // Per cycle, params × params (mm, rad): the covariance of D(T_c), unscaled (Aᵀ W A)⁻¹ block when
  // weighted, s²·(AᵀA)⁻¹ when not; cycle 0's is zero.
  std::vector<Eigen::MatrixXd> covariance;
  // true: every centre weighted by the inverse of its covariance plus the repeatability; false:
  // no covariance was known (neither in the file nor as robot_noise_mm), unit weights.
  bool weighted = false;
  int residual_dof = 0;      // centre coordinates − unknowns (3·poses + params·(cycles − 1))
  double reduced_chi2 = 0.0; // weighted residual χ² / dof (unweighted: s², mm²); NaN if dof is 0
  // D(t) at any time by the same interpolation (30-vector, mm / rad); kConstantPerCycle: the
  // nearest knot's.
  kinematics::ParamVector At(double time_s) const;
  std::string BriefReport() const;
};

// InputError when the series has fewer than 2 cycles, lacks per-pose times, its cycles' mean times
// do not increase, or the centres cannot determine the unknowns (fewer coordinates than unknowns).
DriftInTimeResult IdentifyDriftInTime(const DriftModel& drift_model, const CycleSeries& series,
                                      const DriftInTimeOptions& options);

}  // namespace ramtk::thermal
