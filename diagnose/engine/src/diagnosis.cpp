#include "ramtk/diagnose/engine/diagnosis.h"

#include <algorithm>

namespace ramtk::diagnose {

const char* DataKindName(DataKind kind) {
  switch (kind) {
    case DataKind::kFringe:
      return "fringe";
    case DataKind::kRobot:
      return "robot";
    case DataKind::kLaser:
      return "laser";
  }
  return "unknown";
}

double ExcessRemoved(double rms_before, double rms_after, double noise_floor_rms) {
  const double excess = rms_before * rms_before - noise_floor_rms * noise_floor_rms;
  if (excess <= 0.0) return 0.0;
  const double removed = (rms_before * rms_before - rms_after * rms_after) / excess;
  return std::clamp(removed, -1.0, 1.0);
}

}  // namespace ramtk::diagnose
