// Robot models, forward kinematics, the 30-parameter Jacobian and inverse kinematics for the
// Python package (python/ramtk/_robot.py checks the arguments first). Joint angles in degrees
// (controller values), lengths in millimetres, poses as 4×4 arrays. fk and point_jacobian take a
// batch of joint sets (N×6) and loop in C++ without the GIL.
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
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Rows of an N×6 array of joint angles (degrees).
const double* JointRows(const DoubleArray& q, const char* field, py::ssize_t* rows) {
  if (q.ndim() != 2 || q.shape(1) != kinematics::kNumJoints)
    throw InputError({"", 0, field}, "expected an N×" + std::to_string(kinematics::kNumJoints) + " array");
  *rows = q.shape(0);
  return q.data();
}

JointVector JointsAt(const double* row) {
  JointVector q;
  for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = DegToRad(row[i]);
  return q;
}

Isometry3 PoseFromArray(const DoubleArray& a) {
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
                             })
      .def("to_yaml", &kinematics::RobotModelToYaml)
      .def("__repr__", [](const RobotModel& r) { return "<ramtk.RobotModel '" + r.name + "'>"; });

  m.attr("PARAM_NAMES") = [] {
    std::vector<std::string> names;
    for (int p = 0; p < kinematics::kNumParams; ++p) names.push_back(kinematics::ParamName(p));
    return names;
  }();

  m.def("fk_batch", [](const RobotModel& model, const DoubleArray& q_deg) {
    py::ssize_t n = 0;
    const double* q = JointRows(q_deg, "q_deg", &n);
    py::array_t<double> out({n, py::ssize_t{4}, py::ssize_t{4}});
    double* o = out.mutable_data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t i = 0; i < n; ++i) {
        const Eigen::Matrix4d t = kinematics::BaseFromFlange(model, JointsAt(q + 6 * i)).matrix();
        Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(o + 16 * i) = t;
      }
    }
    return out;
  });
  m.def("point_jacobian_batch", [](const RobotModel& model, const DoubleArray& q_deg, const DoubleArray& point) {
    py::ssize_t n = 0;
    const double* q = JointRows(q_deg, "q_deg", &n);
    if (point.ndim() != 1 || point.shape(0) != 3) throw InputError({"", 0, "point_in_flange_mm"}, "expected 3 values");
    const Vec3 p(point.at(0), point.at(1), point.at(2));
    py::array_t<double> out({n, py::ssize_t{3}, py::ssize_t{kinematics::kNumParams}});
    double* o = out.mutable_data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t i = 0; i < n; ++i) {
        const kinematics::PointParamJacobian j = kinematics::ComputePointParamJacobian(model, JointsAt(q + 6 * i), p);
        Eigen::Map<Eigen::Matrix<double, 3, kinematics::kNumParams, Eigen::RowMajor>>(o + 3 * kinematics::kNumParams *
                                                                                              i) = j;
      }
    }
    return out;
  });
  m.def("ik", [](const RobotModel& model, const DoubleArray& pose, const DoubleArray& seed_deg) {
    py::ssize_t n = 0;
    const double* seed = JointRows(seed_deg, "seed_deg", &n);
    if (n != 1) throw InputError({"", 0, "seed_deg"}, "expected one joint set");
    kinematics::InverseKinematicsSummary s;
    const Isometry3 target = PoseFromArray(pose);
    {
      py::gil_scoped_release release;
      s = kinematics::SolveInverseKinematics(model, target, JointsAt(seed));
    }
    std::vector<double> q(kinematics::kNumJoints);
    for (int i = 0; i < kinematics::kNumJoints; ++i) q[i] = RadToDeg(s.q_controller[i]);
    py::dict out;
    out["q_deg"] = q;
    out["converged"] = s.Converged();
    out["iterations"] = s.iterations;
    out["final_position_error_mm"] = s.final_position_error_mm;
    out["final_rotation_error_deg"] = RadToDeg(s.final_rotation_error_rad);
    out["report"] = s.BriefReport();
    return out;
  });
}

}  // namespace ramtk::python
