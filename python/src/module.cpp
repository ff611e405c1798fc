// `ramtk._core`: the compiled part of the Python package `ramtk` (docs/python.md); the package's
// Python files check the arguments and build the typed results. Errors in the input raise ramtk.InputError
// (a ValueError) whose message names the file, line and field, with the parts as attributes.
#include <pybind11/pybind11.h>

#include "ramtk/calib/sensor_robot.h"
#include "ramtk/core/error.h"
#include "ramtk/core/log.h"
#include "ramtk/diagnose/diagnose.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/vision/scan.h"

namespace py = pybind11;

namespace ramtk::python {
void BindKinematics(py::module_& m);
void BindVision(py::module_& m);
void BindThermal(py::module_& m);
void BindDiagnose(py::module_& m);
void BindCalib(py::module_& m);
void BindCampaign(py::module_& m);
}  // namespace ramtk::python

PYBIND11_MODULE(_core, m) {
  m.doc() =
      "ramtk: robot accuracy maintenance toolkit (fringe scans, sphere centres, robot calibration, thermal drift)";
  m.attr("__version__") = RAMTK_VERSION;
  // Library warnings go to Python's logging module ("ramtk" logger), not to stderr.
  ramtk::SetLogSink([](ramtk::LogLevel level, const std::string& message) {
    py::gil_scoped_acquire gil;
    py::object logger = py::module_::import("logging").attr("getLogger")("ramtk");
    const char* method = level == ramtk::LogLevel::kError     ? "error"
                         : level == ramtk::LogLevel::kWarning ? "warning"
                         : level == ramtk::LogLevel::kInfo    ? "info"
                                                              : "debug";
    logger.attr(method)(message);
  });
  static py::exception<ramtk::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ramtk::InputError& e) {
      py::object error = py::reinterpret_borrow<py::object>(input_error.ptr())(e.what());
      error.attr("file") = e.where().file;
      error.attr("line") = e.where().line;
      error.attr("field") = e.where().field;
      error.attr("message") = e.message();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
  // The defaults of the C++ Options structs, for the Python signatures.
  m.def("defaults", [] {
    py::dict d;
    d["min_modulation"] = ramtk::vision::DecodeOptions{}.min_modulation_fraction;
    d["roi_margin"] = ramtk::vision::ScanRoiOptions{}.margin_mm;
    d["lr_sigma_factor"] = ramtk::vision::StereoMatchOptions{}.lr_sigma_factor;
    d["use_covariance"] = ramtk::calib::SensorRobotOptions{}.use_covariance;
    d["robot_noise_mm"] = ramtk::calib::SensorRobotOptions{}.robot_noise_mm;
    d["screen_keep"] = ramtk::thermal::ScreeningOptions{}.keep;
    d["screen_heldout_z"] = ramtk::thermal::ScreeningOptions{}.heldout_z;
    d["diagnose_folds"] = ramtk::diagnose::DiagnoseOptions{}.folds;
    d["diagnose_noise"] = ramtk::diagnose::DiagnoseOptions{}.noise;
    d["diagnose_alpha"] = ramtk::diagnose::DiagnoseOptions{}.alpha;
    d["diagnose_seed"] = ramtk::diagnose::DiagnoseOptions{}.seed;
    return d;
  });
  ramtk::python::BindKinematics(m);
  ramtk::python::BindVision(m);
  ramtk::python::BindThermal(m);
  ramtk::python::BindDiagnose(m);
  ramtk::python::BindCalib(m);
  ramtk::python::BindCampaign(m);
}
