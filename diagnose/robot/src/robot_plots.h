// Private to the robot diagnosis: the residual pictures (robot_plots.cpp).
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"
#include "ramtk/diagnose/robot/detail/robot_linear.h"

namespace ramtk::diagnose::robot_detail {

// Residuals of the current model against time, pose, each joint and each extra column; held-out
// residual before/after against time; the per-cycle estimates of the added drift parameters
// (rows of `added_series`, µrad for angles, mm for lengths) against time.
void WriteRobotPictures(const RowSet& rs, const std::vector<Eigen::Vector3d>& before,
                        const std::vector<Eigen::Vector3d>& after, const std::vector<Eigen::Vector3d>& heldout_before,
                        const std::vector<Eigen::Vector3d>& heldout_after, double sigma,
                        const std::vector<std::string>& added, const Eigen::MatrixXd& added_series,
                        const std::string& cause, const std::string& folder, std::vector<Picture>* pictures);

}  // namespace ramtk::diagnose::robot_detail
