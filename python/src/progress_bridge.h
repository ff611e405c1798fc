#pragma once
// A Python callable as a ramtk::ProgressCallback. The library calls it without the GIL (from the
// thread running the work); the bridge takes the GIL only for the call, checks for Ctrl-C
// (PyErr_CheckSignals) there, and cancels the work when the callable returns False, raises, or a
// signal handler raised (KeyboardInterrupt). The pending Python error is re-raised by Rethrow()
// once the work returned and the GIL is held again.
#include <pybind11/pybind11.h>

#include <optional>

#include "ramtk/core/progress.h"

namespace ramtk::python {

namespace py = pybind11;

class ProgressBridge {
 public:
  // `callable`: None, or f(stage: str, done: int, total: int) -> bool | None.
  explicit ProgressBridge(py::object callable) : callable_(std::move(callable)) {}

  // The callback: captures only `this` (copies of it never touch Python reference counts).
  ProgressCallback Callback() {
    return [this](const Progress& p) { return Call(p); };
  }

  // With the GIL held: raises the Python error that cancelled the work, if any.
  void Rethrow() {
    if (error_) {
      py::error_already_set e = std::move(*error_);
      error_.reset();
      throw e;
    }
  }

 private:
  bool Call(const Progress& p) {
    py::gil_scoped_acquire gil;
    if (error_) return false;
    if (PyErr_CheckSignals() != 0) {
      error_.emplace();
      return false;
    }
    if (callable_.is_none()) return true;
    try {
      const py::object r = callable_(p.stage, p.done, p.total);
      return !(r.ptr() == Py_False);
    } catch (py::error_already_set& e) {
      error_.emplace(std::move(e));
      return false;
    }
  }

  py::object callable_;
  std::optional<py::error_already_set> error_;
};

}  // namespace ramtk::python
