#pragma once
// The provenance of an output written from Python (docs/formats.md#provenance): the command is
// ["python", "ramtk.<function>"] and the options are the call's keyword options as JSON (values
// JSON cannot hold are recorded as their str()).
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

#include "ramtk/core/provenance.h"

namespace ramtk::python {

namespace py = pybind11;

inline Provenance PythonProvenance(const std::string& function, const py::dict& options) {
  const py::object dumps = py::module_::import("json").attr("dumps");
  const std::string text =
      dumps(options, py::arg("default") = py::module_::import("builtins").attr("str"), py::arg("sort_keys") = true)
          .cast<std::string>();
  return StartProvenance({"python", "ramtk." + function}, nlohmann::json::parse(text));
}

}  // namespace ramtk::python
