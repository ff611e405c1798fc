// `ramtk diagnose` from Python: the diagnosis as a dict (diagnosis.json) plus the report paths.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "numpy_convert.h"
#include "ramtk/core/error.h"
#include "ramtk/diagnose/engine/diagnose.h"
#include "ramtk/diagnose/fringe/fringe.h"
#include "ramtk/diagnose/laser/laser.h"
#include "ramtk/diagnose/engine/report.h"
#include "ramtk/diagnose/robot/robot.h"

namespace ramtk::python {

void BindDiagnose(py::module_& m) {
  m.def(
      "diagnose",
      [](const std::string& data, const std::string& model, const std::vector<std::string>& with,
         const std::string& out, int folds, double noise, double alpha, std::uint64_t seed) {
        diagnose::DiagnoseOptions o;
        o.data = data;
        o.model = model;
        o.with = with;
        o.output_folder = out;
        o.folds = folds;
        o.noise = noise;
        o.alpha = alpha;
        o.seed = seed;
        ThrowIfInvalid(o.Validate(), "DiagnoseOptions");
        diagnose::Diagnosis result;
        {
          py::gil_scoped_release release;
          switch (diagnose::DetectKind(data)) {
            case diagnose::DataKind::kRobot:
              result = diagnose::DiagnoseRobot(o);
              break;
            case diagnose::DataKind::kFringe:
              result = diagnose::DiagnoseFringe(o);
              break;
            case diagnose::DataKind::kLaser:
              result = diagnose::DiagnoseLaser(o);
              break;
          }
          if (!out.empty()) diagnose::WriteDiagnosis(result, out);
        }
        py::dict d = JsonToPython(diagnose::DiagnosisJson(result));
        if (!out.empty()) {
          d["report_md"] = out + "/report.md";
          d["diagnosis_json"] = out + "/diagnosis.json";
        }
        d["one_line"] = diagnose::OneLine(result);
        return d;
      },
      py::arg("data"), py::arg("model") = "", py::arg("with_") = std::vector<std::string>{}, py::arg("out") = "",
      py::arg("folds") = diagnose::DiagnoseOptions{}.folds, py::arg("noise") = diagnose::DiagnoseOptions{}.noise,
      py::arg("alpha") = diagnose::DiagnoseOptions{}.alpha, py::arg("seed") = diagnose::DiagnoseOptions{}.seed,
      "What the simulation gets wrong on measured data (fringe manifest, robot CSV, laser log): the diagnosis dict");
}

}  // namespace ramtk::python
