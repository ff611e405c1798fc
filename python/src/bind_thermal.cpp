// Thermal drift: the thesis simulator, identification of ΔX per cycle and parameter screening,
// from the files of docs/formats.md (ball / monitoring CSV, set-up JSON) or tables in memory.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "numpy_convert.h"
#include "ramtk/kinematics/robot_io.h"
#include "ramtk/thermal/identify.h"
#include "ramtk/thermal/monitoring.h"
#include "ramtk/thermal/screening.h"
#include "ramtk/thermal/simulator.h"

namespace ramtk::python {
namespace {

using namespace ramtk::thermal;

CycleSeries Series(const std::string& source, const std::string& text) {
  return GroupCycles(MeasurementsOf(source, text), source);
}

}  // namespace

void BindThermal(py::module_& m) {
  m.def("simulate_thermal",
        [](const kinematics::RobotModel& model, const std::string& out, std::uint64_t seed, int cycles, bool force) {
          ThermalSimOptions o = ThesisPreset(seed);
          if (cycles > 0) o.cycles = cycles;
          ThermalSimResult r;
          {
            py::gil_scoped_release release;
            r = SimulateThermal(model, o);
            WriteThermalSimulation(r, o, "thesis", out, force);
          }
          py::dict d;
          std::vector<std::string> drifting;
          for (int p : r.drifting_params) drifting.push_back(kinematics::ParamName(p));
          d["drifting_params"] = drifting;
          d["true_delta_x"] = ToArray(r.true_delta_x);  // 30 × cycles, mm / rad
          d["ball"] = out + "/ball.csv";
          d["monitoring"] = out + "/monitoring.csv";
          d["setup"] = out + "/setup.json";
          return d;
        });

  m.def("thermal_identify", [](const kinematics::RobotModel& model, const std::string& setup, const std::string& ball,
                               const std::string& ball_text, const std::vector<std::string>& params) {
    const ThermalSetup s = ReadThermalSetup(setup);
    const CycleSeries series = Series(ball, ball_text);
    std::string list;
    for (const std::string& p : params) list += (list.empty() ? "" : ",") + p;
    IdentificationOptions o;
    o.params = ParseParamList(list, model, "params");
    IdentificationSummary summary;
    Eigen::MatrixXd x;
    {
      py::gil_scoped_release release;
      x = IdentifyCycles(model, s, series, o, &summary);
    }
    Eigen::MatrixXd selected(static_cast<Eigen::Index>(o.params.size()), x.cols());
    for (std::size_t i = 0; i < o.params.size(); ++i) selected.row(i) = x.row(o.params[i]);
    py::dict d;
    d["delta_x"] = ToArray(selected);  // params × cycles, mm / rad
    std::vector<int> cycle_numbers;
    for (const Cycle& c : series.cycles) cycle_numbers.push_back(c.cycle);
    d["cycles"] = cycle_numbers;
    d["rank"] = summary.rank;
    d["condition_number"] = summary.condition_number;
    d["rms_residual_mm"] = summary.rms_residual_mm;
    d["report"] = summary.BriefReport();
    return d;
  });

  m.def("thermal_screen", [](const kinematics::RobotModel& model, const std::string& setup, const std::string& ball,
                             const std::string& ball_text, const std::string& monitoring,
                             const std::string& monitoring_text, int keep, double heldout_z) {
    const ThermalExperiment e =
        MakeExperiment(model, ReadThermalSetup(setup), Series(ball, ball_text), Series(monitoring, monitoring_text));
    ScreeningOptions o;
    o.keep = keep;
    o.heldout_z = heldout_z;
    ScreeningSummary s;
    {
      py::gil_scoped_release release;
      s = ScreenParameters(e, o);
    }
    std::vector<std::string> selected;
    for (int p : s.selected) selected.push_back(kinematics::ParamName(p));
    py::list steps;
    for (const ScreeningStep& st : s.steps) {
      py::dict row;
      row["card"] = st.card;
      row["removed"] = st.removed < 0 ? std::string("-") : kinematics::ParamName(st.removed);
      row["lambda_percent"] = st.lambda;
      row["heldout_rms_mm"] = st.heldout_rms_mm;
      steps.append(row);
    }
    py::dict d;
    d["selected"] = selected;
    d["final_lambda_percent"] = s.final_lambda;
    d["steps"] = steps;
    d["table"] = FormatEliminationTable(s);
    return d;
  });
}

}  // namespace ramtk::python
