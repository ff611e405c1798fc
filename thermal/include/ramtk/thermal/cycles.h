#pragma once
// Measurement cycles. A thermal experiment repeats the same set of robot poses once per cycle
// (thesis §5.1: 20 ball poses and 34 monitoring points per cycle, 90 cycles). The first, cold
// cycle is the reference: every later cycle is compared with it pose by pose (eq. 3-5), so all
// cycles must hold the same poses at the same joint angles.

#include <map>
#include <string>
#include <vector>

#include "ramtk/kinematics/measurements_io.h"

namespace ramtk::thermal {

using kinematics::JointVector;

struct CycleOptions {
  // The cold reference cycle (thesis P_scool, eq. 3-3).
  int reference_cycle = 0;
  // Joint angles of a pose may differ between cycles by at most this (deg) — the same taught
  // pose, read back by the controller.
  double joint_tolerance_deg = 0.01;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// One cycle: per pose (in CycleSeries::ids order) the joints and the measured position.
struct Cycle {
  int cycle = 0;
  double time_s = 0.0;                    // mean time of the cycle's rows
  std::vector<double> pose_time_s;        // per pose, the time of its row (s)
  std::vector<Vec3> position_mm;          // per pose
  std::vector<JointVector> q_controller;  // per pose, rad
  std::map<std::string, double> extra;    // mean of each extra column (e.g. temp_j2) over the rows
  // Per pose, the covariance of position_mm (mm²) from the cov_xx..cov_yz columns; empty when
  // the file has none.
  std::vector<Mat3> covariance_mm2;
};

struct CycleSeries {
  std::string path;                 // file it came from (for messages)
  std::vector<int> ids;             // pose / point ids, ascending (the reference cycle's set)
  std::vector<JointVector> taught;  // reference cycle's joints per id, rad
  std::vector<Cycle> cycles;        // ascending cycle number; cycles[0] is the reference
  std::vector<std::string> extra_columns;
  bool has_covariance = false;  // every cycle holds covariance_mm2 (the file had cov_xx..cov_yz)

  int NumPoses() const { return static_cast<int>(ids.size()); }
  int NumCycles() const { return static_cast<int>(cycles.size()); }
  // Position of cycle number `cycle` in `cycles`, or -1.
  int Find(int cycle) const;
  // Stacked Y (eq. 3-8) of every cycle against the reference: 3·poses × cycles, restricted to
  // the poses at positions `pose_subset` (all if empty).
  Eigen::MatrixXd DifferencesFromReference(const std::vector<int>& pose_subset = {}) const;
  // Covariance of each difference (cycle c, pose k: C_c,k + C_ref,k + 2·robot_noise_mm²·I),
  // indexed [cycle][pose] over every pose — what IdentificationOptions::difference_covariance_mm2
  // takes. robot_noise_mm is the robot's repeatability σ per axis, which moves the ball but is not
  // in the scan's covariance. Empty without covariances.
  std::vector<std::vector<Mat3>> DifferenceCovariances(double robot_noise_mm = 0.0) const;
};

// Groups rows by cycle and checks the contract above. Cycles before the reference are dropped.
// InputError (naming `path`, the line and the field) when the reference cycle is missing, a
// cycle lacks or repeats a pose, or a pose's joints differ from the reference's.
CycleSeries GroupCycles(const kinematics::RobotMeasurementSet& set, const std::string& path,
                        const CycleOptions& options = {});

}  // namespace ramtk::thermal
