#pragma once
// Conversions between ramtk's C++ types and numpy arrays for the Python module.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>

#include "ramtk/kinematics/measurements_io.h"

namespace ramtk::python {

namespace py = pybind11;

// A single-channel cv::Mat as a 2-D numpy array without copying: the array keeps a reference to
// the matrix's buffer (cv::Mat is reference counted), so it stays valid after the C++ result is
// gone. Continuous matrices only (every matrix ramtk returns is).
inline py::array MatToArray(const cv::Mat& mat) {
  if (mat.empty()) return py::array_t<float>(std::vector<py::ssize_t>{0, 0});
  if (mat.channels() != 1) throw std::invalid_argument("MatToArray: single-channel matrices only");
  py::dtype dtype;
  switch (mat.depth()) {
    case CV_8U:
      dtype = py::dtype::of<std::uint8_t>();
      break;
    case CV_16U:
      dtype = py::dtype::of<std::uint16_t>();
      break;
    case CV_32F:
      dtype = py::dtype::of<float>();
      break;
    case CV_64F:
      dtype = py::dtype::of<double>();
      break;
    default:
      throw std::invalid_argument("MatToArray: unsupported depth");
  }
  auto* owner = new cv::Mat(mat);  // shares the buffer
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<cv::Mat*>(p); });
  return py::array(dtype, {mat.rows, mat.cols},
                   {static_cast<py::ssize_t>(mat.step[0]), static_cast<py::ssize_t>(mat.elemSize())}, owner->data,
                   free_when_done);
}

// Parses JSON text into Python objects (dict, list, float, ...).
inline py::object JsonToPython(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// Eigen matrix -> a numpy array that owns a copy (small matrices: poses, covariances).
template <typename Derived>
py::array_t<double> ToArray(const Eigen::MatrixBase<Derived>& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto r = out.template mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r(i, j) = m(i, j);
  return out;
}

// A robot measurement table: the file `source`, or (text not empty) the CSV text the Python layer
// made from arrays or columns, parsed with the file reader's checks; errors name `source`.
inline kinematics::RobotMeasurementSet MeasurementsOf(const std::string& source, const std::string& text) {
  return text.empty() ? kinematics::ReadRobotMeasurements(source) : kinematics::ParseRobotMeasurements(text, source);
}

}  // namespace ramtk::python
