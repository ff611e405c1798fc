// Detail of the robot diagnosis (its sources and tests use it): the linearised measurement model and its block least squares.
//
// Every candidate is linear in its parameters around the current model: the residual of row i
// (3 coordinates, sensor frame) is r_i ≈ Js_i·s + Jc_i·p_cycle(i), with static parameters s (the
// set-up nuisance and constant effects) and per-cycle parameters p_c (thermal drift). The normal
// equations are solved by eliminating the per-cycle blocks (Schur complement), with pseudo-inverses
// so that aliased combinations (e.g. a constant drift against the static set-up) do not matter for
// the predictions.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "ramtk/kinematics/robot_model.h"

namespace ramtk::diagnose::robot_detail {

using Mat3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;

// One measured ball centre, linearised.
struct Row {
  int cycle = 0;                                                // cycle number of the file
  int cycle_pos = 0;                                            // 0-based position among the cycles present
  int pose = 0;                                                 // pose column
  double time_h = 0;                                            // hours since the first row
  kinematics::JointVector q = kinematics::JointVector::Zero();  // controller, rad
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();           // mm, sensor frame
  Eigen::Vector3d predicted = Eigen::Vector3d::Zero();          // current model without drift
  Eigen::Vector3d residual = Eigen::Vector3d::Zero();           // measured − predicted
  Eigen::Matrix<double, 3, kinematics::kNumParams> j_param;     // ∂/∂X (sensor frame)
  Eigen::Matrix<double, 3, 9> j_setup;                          // ∂/∂[φ sensor, t sensor, P_e]
  Eigen::Matrix3d ball_dir;                                     // ∂/∂P_e (sensor frame)
  std::map<std::string, double> extra;
};

// A design: column blocks per row.
struct Design {
  std::vector<Mat3X> stat;   // per row: 3 × ns
  std::vector<Mat3X> cycle;  // per row: 3 × np (may be 0 columns)
  int ns = 0, np = 0;
  std::vector<std::string> stat_names, cycle_names;
};

struct Fit {
  Eigen::VectorXd s;           // static parameters (design units)
  Eigen::MatrixXd p;           // np × cycles
  Eigen::MatrixXd s_cov_unit;  // ns × ns covariance for unit noise
  bool ok = false;
};

// Solves on the rows with train[i] true. `num_cycles` = 1 + the largest cycle_pos.
Fit SolveDesign(const std::vector<Row>& rows, const Design& d, const std::vector<char>& train, int num_cycles);
// Residual of row i after the fit.
Eigen::Vector3d FitResidual(const std::vector<Row>& rows, const Design& d, const Fit& f, int i);

// Cross-validation by pose folds: sum of squares and count of the held-out residual coordinates,
// and the full-data fit's in-sample sum of squares.
struct CvResult {
  double heldout_ss = 0, train_ss = 0;
  int heldout_n = 0, train_n = 0;
  Fit full;
  std::vector<Eigen::Vector3d> heldout_residual;  // per row (from its held-out fold)
  double HeldoutRms() const { return heldout_n ? std::sqrt(heldout_ss / heldout_n) : 0.0; }
  double TrainRms() const { return train_n ? std::sqrt(train_ss / train_n) : 0.0; }
};
CvResult CrossValidate(const std::vector<Row>& rows, const Design& d, const std::vector<int>& fold_of_row, int folds,
                       int num_cycles);

// Columns of `candidate` (pooled over all rows) that are not (nearly) in the span of `base` and
// of the candidate columns kept before them. Returns kept column indices of `candidate`.
std::vector<int> IndependentColumns(const std::vector<Mat3X>& base, const std::vector<Mat3X>& candidate,
                                    double rtol = 1e-5);

// Builders.
Design NuisanceDesign(const std::vector<Row>& rows);  // 9 set-up columns, no per-cycle
// Appends parameter columns (ParamVector indices) as static or per-cycle columns.
void AddParamColumns(const std::vector<Row>& rows, const std::vector<int>& params, bool per_cycle, Design* d);
// Appends arbitrary static columns (per row 3 × k), with names.
void AddStaticColumns(const std::vector<Mat3X>& cols, const std::vector<std::string>& names, Design* d);
// Selects columns of per-row blocks.
std::vector<Mat3X> SelectColumns(const std::vector<Mat3X>& blocks, const std::vector<int>& keep);

// Gravity torque (N·m) about each joint axis at controller joints q (base Z up): links as a
// uniform 0.1 kg/mm line between successive frame origins plus a 20 kg payload at the ball.
Eigen::Matrix<double, 6, 1> GravityTorques(const kinematics::RobotModel& model, const kinematics::JointVector& q,
                                           const Eigen::Vector3d& ball_in_flange);

}  // namespace ramtk::diagnose::robot_detail

// ---- building the rows and the noise floor (robot_rows.cpp) ----
#include "ramtk/diagnose/robot/robot.h"

namespace ramtk::diagnose::robot_detail {

struct RowSet {
  std::vector<Row> rows;
  thermal::ThermalSetup setup;  // the set-up the rows are linearised at
  std::string setup_note;       // "given" or how it was calibrated
  int num_cycles = 0;
  std::vector<int> cycle_numbers;  // file cycle number per cycle_pos
  std::vector<int> pose_ids;       // distinct pose ids, ascending
  std::vector<std::string> extra_columns;
};

// Linearises every ball row at the current model and set-up. InputError when there are too few.
RowSet BuildRows(const RobotDiagnoseInput& in);

// σ per coordinate from successive cycles of the same pose (same joints): robust, insensitive to
// slow drift. Returns 0 when fewer than 10 pairs exist; *pairs receives their number.
double EstimateNoiseFromCycles(const std::vector<Row>& rows, int* pairs);

}  // namespace ramtk::diagnose::robot_detail
