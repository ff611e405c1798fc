#include "ramtk/calib/hand_eye.h"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "ramtk/core/ceres_solve.h"
#include "ramtk/core/error.h"
#include "ramtk/core/units.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::calib {
namespace {

cv::Mat ToCvR(const Mat3& r) {
  cv::Mat m;
  cv::eigen2cv(r, m);
  return m;
}
cv::Mat ToCvT(const Vec3& t) { return (cv::Mat_<double>(3, 1) << t.x(), t.y(), t.z()); }
Isometry3 FromCv(const cv::Mat& r, const cv::Mat& t) {
  Isometry3 out = Isometry3::Identity();
  Mat3 rr;
  cv::cv2eigen(r, rr);
  out.linear() = rr;
  out.translation() = Vec3(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  return out;
}

// measured − predicted camera-frame position of one board point:
// predicted = camera_from_base · base_from_flange · flange_from_board · point.
struct BoardPointResidual {
  Isometry3 base_from_flange;
  Vec3 measured;
  Vec3 point;
  template <typename T>
  bool operator()(const T* q_cb, const T* t_cb, const T* q_fb, const T* t_fb, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> r_cb(q_cb), r_fb(q_fb);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tc(t_cb), tf(t_fb);
    const Eigen::Matrix<T, 3, 1> in_flange = r_fb * point.cast<T>() + tf;
    const Eigen::Matrix<T, 3, 1> in_base =
        base_from_flange.linear().cast<T>() * in_flange + base_from_flange.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = measured.cast<T>() - (r_cb * in_base + tc);
    return true;
  }
};

}  // namespace

bool CameraFromBoard(const BoardDetection& detection, const cv::Matx33d& camera_matrix,
                     const std::vector<double>& distortion, Isometry3* camera_from_board) {
  if (!detection.found || detection.image_points.size() < 4) return false;
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(detection.object_points, detection.image_points, camera_matrix, distortion, rvec, tvec, false,
                    cv::SOLVEPNP_ITERATIVE)) {
    return false;
  }
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  *camera_from_board = FromCv(r, cv::Mat(tvec));
  return true;
}

std::string HandEyeOptions::Validate() const {
  if (min_poses < 3) return "min_poses must be at least 3";
  if (!(refine_length_mm > 0.0)) return "refine_length_mm must be positive";
  return "";
}

std::string HandEyeSummary::BriefReport() const {
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "hand-eye (%s%s): %d poses, RMS rotation %.4f deg, RMS translation %.4f mm, worst %.4f mm (index %d)",
                method.c_str(), refined ? " + Ceres" : "", num_poses, rms_rotation_deg, rms_translation_mm,
                worst_translation_mm, worst_pose);
  return buf;
}

HandEyeResult CalibrateCameraToRobot(const kinematics::RobotModel& model, const std::vector<BoardPoseObservation>& obs,
                                     const HandEyeOptions& options, HandEyeSummary* summary) {
  std::vector<StandCameraObservation> flange_obs;
  for (const BoardPoseObservation& o : obs) {
    if (!o.q_controller.allFinite()) throw InputError({"", 0, "poses"}, "non-finite joint angle");
    flange_obs.push_back({kinematics::BaseFromFlange(model, o.q_controller), o.camera_from_board});
  }
  return CalibrateStandCamera(flange_obs, options, summary);
}

void CheckRotationsExciteTwoAxes(const std::vector<Isometry3>& flange) {
  // The rotation part is observable only from rotations about at least two different axes; with
  // fewer, OpenCV's closed forms divide by zero (a "determinant is null" exception).
  {
    std::vector<Vec3> axes;
    double largest_deg = 0.0;
    for (std::size_t i = 1; i < flange.size(); ++i) {
      const Eigen::AngleAxisd rel(flange[0].linear().transpose() * flange[i].linear());
      largest_deg = std::max(largest_deg, RadToDeg(rel.angle()));
      if (RadToDeg(rel.angle()) > 1.0) axes.push_back(rel.axis());
    }
    bool two_axes = false;
    for (std::size_t i = 0; i < axes.size() && !two_axes; ++i)
      for (std::size_t j = i + 1; j < axes.size() && !two_axes; ++j)
        two_axes = std::abs(axes[i].dot(axes[j])) < std::cos(DegToRad(5.0));
    if (!two_axes) {
      throw InputError({"", 0, "poses"},
                       "the flange orientations do not vary enough (largest rotation from the first "
                       "pose " +
                           std::to_string(largest_deg) +
                           " deg): hand-eye needs rotations "
                           "of more than 1 deg about at least two axes 5 deg apart");
    }
  }
}

