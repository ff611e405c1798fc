#pragma once
// Scatter of repeated point measurements (thesis Table 5-6).

#include <vector>

#include "ramtk/core/rotation.h"

namespace ramtk::tcf {

struct PointScatter {
  Vec3 mean = Vec3::Zero();
  // sqrt(Σ|p_i − mean|² / (n − 1)): the sample standard deviation of the 3-D position; the thesis's
  // "RMS 0.48 mm" of Table 5-6 is this statistic.
  double sample_std_mm = 0.0;
  // sqrt(Σ|p_i − mean|² / n): the RMS distance from the mean (0.46 mm for Table 5-6).
  double rms_from_mean_mm = 0.0;
  double max_from_mean_mm = 0.0;
  int count = 0;
};

// Needs at least two points (else the sample std is 0).
PointScatter ComputePointScatter(const std::vector<Vec3>& points);

}  // namespace ramtk::tcf
