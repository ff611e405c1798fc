#pragma once
// Calibration of the cross-laser device's frame ("lasersensor") against the robot base, thesis
// §4.3.1, eqs. (4-15)..(4-27).
//
// The flange (or a calibration pin on it) is driven through each beam twice: horizontally (the
// blocked / clear flange positions k = 1, 2 give x and y of a point on the beam) and vertically
// (k = 3, 4 give its z), for two points per beam: A, B on the x beam, C, D on the y beam. The
// beam lines AB and CD generally do not intersect; the origin is the midpoint M of their common
// perpendicular PQ (eq. 4-22). X = AB/|AB| (4-23), Z = X × CD/|X × CD| (4-25), Y' = Z × X (4-26),
// base_from_lasersensor = [X Y' Z M] (4-27).
//
// Sign convention of β (thesis §4.3.2): β is the angle from the x beam (X_s) to the y beam (Y_s),
// positive counter-clockwise about Z_s. Because Z_s = X_s × Y_s / |…|, the y beam always lies at
// +β about Z_s with β = arccos(X_s · Y_s) in (0°, 180°): β > 90° means the beams open wider than
// a right angle. In the sensor frame the y beam's direction is (cos β, sin β, 0).

#include <array>
#include <limits>
#include <map>
#include <string>

#include "ramtk/core/rotation.h"

namespace ramtk::tcf {

struct SensorFrameOptions {
  // Beams whose directions are closer than this to parallel (deg) are rejected.
  double min_beam_angle_deg = 20.0;
  // Beams whose lines pass farther apart than this (mm) are rejected: they do not cross.
  double max_beam_gap_mm = 5.0;
  // Points of one beam closer than this (mm) are rejected: the beam direction is undefined.
  double min_point_separation_mm = 1.0;
  // Empty if valid, otherwise what is wrong.
  std::string Validate() const;
};

// The calibrated device frame and the beam geometry in it.
struct SensorFrame {
  static Vec3 Unset() { return Vec3::Constant(std::numeric_limits<double>::quiet_NaN()); }
  Isometry3 base_from_lasersensor = Isometry3::Identity();  // eq. (4-27)
  double beta_rad = 0.0;     // angle X_s -> Y_s about Z_s, in (0, pi); see the header comment
  double beam_gap_mm = 0.0;  // |PQ|, shortest distance between the beam lines
  double x_beam_z_mm = 0.0;  // z of the x beam line (through P) in the sensor frame
  double y_beam_z_mm = 0.0;  // z of the y beam line (through Q) in the sensor frame
  // Intermediate results (base frame, mm) for reporting: A, B, C, D (eq. 4-16), P, Q, M (4-22),
  // and the unit vectors n = X_s, m = Y_s (the y beam), o = Y'_s, p = Z_s. NaN when not
  // computed (a frame not calibrated from beam points, e.g. a simulator's); not written then.
  Vec3 a_in_base = Unset(), b_in_base = Unset(), c_in_base = Unset(), d_in_base = Unset(), p_in_base = Unset(),
       q_in_base = Unset(), m_in_base = Unset();
  Vec3 n = Unset(), m = Unset(), o = Unset(), p = Unset();

  // Direction of the y beam in the sensor frame: (cos β, sin β, 0).
  Vec3 YBeamDirection() const;
  std::string BriefReport() const;
};

// Points A, B, C, D from the 16 flange positions keyed "A1".."D4" (eq. 4-16): x, y from the mean
// of k = 1, 2 and z from the mean of k = 3, 4.
struct BeamPoints {
  Vec3 a, b, c, d;
};
BeamPoints BeamPointsFromFlangePositions(const std::map<std::string, Vec3>& flange_in_base,
                                         const std::string& source = "");

// The frame from four beam points (eqs. 4-17..4-27). InputError if the beams are parallel or do
// not come near each other (see options). `source` names the input in errors.
SensorFrame CalibrateSensorFrame(const BeamPoints& points, const SensorFrameOptions& options = {},
                                 const std::string& source = "");

// Reads the Table 5-3 CSV format `label,x,y,z` (labels A1..A4, B1..B4, C1..C4, D1..D4).
std::map<std::string, Vec3> ReadSensorCalibrationPoints(const std::string& path);

// Sensor frame JSON (written by `ramtk tcf calibrate-sensor`, read by `ramtk tcf solve`).
std::string SensorFrameToJson(const SensorFrame& frame);
SensorFrame SensorFrameFromJson(const std::string& text, const std::string& path);
SensorFrame ReadSensorFrame(const std::string& path);

}  // namespace ramtk::tcf
