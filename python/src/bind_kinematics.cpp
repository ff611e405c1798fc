// Robot models, forward kinematics, the 30-parameter Jacobian and inverse kinematics. Joint
// angles in degrees (controller values), lengths in millimetres, poses as 4×4 arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "numpy_convert.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"
#include "ramtk/kinematics/inverse.h"
#include "ramtk/kinematics/jacobian.h"
#include "ramtk/kinematics/robot_io.h"

namespace ramtk::python {
namespace {

using kinematics::JointVector;
using kinematics::RobotModel;

JointVector JointsFromDegrees(const std::vector<double>& q_deg) {
  if (q_deg.size() != static_cast<std::size_t>(kinematics::kNumJoints)) {
    throw InputError({"", 0, "q_deg"}, "expected " + std::to_string(kinematics::kNumJoints) + " joint angles, got " +
                                           std::to_string(q_deg.size()));
  }
  JointVector q;
  for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = DegToRad(q_deg[i]);
  return q;
}

Isometry3 PoseFromArray(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) throw InputError({"", 0, "pose"}, "expected a 4x4 array");
  auto r = a.unchecked<2>();
  Isometry3 t = Isometry3::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) t.matrix()(i, j) = r(i, j);
  return t;
}

}  // namespace

void BindKinematics(py::module_& m) {
  py::class_<RobotModel>(m, "RobotModel", "A DH / MDH(β) robot model (docs/formats.md, robot YAML)")
      .def_static("read", &kinematics::ReadRobotModel, py::arg("path"), "Reads a robot model YAML")
      .def_readonly("name", &RobotModel::name)
      .def_property_readonly("free_params",
                             [](const RobotModel& r) {
                               std::vector<std::string> names;
                               for (int p : r.FreeParams()) names.push_back(kinematics::ParamName(p));
                               return names;
                             },
                             "Names of the identifiable parameters (not structural zeros)")
      .def("to_yaml", &kinematics::RobotModelToYaml)
      .def("__repr__", [](const RobotModel& r) { return "<ramtk.RobotModel '" + r.name + "'>"; });

  m.attr("PARAM_NAMES") = [] {
    std::vector<std::string> names;
    for (int p = 0; p < kinematics::kNumParams; ++p) names.push_back(kinematics::ParamName(p));
    return names;
  }();

  m.def(
      "fk", [](const RobotModel& model, const std::vector<double>& q_deg) {
        return ToArray(kinematics::BaseFromFlange(model, JointsFromDegrees(q_deg)).matrix());
      },
      py::arg("model"), py::arg("q_deg"), "base_from_flange (4×4, mm) at controller joints q (degrees)");
  m.def(
      "point_jacobian",
      [](const RobotModel& model, const std::vector<double>& q_deg, const std::vector<double>& point_in_flange_mm) {
        if (point_in_flange_mm.size() != 3) throw InputError({"", 0, "point_in_flange_mm"}, "expected 3 values");
        const Vec3 p(point_in_flange_mm[0], point_in_flange_mm[1], point_in_flange_mm[2]);
        return ToArray(kinematics::ComputePointParamJacobian(model, JointsFromDegrees(q_deg), p));
      },
      py::arg("model"), py::arg("q_deg"), py::arg("point_in_flange_mm") = std::vector<double>{0, 0, 0},
      "3×30 derivative of the point in the base frame w.r.t. the parameters (PARAM_NAMES order; mm per mm, mm per "
      "rad) — thesis eq. 3-6");
  m.def(
      "ik",
      [](const RobotModel& model, const py::array_t<double, py::array::c_style | py::array::forcecast>& pose,
         const std::vector<double>& seed_deg) {
        const kinematics::InverseKinematicsSummary s =
            kinematics::SolveInverseKinematics(model, PoseFromArray(pose), JointsFromDegrees(seed_deg));
        std::vector<double> q(kinematics::kNumJoints);
        for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = RadToDeg(s.q_controller[i]);
        py::dict out;
        out["q_deg"] = q;
        out["converged"] = s.Converged();
        out["final_position_error_mm"] = s.final_position_error_mm;
        out["final_rotation_error_deg"] = RadToDeg(s.final_rotation_error_rad);
        out["report"] = s.BriefReport();
        return out;
      },
      py::arg("model"), py::arg("pose"), py::arg("seed_deg"),
      "Controller joints (degrees) reaching the 4×4 base_from_flange pose (mm), from a seed");
}

}  // namespace ramtk::python
