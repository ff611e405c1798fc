// Tracker files (kinematics/tracker_io.h): the same bytes as a measurement file in several column
// layouts (plain, one target per row, 6-D poses with references and drift removal) and as a format
// YAML file.
#include "fuzz_common.h"
#include "ramtk/kinematics/tracker_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ramtk::kinematics;
  const std::string text = ramtk::fuzz::Text(data, size);
  static const std::vector<TrackerFormat> formats = [] {
    std::vector<TrackerFormat> f(4);
    f[1].target_column = "target";
    f[2].rotation = RotationForm::kQuaternion;
    f[2].reference_columns = {"r1", "r2", "r3", "r4", "r5", "r6", "r7", "r8", "r9"};
    f[2].time_form = "iso8601";
    f[3].rotation = RotationForm::kMatrix;
    f[3].separator = ';';
    f[3].decimal = ',';
    f[3].time_column = "t";
    f[3].time_form = "yyyymmddhhmmss";
    return f;
  }();
  for (const TrackerFormat& format : formats) {
    ramtk::fuzz::Quiet();
    try {
      TrackerMeasurements m = ParseTrackerMeasurements(text, "fuzz.csv", format);
      (void)RemoveTrackerDrift(&m);
    } catch (const ramtk::InputError&) {
    }
  }
  RAMTK_FUZZ_BODY((void)ParseTrackerFormat(text, "fuzz.yaml"));
}
