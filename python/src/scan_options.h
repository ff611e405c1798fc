#pragma once
// ScanOptions from the Python layer's option dict (keys = `ramtk scan`'s option names), shared by
// scan, scan_frames and scan_batch.
#include <pybind11/pybind11.h>

#include "ramtk/vision/scan.h"

namespace ramtk::python {

vision::ScanOptions ScanOptionsOf(const pybind11::dict& options);

}  // namespace ramtk::python
