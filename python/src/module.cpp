// `import ramtk`: the Python module (docs/python.md). Errors in the input raise ramtk.InputError
// (a ValueError) whose message names the file, line and field, with the parts as attributes.
#include <pybind11/pybind11.h>

#include "ramtk/core/error.h"
#include "ramtk/core/log.h"

namespace py = pybind11;

namespace ramtk::python {
void BindKinematics(py::module_& m);
void BindVision(py::module_& m);
void BindThermal(py::module_& m);
void BindDiagnose(py::module_& m);
void BindCalib(py::module_& m);
}  // namespace ramtk::python

PYBIND11_MODULE(ramtk, m) {
  m.doc() = "ramtk: robot accuracy maintenance toolkit (fringe scans, sphere centres, robot calibration, thermal drift)";
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
  ramtk::python::BindKinematics(m);
  ramtk::python::BindVision(m);
  ramtk::python::BindThermal(m);
  ramtk::python::BindDiagnose(m);
  ramtk::python::BindCalib(m);
}
