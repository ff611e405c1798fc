// Sensor-to-robot calibration (sensor_from_base, ball_in_flange) from a ball measurement table,
// with the centres' covariance weighting when the table carries cov_xx..cov_yz.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "numpy_convert.h"
#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/error.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::python {

void BindCalib(py::module_& m) {
  m.def("calibrate_sensor_robot", [](const kinematics::RobotModel& model, const std::string& source,
                                     const std::string& text, bool use_covariance, double robot_noise_mm) {
    const kinematics::RobotMeasurementSet set = MeasurementsOf(source, text);
    const std::vector<calib::BallObservation> obs = calib::BallObservationsFromMeasurements(set, source);
    calib::SensorRobotOptions o;
    o.use_covariance = use_covariance;
    o.robot_noise_mm = robot_noise_mm;
    ThrowIfInvalid(o.Validate(), "SensorRobotOptions");
    calib::SensorRobotSummary summary;
    calib::SensorRobotCalibration r;
    {
      py::gil_scoped_release release;
      r = calib::CalibrateSensorRobot(model, obs, o, &summary);
    }
    py::dict d;
    d["sensor_from_base"] = ToArray(r.sensor_from_base.matrix());
    d["ball_in_flange_mm"] = ToArray(r.ball_in_flange).attr("ravel")();
    d["covariance"] = ToArray(r.covariance);  // [φ rad, t mm, P_e mm]
    d["has_covariance"] = r.has_covariance;
    d["rms_mm"] = r.rms_mm;
    d["rotation_std_arcsec"] = ToArray(r.RotationStdArcsec()).attr("ravel")();
    d["translation_std_mm"] = ToArray(r.TranslationStdMm()).attr("ravel")();
    d["ball_std_mm"] = ToArray(r.BallStdMm()).attr("ravel")();
    d["converged"] = summary.termination != Termination::kFailure;
    d["report"] = summary.BriefReport();
    return d;
  });
}

}  // namespace ramtk::python
