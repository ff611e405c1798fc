// Diagnosis of the cross-laser TCF device (`ramtk diagnose` on laser data). Two inputs:
//  * a device log (CSV time_s,beam,state) with its programmed motion (JSON, --with) and the
//    calibrated sensor frame (JSON, --model): the log is held against the event predicted by the
//    ideal device — perpendicular beams crossing at the frame origin, lines of zero width, no
//    trigger latency, the programmed speed — for the tool fitted to the log;
//  * sensor-frame calibration points (Table 5-3 CSV label,x,y,z): the 16 flange positions are held
//    against the ideal device (perpendicular intersecting beams) passed by a pin.
// Candidates are the laser effects of the catalogue, each fitted by least squares together with
// the nuisance parameters (tool or frame), cross-validated, and selected (model_selection.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ramtk/core/rotation.h"
#include "ramtk/diagnose/engine/diagnose.h"
#include "ramtk/diagnose/engine/diagnosis.h"
#include "ramtk/tcf/device_io.h"
#include "ramtk/tcf/sensor_frame.h"

namespace ramtk::diagnose {

// Dispatches on the file: a device log needs --with motion.json and --model sensor_frame.json;
// calibration points need neither. Pictures go to options.output_folder when it is set.
Diagnosis DiagnoseLaser(const DiagnoseOptions& options);

// Default expected noise of one residual (mm): the robot's repeatability for logs, the reading
// resolution and short-move repeatability for calibration points.
inline constexpr double kLaserLogNoiseMm = 0.03;
inline constexpr double kSensorPointNoiseMm = 0.01;

// The log analysis. Residual of an event: the clearance (mm) the ideal device predicts between
// the beam line and the tool at the logged instant (0 for a perfect model). Events outside the
// programmed segments (transfers) are not used.
Diagnosis DiagnoseLaserLog(const std::vector<tcf::BeamEvent>& events, const tcf::ProgrammedMotion& motion,
                           const tcf::SensorFrame& sensor, const DiagnoseOptions& options);

// The calibration-point analysis (residual: observed − predicted flange coordinate along the
// pass, mm; leave-one-out cross-validation). Beyond the named cause it tries each remaining
// effect on top of it and reports a second one when it passes the same selection rule.
Diagnosis DiagnoseSensorPoints(const std::map<std::string, Vec3>& flange_in_base, const DiagnoseOptions& options);

}  // namespace ramtk::diagnose
