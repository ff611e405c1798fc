// The campaign layer: `measure`, batch scans with shards and `merge`, the campaign digital twin,
// robot calibration and hand-eye.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "numpy_convert.h"

namespace ramtk::python {

void BindCampaign(py::module_& m) { (void)m; }

}  // namespace ramtk::python
