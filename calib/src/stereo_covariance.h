#pragma once
// Standard deviations of a stereo rig's R and T (not installed). OpenCV's stereoCalibrate gives
// none, so they are computed here from the joint Jacobian of every reprojection residual of both
// cameras with respect to both cameras' intrinsics (fx fy cx cy k1 k2 p1 p2 [k3]), R, T and the
// board poses, scaled by the residual variance — the same first-order model as OpenCV's
// stdDeviationsIntrinsics — so the intrinsics' uncertainty is carried into R and T.
#include <opencv2/core.hpp>
#include <vector>

namespace ramtk::calib::internal {

// Returns false if the normal matrix is singular. std_rt: rvec of R (rad), then T (mm);
// std_left/right: fx fy cx cy k1 k2 p1 p2 k3 (k3 = 0 when fixed). per_camera_variance: each
// camera's residuals have their own variance, the covariance is the unweighted fit's sandwich
// (JᵀJ)⁻¹ JᵀΣJ (JᵀJ)⁻¹; otherwise one pooled variance times (JᵀJ)⁻¹.
bool StereoExtrinsicStd(const std::vector<std::vector<cv::Point3f>>& object,
                        const std::vector<std::vector<cv::Point2f>>& left,
                        const std::vector<std::vector<cv::Point2f>>& right, const cv::Matx33d& k1,
                        const std::vector<double>& d1, const cv::Matx33d& k2, const std::vector<double>& d2,
                        const cv::Matx33d& rotation, const cv::Vec3d& translation, bool fix_k3, bool per_camera_variance, cv::Vec6d* std_rt,
                        std::vector<double>* std_left, std::vector<double>* std_right);

}  // namespace ramtk::calib::internal
