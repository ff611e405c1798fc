#pragma once
// OpenCV aruco objects for a BoardSpec (not installed).
#include <opencv2/aruco/charuco.hpp>

#include "ramtk/calib/board.h"

namespace ramtk::calib::internal {

cv::Ptr<cv::aruco::CharucoBoard> MakeCharucoBoard(const BoardSpec& board);

}  // namespace ramtk::calib::internal