HandEyeResult CalibrateStandCamera(const std::vector<StandCameraObservation>& obs, const HandEyeOptions& options,
                                   HandEyeSummary* summary) {
  ThrowIfInvalid(options.Validate(), "HandEyeOptions");
  if (static_cast<int>(obs.size()) < options.min_poses) {
    throw InputError({"", 0, "poses"}, std::to_string(obs.size()) + " poses given; at least " +
                                           std::to_string(options.min_poses) + " are needed");
  }
  std::vector<cv::Mat> r_world2cam, t_world2cam, r_base2gripper, t_base2gripper;
  std::vector<Isometry3> flange;
  for (const StandCameraObservation& o : obs) {
    if (!o.base_from_flange.matrix().allFinite() || !o.camera_from_board.matrix().allFinite()) {
      throw InputError({"", 0, "poses"}, "non-finite flange or board pose");
    }
    flange.push_back(o.base_from_flange);
    r_world2cam.push_back(ToCvR(o.camera_from_board.linear()));
    t_world2cam.push_back(ToCvT(o.camera_from_board.translation()));
    r_base2gripper.push_back(ToCvR(flange.back().linear()));
    t_base2gripper.push_back(ToCvT(flange.back().translation()));
  }
  CheckRotationsExciteTwoAxes(flange);
  cv::Mat r_board_from_flange, t_board_from_flange, r_cam_from_base, t_cam_from_base;
  cv::calibrateRobotWorldHandEye(
      r_world2cam, t_world2cam, r_base2gripper, t_base2gripper, r_board_from_flange, t_board_from_flange,
      r_cam_from_base, t_cam_from_base,
      options.method == HandEyeMethod::kShah ? cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH : cv::CALIB_ROBOT_WORLD_HAND_EYE_LI);
  HandEyeResult r;
  r.camera_from_base = FromCv(r_cam_from_base, t_cam_from_base);
  r.flange_from_board = FromCv(r_board_from_flange, t_board_from_flange).inverse();
  HandEyeSummary s;
  s.method = options.method == HandEyeMethod::kShah ? "shah" : "li";
  if (options.refine) {
    Eigen::Quaterniond q_cb(r.camera_from_base.linear()), q_fb(r.flange_from_board.linear());
    q_cb.normalize();
    q_fb.normalize();
    Vec3 t_cb = r.camera_from_base.translation(), t_fb = r.flange_from_board.translation();
    const double l = options.refine_length_mm;
    const Vec3 points[5] = {Vec3::Zero(), Vec3(l, 0, 0), Vec3(-l, 0, 0), Vec3(0, l, 0), Vec3(0, -l, 0)};
    ceres::Problem problem;
    for (std::size_t i = 0; i < obs.size(); ++i) {
      for (const Vec3& p : points) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BoardPointResidual, 3, 4, 3, 4, 3>(
                                     new BoardPointResidual{flange[i], obs[i].camera_from_board * p, p}),
                                 nullptr, q_cb.coeffs().data(), t_cb.data(), q_fb.coeffs().data(), t_fb.data());
      }
    }
    problem.SetManifold(q_cb.coeffs().data(), new ceres::EigenQuaternionManifold);
    problem.SetManifold(q_fb.coeffs().data(), new ceres::EigenQuaternionManifold);
    ceres::Solver::Summary cs;
    ceres::Solve(DenseSolverOptions({100, 1e-14, 1e-14, 1e-10}), &problem, &cs);
    if (cs.IsSolutionUsable()) {
      r.camera_from_base.linear() = q_cb.normalized().toRotationMatrix();
      r.camera_from_base.translation() = t_cb;
      r.flange_from_board.linear() = q_fb.normalized().toRotationMatrix();
      r.flange_from_board.translation() = t_fb;
      s.refined = true;
      s.iterations = CeresIterations(cs);
      s.initial_cost = cs.initial_cost;
      s.final_cost = cs.final_cost;
    }
  }
  s.num_poses = static_cast<int>(obs.size());
  double sr = 0.0, st = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Isometry3 pred = r.camera_from_base * flange[i] * r.flange_from_board;
    const double dr = RotationAngleBetween(pred.linear(), obs[i].camera_from_board.linear());
    const double dt = (pred.translation() - obs[i].camera_from_board.translation()).norm();
    r.rotation_residual_rad.push_back(dr);
    r.translation_residual_mm.push_back(dt);
    sr += dr * dr;
    st += dt * dt;
    if (dt >= s.worst_translation_mm) s.worst_translation_mm = dt, s.worst_pose = static_cast<int>(i);
  }
  s.rms_rotation_deg = RadToDeg(std::sqrt(sr / obs.size()));
  s.rms_translation_mm = std::sqrt(st / obs.size());
  if (summary) *summary = s;
  return r;
}

}  // namespace ramtk::calib
