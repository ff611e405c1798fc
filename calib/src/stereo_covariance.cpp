#include "stereo_covariance.h"

#include <Eigen/Dense>
#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace ramtk::calib::internal {

bool StereoExtrinsicStd(const std::vector<std::vector<cv::Point3f>>& object,
                        const std::vector<std::vector<cv::Point2f>>& left,
                        const std::vector<std::vector<cv::Point2f>>& right, const cv::Matx33d& k1,
                        const std::vector<double>& d1, const cv::Matx33d& k2, const std::vector<double>& d2,
                        const cv::Matx33d& rotation, const cv::Vec3d& translation, bool fix_k3,
                        bool per_camera_variance, cv::Vec6d* std_rt, std::vector<double>* std_left,
                        std::vector<double>* std_right) {
  const int n_intr = fix_k3 ? 8 : 9;  // fx fy cx cy k1 k2 p1 p2 [k3]
  const int n_views = static_cast<int>(object.size());
  const int n_params = 2 * n_intr + 6 + 6 * n_views;
  const int rig = 2 * n_intr;  // column of rvec_rl
  int rows = 0;
  for (const auto& o : object) rows += 4 * static_cast<int>(o.size());
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(rows, n_params);
  double sum2 = 0.0, sum2_left = 0.0, sum2_right = 0.0;
  std::vector<char> right_row(rows, 0);  // 1 for the right camera's residual rows
  cv::Vec3d rv_rl;
  cv::Rodrigues(rotation, rv_rl);
  int row = 0;
  for (int v = 0; v < n_views; ++v) {
    const int m = static_cast<int>(object[v].size());
    cv::Vec3d rv, tv;
    cv::solvePnP(object[v], left[v], k1, d1, rv, tv, false, cv::SOLVEPNP_ITERATIVE);
    std::vector<cv::Point2f> pl, pr;
    cv::Mat jl, jr;
    cv::projectPoints(object[v], rv, tv, k1, d1, pl, jl);
    cv::Mat rv3, tv3, dr3dr1, dr3dt1, dr3dr2, dr3dt2, dt3dr1, dt3dt1, dt3dr2, dt3dt2;
    cv::composeRT(rv, tv, rv_rl, translation, rv3, tv3, dr3dr1, dr3dt1, dr3dr2, dr3dt2, dt3dr1, dt3dt1, dt3dr2, dt3dt2);
    cv::projectPoints(object[v], rv3, tv3, k2, d2, pr, jr);
    Eigen::MatrixXd el, er;
    cv::cv2eigen(jl, el);  // 2m × (3 rot, 3 trans, 2 f, 2 c, ndist)
    cv::cv2eigen(jr, er);
    Eigen::Matrix3d a, b, c, d, e, f, g, h;
    cv::cv2eigen(dr3dr1, a), cv::cv2eigen(dr3dt1, b), cv::cv2eigen(dr3dr2, c), cv::cv2eigen(dr3dt2, d);
    cv::cv2eigen(dt3dr1, e), cv::cv2eigen(dt3dt1, f), cv::cv2eigen(dt3dr2, g), cv::cv2eigen(dt3dt2, h);
    const int view_col = 2 * n_intr + 6 + 6 * v;
    // Left camera rows.
    j.block(row, 0, 2 * m, 4) = el.middleCols(6, 4);
    j.block(row, 4, 2 * m, n_intr - 4) = el.middleCols(10, n_intr - 4);
    j.block(row, view_col, 2 * m, 6) = el.leftCols(6);
    // Right camera rows, through the composition board → left → right.
    const Eigen::MatrixXd jr_r = er.leftCols(3), jr_t = er.middleCols(3, 3);
    j.block(row + 2 * m, n_intr, 2 * m, 4) = er.middleCols(6, 4);
    j.block(row + 2 * m, n_intr + 4, 2 * m, n_intr - 4) = er.middleCols(10, n_intr - 4);
    j.block(row + 2 * m, rig, 2 * m, 3) = jr_r * c + jr_t * g;
    j.block(row + 2 * m, rig + 3, 2 * m, 3) = jr_r * d + jr_t * h;
    j.block(row + 2 * m, view_col, 2 * m, 3) = jr_r * a + jr_t * e;
    j.block(row + 2 * m, view_col + 3, 2 * m, 3) = jr_r * b + jr_t * f;
    for (int k = 0; k < m; ++k) {
      sum2_left += std::pow(cv::norm(pl[k] - left[v][k]), 2);
      sum2_right += std::pow(cv::norm(pr[k] - right[v][k]), 2);
    }
    std::fill(right_row.begin() + row + 2 * m, right_row.begin() + row + 4 * m, 1);
    row += 4 * m;
  }
  const Eigen::MatrixXd normal = j.transpose() * j;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(normal);
  if (ldlt.info() != Eigen::Success || rows <= n_params) return false;
  sum2 = sum2_left + sum2_right;
  const Eigen::MatrixXd inverse = ldlt.solve(Eigen::MatrixXd::Identity(n_params, n_params));
  // The degrees of freedom shared between the cameras in proportion to their rows.
  const double dof_scale = static_cast<double>(rows) / (rows - n_params);
  double variance = sum2 / (rows - n_params);
  Eigen::MatrixXd cov = inverse;
  if (per_camera_variance) {
    const double var_left = sum2_left / (rows / 2) * dof_scale, var_right = sum2_right / (rows / 2) * dof_scale;
    Eigen::VectorXd weight(rows);
    for (int r = 0; r < rows; ++r) weight(r) = right_row[r] ? var_right : var_left;
    const Eigen::MatrixXd meat = j.transpose() * weight.asDiagonal() * j;
    cov = inverse * meat * inverse;
    variance = 1.0;
  }
  auto sd = [&](int col) { return std::sqrt(std::max(0.0, variance * cov(col, col))); };
  for (int k = 0; k < 6; ++k) (*std_rt)[k] = sd(rig + k);
  std_left->assign(9, 0.0);
  std_right->assign(9, 0.0);
  for (int k = 0; k < n_intr; ++k) {
    (*std_left)[k] = sd(k);
    (*std_right)[k] = sd(n_intr + k);
  }
  return true;
}

}  // namespace ramtk::calib::internal
