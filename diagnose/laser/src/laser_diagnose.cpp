// `ramtk diagnose` on laser data: which input it is, and reading it.
#include <algorithm>
#include <cctype>
#include <fstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/diagnose/laser/laser.h"

namespace ramtk::diagnose {
namespace {

bool IsCalibrationPoints(const std::string& path) {
  RequireRegularFile(path);  // a FIFO would block the probe below
  std::ifstream in(path);
  std::string header;
  while (std::getline(in, header) && (header.empty() || header[0] == '#')) {
  }
  std::transform(header.begin(), header.end(), header.begin(), [](unsigned char c) { return std::tolower(c); });
  return header.find("label") != std::string::npos;
}

}  // namespace

Diagnosis DiagnoseLaser(const DiagnoseOptions& options) {
  ThrowIfInvalid(options.Validate(), "DiagnoseOptions");
  if (IsCalibrationPoints(options.data))
    return DiagnoseSensorPoints(tcf::ReadSensorCalibrationPoints(options.data), options);
  if (options.with.empty())
    throw InputError({options.data, 0, "--with"}, "a laser log needs its programmed motion JSON (--with motion.json)");
  if (options.model.empty())
    throw InputError({options.data, 0, "--model"}, "a laser log needs the calibrated sensor frame JSON (--model)");
  const std::vector<tcf::BeamEvent> events = tcf::ReadDeviceLog(options.data);
  const tcf::ProgrammedMotion motion = tcf::ReadProgrammedMotion(options.with.front());
  const tcf::SensorFrame sensor = tcf::ReadSensorFrame(options.model);
  return DiagnoseLaserLog(events, motion, sensor, options);
}

}  // namespace ramtk::diagnose
