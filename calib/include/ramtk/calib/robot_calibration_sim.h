#pragma once
// Simulator of a robot calibration session: a tracker measures targets on the tool (or the tool's
// 6-D pose) of a robot whose links differ from the nominal file by known errors, at random joint
// configurations. The truth it returns is what `CalibrateRobot` should recover.

#include <cstdint>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/kinematics/chain.h"
#include "ramtk/kinematics/tracker_io.h"

namespace ramtk::calib {

struct RobotCalibrationSimOptions {
  int num_poses = 200;
  // Joint values drawn uniformly within ±this (deg) of zero, every joint.
  double joint_range_deg = 150.0;
  // Link errors: each perturbed length gets N(0, length_error_mm), each angle N(0, angle_error_deg).
  double length_error_mm = 1.0;
  double angle_error_deg = 0.1;
  // Which link unknowns (chain order, 5N) to perturb; empty: every one that is not a structural
  // zero of the file.
  std::vector<bool> perturb;
  // Targets on the tool (mm, flange frame); the first is the tool origin for 6-D data.
  std::vector<Vec3> targets_in_flange = {Vec3(20.0, -10.0, 120.0)};
  bool six_d = false;             // measure the tool's rotation too
  Mat3 flange_from_tool_rotation = RotX(0.3) * RotZ(-0.2);
  Isometry3 tracker_from_base = DefaultTrackerFromBase();
  // Measurement noise per coordinate (mm) and per rotation component (deg), 1σ.
  double position_noise_mm = 0.01;
  double rotation_noise_deg = 0.001;
  std::uint64_t seed = 1;        // errors and poses
  std::uint64_t noise_seed = 1;  // noise alone (Monte Carlo over one pose set)

  std::string Validate() const;
  // A tracker 2.6 m from the base, turned 137.5° about the vertical and tilted 2.9°.
  static Isometry3 DefaultTrackerFromBase();
};

struct RobotCalibrationSimulation {
  kinematics::RobotChain truth;
  kinematics::TrackerMeasurements data;
};

RobotCalibrationSimulation SimulateRobotCalibration(const kinematics::RobotChain& nominal,
                                                    const RobotCalibrationSimOptions& options);

}  // namespace ramtk::calib
